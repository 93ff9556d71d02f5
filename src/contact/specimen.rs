//! Shot-specimen contact: the flat specimen is the plane `z = 0` with normal `+z`
//! (the specimen frame is the world frame).

use super::HertzLaw;
use crate::Vec3;

/// Shot against the specimen plane `z = 0` (specimen frame = world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpecimenContact {
    /// Normal law of the shot-specimen material pair.
    pub law: HertzLaw,
}

impl SpecimenContact {
    /// Gap (m) between a shot of `radius` at `pos` and the plane; negative when overlapping.
    #[inline]
    pub fn gap(&self, pos: &Vec3, radius: f64) -> f64 {
        pos.z - radius
    }

    /// Hertz effective radius: the shot's radius (a flat specimen).
    #[inline]
    pub fn effective_radius(&self, radius: f64) -> f64 {
        radius
    }
}
