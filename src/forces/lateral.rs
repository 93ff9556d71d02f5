//! Lateral (lift) jet force (paper Eqs 15-18, as read in model-notes).
//!
//! Magnitude `m (C_L/C_D) |a_axial| f tan^2(alpha)`, pointing radially away from the jet
//! axis, where `a_axial` is the axial drag acceleration at the shot, `f = 10 r/(s + 5d)`
//! in the potential core and mixing layer (Eq 15) and `f = 5 r/s` in the developed region
//! (Eq 16); zero in the bore and in still air. With the paper's constants
//! (`C_L = 0.15`, `tan(alpha) = 0.1`) a lone shot drifts well under 0.1 mm.

use crate::Vec3;
use crate::flow::{FlowSample, Region};
use crate::forces::DragModel;

/// The paper's lateral jet force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LateralForceModel {
    /// Lift coefficient `C_L` (default: `0.15`).
    pub lift_coefficient: f64,
    /// Divergence `tan(alpha)` of the jet's streamlines (default: `0.1`).
    pub divergence_tan: f64,
    /// Nozzle bore `d`, m.
    pub bore: f64,
    /// Drag law whose axial acceleration drives this force (it is computed here even
    /// when the drag effect itself is off).
    pub drag: DragModel,
}

impl LateralForceModel {
    /// Weight `f` of Eqs 15-16 (dimensionless, 0 on the axis, about 1 at the jet edge).
    #[inline]
    pub fn weight(&self, region: Region, s: f64, r: f64) -> f64 {
        match region {
            Region::Core | Region::Mixing | Region::Lip => 10.0 * r / (s + 5.0 * self.bore),
            Region::Developed => 5.0 * r / s.max(1e-12),
            Region::Nozzle | Region::Outside => 0.0,
        }
    }

    /// Lateral force (N) on a shot of `mass` (kg) at the flow sample `flow`. `mean_drag`
    /// gives the drag force (N) of the mean flow on the shot under this law's drag; it is
    /// called only where the force is not zero (the caller may have that drag already).
    #[inline]
    pub fn force(
        &self,
        mass: f64,
        flow: &FlowSample,
        region: Region,
        axis: &Vec3,
        mean_drag: impl FnOnce() -> Vec3,
    ) -> Vec3 {
        let f = self.weight(region, flow.coords.s, flow.coords.r);
        if f == 0.0 {
            return Vec3::zeros();
        }
        let a_axial = mean_drag().dot(axis).abs() / mass;
        let ratio = self.lift_coefficient / self.drag.coefficient;
        flow.coords.radial()
            * (mass * ratio * a_axial * f * self.divergence_tan * self.divergence_tan)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::JetCoords;

    #[test]
    fn weight_is_zero_on_axis_and_one_at_the_jet_edge() {
        let m = LateralForceModel {
            lift_coefficient: 0.15,
            divergence_tan: 0.1,
            bore: 6e-3,
            drag: DragModel { coefficient: 0.47 },
        };
        let d = 6e-3;
        assert_eq!(m.weight(Region::Core, 0.01, 0.0), 0.0);
        // Outer edge of the mixing layer r = (5d + s)/10 gives f = 1 (Eq 15).
        let s = 2.0 * d;
        assert!((m.weight(Region::Mixing, s, (5.0 * d + s) / 10.0) - 1.0).abs() < 1e-12);
        // Edge of the developed jet r = s/5 gives f = 1 (Eq 16).
        assert!((m.weight(Region::Developed, 0.08, 0.016) - 1.0).abs() < 1e-12);
        assert_eq!(m.weight(Region::Nozzle, -0.01, 0.002), 0.0);
    }

    #[test]
    fn force_points_outwards_with_hand_magnitude() {
        let m = LateralForceModel {
            lift_coefficient: 0.15,
            divergence_tan: 0.1,
            bore: 6e-3,
            drag: DragModel { coefficient: 0.47 },
        };
        let axis = Vec3::new(0.0, 0.0, -1.0);
        let flow = FlowSample {
            velocity: axis * 300.0,
            density: 5.0,
            coords: JetCoords {
                s: 0.01,
                r: 0.002,
                offset: Vec3::new(0.0, 0.002, 0.0),
            },
        };
        let (mass, area) = (2e-6, 5e-7);
        let drag = || m.drag.force(area, 5.0, &flow.velocity, &Vec3::zeros());
        let f = m.force(mass, &flow, Region::Mixing, &axis, drag);
        let a_axial = 0.5 * 5.0 * 0.47 * area * 300.0 * 300.0 / mass;
        let expected = mass * (0.15 / 0.47) * a_axial * (10.0 * 0.002 / (0.01 + 0.03)) * 0.01;
        assert!((f.y - expected).abs() < 1e-15 * expected.max(1.0) && f.x == 0.0 && f.z == 0.0);
    }
}
