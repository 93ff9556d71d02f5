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
    #[inline]
    pub fn acceleration(
        &self,
        body: &ShotBody,
        pos: &Vec3,
        vel: &Vec3,
        region: Region,
        gust: &Vec3,
        work: &mut WorkCounters,
    ) -> Vec3 {
        let mut acc = Vec3::zeros();
        if let Some(field) = &self.field {
            let mut force = Vec3::zeros();
            work.flow_samples += 1;
            let flow = field.sample(pos, region);
            let area = body.area();
            if let Some(drag) = &self.drag {
                work.drag_calls += 1;
                let air = if self.turbulence.is_some() && Turbulence::turbulent(region) {
                    flow.velocity + gust
                } else {
                    flow.velocity
                };
                force += drag.force(area, flow.density, &air, vel);
            }
            if let Some(lateral) = &self.lateral {
                work.lateral_force_calls += 1;
                force += lateral.force(body.mass, area, &flow, region, &field.axis, vel);
            }
            acc = force / body.mass;
        }
        if let Some(g) = &self.gravity {
            work.gravity_calls += 1;
            acc += g.acceleration;
        }
        acc
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
