//! Shot-specimen contact: the flat specimen is the plane `z = 0` with normal `+z`
//! (the specimen frame is the world frame).

use std::sync::Arc;

use super::HertzLaw;
use super::restitution::SpeedLaw;
use crate::Vec3;
use crate::state::ShotState;

/// Shot against the specimen plane `z = 0` (specimen frame = world frame).
#[derive(Debug, Clone, PartialEq)]
pub struct SpecimenContact {
    /// Normal law of the shot-specimen material pair (with a restitution curve: its
    /// stiffness; each contact takes its own damping).
    pub law: HertzLaw,
    /// Restitution against the normal impact speed (`[restitution]
    /// shot_specimen_curve`), if given: each contact then takes the damping of its
    /// speed at the touch ([`crate::contact::restitution`]).
    pub by_speed: Option<Arc<SpeedLaw>>,
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

    /// The law of a contact that starts at normal speed `speed` (m/s, towards the plane).
    #[inline]
    pub fn law_at(&self, speed: f64) -> HertzLaw {
        match &self.by_speed {
            None => self.law,
            Some(s) => self.law.with_damping(s.damping(speed)),
        }
    }

    /// The law of shot `m`'s specimen contact: the one that started at its touch
    /// (`ShotState::specimen_damping`); for a contact not yet registered (the fixed-step
    /// methods see the overlap before they record the touch), that of the normal velocity
    /// `vz` now.
    #[inline]
    pub fn law_of(&self, m: &ShotState, vz: f64) -> HertzLaw {
        match &self.by_speed {
            None => self.law,
            Some(_) if m.on_specimen => self.law.with_damping(m.specimen_damping),
            Some(_) => self.law_at(-vz),
        }
    }
}
