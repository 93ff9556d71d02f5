//! Body-force stage: the per-shot effects (drag, lateral jet force, gravity) a scene
//! switched on. A [`ForceSet`] holds only the enabled models; the jet field is sampled
//! only when drag or the lateral force needs it. Called by the integrator once per shot
//! per Runge-Kutta stage; returns an acceleration.

pub mod drag;
pub mod gravity;
pub mod lateral;
pub mod turbulence;

pub use drag::DragModel;
pub use gravity::GravityModel;
pub use lateral::LateralForceModel;
pub use turbulence::Turbulence;

use crate::Vec3;
use crate::counters::WorkCounters;
use crate::flow::{JetField, Region};

/// Mass and size of one shot, as the force models need them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShotBody {
    /// Radius, m.
    pub radius: f64,
    /// Mass, kg.
    pub mass: f64,
}

impl ShotBody {
    /// Frontal area `pi R^2`, m^2.
    #[inline]
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * self.radius * self.radius
    }
}

/// The enabled body-force models. A disabled model is `None` and is never evaluated.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceSet {
    /// Drag (Eq 1).
    pub drag: Option<DragModel>,
    /// Lateral jet force (Eqs 15-18).
    pub lateral: Option<LateralForceModel>,
    /// Gravity.
    pub gravity: Option<GravityModel>,
    /// The jet field; `Some` exactly when drag or the lateral force is on.
    pub field: Option<JetField>,
    /// Turbulent eddies seen through drag (beyond the paper).
    pub turbulence: Option<Turbulence>,
}

impl ForceSet {
    /// Whether the jet field is sampled at all (drag or lateral force on).
    #[inline]
    pub fn needs_flow(&self) -> bool {
        self.field.is_some()
    }

    /// Acceleration (m/s^2) of `body` at `pos`, `vel`, with the jet region frozen to
    /// `region`; `gust` is the turbulent fluctuation the shot sees (zero without the
    /// effect), added to the air velocity in drag.
    #[inline(always)]
    pub fn acceleration(
        &self,
        body: &ShotBody,
        pos: &Vec3,
        vel: &Vec3,
        region: Region,
        gust: &Vec3,
        work: &mut WorkCounters,
    ) -> Vec3 {
        let mut acc = match &self.field {
            Some(field) => self.air_acceleration(field, body, pos, vel, region, gust, work),
            None => Vec3::zeros(),
        };
        if let Some(g) = &self.gravity {
            work.gravity_calls += 1;
            acc += g.acceleration;
        }
        acc
    }

    /// The air's part of [`ForceSet::acceleration`]: drag and the lateral force (kept out
    /// of line, so that the body forces of a scene without air are inlined).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn air_acceleration(
        &self,
        field: &JetField,
        body: &ShotBody,
        pos: &Vec3,
        vel: &Vec3,
        region: Region,
        gust: &Vec3,
        work: &mut WorkCounters,
    ) -> Vec3 {
        let mut force = Vec3::zeros();
        work.flow_samples += 1;
        let flow = field.sample(pos, region);
        let area = body.area();
        // The lateral force is driven by the mean flow's drag: computed once when the
        // drag effect has it (no gust), by the lateral force otherwise.
        let mut mean_drag = None;
        if let Some(drag) = &self.drag {
            work.drag_calls += 1;
            let f = if self.turbulence.is_some() && Turbulence::turbulent(region) {
                drag.force(area, flow.density, &(flow.velocity + gust), vel)
            } else {
                let f = drag.force(area, flow.density, &flow.velocity, vel);
                mean_drag = Some(f);
                f
            };
            force += f;
        }
        if let Some(lateral) = &self.lateral {
            work.lateral_force_calls += 1;
            let drag = || {
                mean_drag.unwrap_or_else(|| {
                    (lateral.drag).force(area, flow.density, &flow.velocity, vel)
                })
            };
            force += lateral.force(body.mass, &flow, region, &field.axis, drag);
        }
        force / body.mass
    }

    /// Upper bound of the body-force acceleration (m/s^2) on `body` moving at most at
    /// `speed` (m/s): used for conservative reach bounds when grouping shots.
    pub fn acceleration_bound(&self, body: &ShotBody, speed: f64) -> f64 {
        let mut a = 0.0;
        if let Some(field) = &self.field {
            let cd = self
                .drag
                .map(|d| d.coefficient)
                .or(self.lateral.map(|l| l.drag.coefficient))
                .unwrap_or(0.0);
            let gusts = self
                .turbulence
                .map_or(0.0, |t| 3f64.sqrt() * turbulence::TRUNCATION * t.intensity);
            let rel = field.max_speed() * (1.0 + gusts) + speed;
            let drag = 0.5 * field.max_density() * cd * body.area() * rel * rel / body.mass;
            // Lateral force <= (C_L/C_D) f tan^2(alpha) |a_axial| with f <= ~2 near the lip.
            let lateral = self.lateral.map_or(0.0, |l| {
                2.0 * l.lift_coefficient / l.drag.coefficient * l.divergence_tan.powi(2)
            });
            a += drag * (1.0 + lateral);
        }
        if let Some(g) = &self.gravity {
            a += g.acceleration.norm();
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::JetModel;

    fn forces(turbulence: Option<Turbulence>) -> ForceSet {
        let drag = DragModel { coefficient: 0.47 };
        ForceSet {
            drag: Some(drag),
            lateral: Some(LateralForceModel {
                lift_coefficient: 0.15,
                divergence_tan: 0.1,
                bore: 6e-3,
                drag,
            }),
            gravity: None,
            field: Some(crate::flow::jet::tests::paper_field(JetModel::Paper)),
            turbulence,
        }
    }

    /// The drag term and the lateral force's mean-flow drag are computed once when they
    /// are the same force; with a gust, the lateral force still follows the mean flow.
    #[test]
    fn the_lateral_force_is_driven_by_the_mean_flows_drag() {
        let body = ShotBody {
            radius: 0.4e-3,
            mass: 2.1e-6,
        };
        // In the mixing layer, off the axis, moving slower than the air.
        let pos = Vec3::new(1.5e-3, 1.0e-3, 0.1 - 0.012);
        let vel = Vec3::new(1.0, -2.0, -60.0);
        let gust = Vec3::new(3.0, -1.0, 20.0);
        let mut work = WorkCounters::default();
        for turbulence in [
            None,
            Some(Turbulence {
                intensity: 0.1,
                scale: 0.4,
                bore: 6e-3,
                seed: 1,
            }),
        ] {
            let set = forces(turbulence);
            let field = set.field.as_ref().unwrap();
            let region = field.region_of(&field.coords(&pos));
            assert_eq!(region, Region::Lip); // the mixing layer where its density is capped
            let flow = field.sample(&pos, region);
            let (drag, lateral) = (set.drag.unwrap(), set.lateral.unwrap());
            let area = body.area();
            let mean = drag.force(area, flow.density, &flow.velocity, &vel);
            let seen = if turbulence.is_some() {
                drag.force(area, flow.density, &(flow.velocity + gust), &vel)
            } else {
                mean
            };
            let side = lateral.force(body.mass, &flow, region, &field.axis, || mean);
            assert!(side.norm() > 0.0 && side.dot(&field.axis).abs() < 1e-18);
            let expected = (Vec3::zeros() + seen + side) / body.mass;
            let got = set.acceleration(&body, &pos, &vel, region, &gust, &mut work);
            assert_eq!(got, expected);
        }
    }
}
