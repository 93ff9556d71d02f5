//! Aerodynamic drag on a shot (paper Eq 1 in vector form, model-notes defect 5).
//!
//! `F = 1/2 rho C_D (pi D^2/4) |u - v| (u - v)`, with `C_D = 0.47` (sphere in turbulent
//! flow, constant as in the paper). Reads one flow sample per shot; writes a force.

use crate::Vec3;

/// Quadratic drag with a constant coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragModel {
    /// Drag coefficient `C_D` (default: `0.47`).
    pub coefficient: f64,
}

impl DragModel {
    /// Drag force (N) on a sphere of frontal area `area` (m^2) moving at `velocity` (m/s)
    /// through air of density `density` (kg/m^3) moving at `air_velocity` (m/s).
    #[inline]
    pub fn force(&self, area: f64, density: f64, air_velocity: &Vec3, velocity: &Vec3) -> Vec3 {
        let rel = air_velocity - velocity;
        rel * (0.5 * density * self.coefficient * area * rel.norm())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drag_matches_hand_value_and_opposes_relative_motion() {
        let m = DragModel { coefficient: 0.47 };
        let area = std::f64::consts::PI * 0.4e-3 * 0.4e-3;
        let f = m.force(
            area,
            5.0,
            &Vec3::new(0.0, 0.0, -300.0),
            &Vec3::new(0.0, 0.0, -100.0),
        );
        let expected = 0.5 * 5.0 * 0.47 * area * 200.0 * 200.0;
        assert!((f.z + expected).abs() < 1e-15 && f.x == 0.0 && f.y == 0.0);
        let back = m.force(area, 5.0, &Vec3::zeros(), &Vec3::new(3.0, 0.0, 0.0));
        assert!(back.x < 0.0);
    }
}
