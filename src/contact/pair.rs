//! Shot-shot contact: Hertz between two spheres; candidates come from the broad phase.

use super::HertzLaw;

/// Shot against shot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContact {
    /// Normal law of the shot-shot material pair.
    pub law: HertzLaw,
}

impl PairContact {
    /// Hertz effective radius `R_1 R_2 / (R_1 + R_2)`.
    #[inline]
    pub fn effective_radius(r1: f64, r2: f64) -> f64 {
        r1 * r2 / (r1 + r2)
    }
}
