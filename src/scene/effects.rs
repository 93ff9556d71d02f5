//! `[effects]`: which physical effects a run includes. Each is `true`, `false` or
//! `"auto"`; `effects = "auto"` sets all to auto. Auto decides from the scene, and the
//! run reports every decision with its reason.

use super::error::SceneError;
use super::validate::did_you_mean;
use super::{Feed, Scene};
use serde::Serialize;

/// One effect's setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    /// Always on.
    On,
    /// Always off.
    Off,
    /// Decided from the scene.
    Auto,
}

/// The effects, in report order.
pub const EFFECT_NAMES: [&str; 8] = [
    "drag",
    "lateral_force",
    "gravity",
    "specimen_contact",
    "shot_shot_contact",
    "nozzle_wall_contact",
    "friction",
    "turbulent_dispersion",
];

/// The settings as written (all `Auto` when `[effects]` is absent).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EffectRequest {
    /// Per effect, in [`EFFECT_NAMES`] order.
    pub switches: [Switch; 8],
}

impl EffectRequest {
    /// Parses the `effects` value of a scene file.
    pub fn from_value(v: Option<&toml::Value>, path: &str) -> Result<Self, SceneError> {
        let mut switches = [Switch::Auto; 8];
        let bad = |key: &str, message: String| SceneError::Invalid {
            path: path.to_string(),
            key: key.to_string(),
            message,
        };
        match v {
            None => {}
            Some(toml::Value::String(s)) if s == "auto" => {}
            Some(toml::Value::String(s)) => {
                return Err(bad(
                    "effects",
                    format!(
                        "unknown value \"{s}\"; allowed: \"auto\" or a table [effects] with keys {}",
                        EFFECT_NAMES.join(", ")
                    ),
                ));
            }
            Some(toml::Value::Table(t)) => {
                for (k, val) in t {
                    let Some(i) = EFFECT_NAMES.iter().position(|n| n == k) else {
                        let hint = did_you_mean(k, EFFECT_NAMES.iter().copied())
                            .map(|s| format!("did you mean `{s}`? "))
                            .unwrap_or_default();
                        return Err(bad(
                            &format!("effects.{k}"),
                            format!("unknown effect; {hint}allowed: {}", EFFECT_NAMES.join(", ")),
                        ));
                    };
                    switches[i] = match val {
                        toml::Value::Boolean(true) => Switch::On,
                        toml::Value::Boolean(false) => Switch::Off,
                        toml::Value::String(s) if s == "auto" => Switch::Auto,
                        other => {
                            return Err(bad(
                                &format!("effects.{k}"),
                                format!("got {other}; allowed: true, false or \"auto\""),
                            ));
                        }
                    };
                }
            }
            Some(other) => {
                return Err(bad(
                    "effects",
                    format!("got {other}; allowed: \"auto\" or a table"),
                ));
            }
        }
        Ok(EffectRequest { switches })
    }
}

/// One effect's final state and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct EffectDecision {
    /// Effect name.
    pub name: &'static str,
    /// Whether it runs.
    pub on: bool,
    /// Why (the scene said so, or what auto saw).
    pub reason: String,
}

/// The resolved effects of a scene.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Effects {
    /// Drag.
    pub drag: bool,
    /// Lateral jet force.
    pub lateral_force: bool,
    /// Gravity.
    pub gravity: bool,
    /// Shot-specimen contact.
    pub specimen_contact: bool,
    /// Shot-shot contact.
    pub shot_shot_contact: bool,
    /// Shot-nozzle-wall contact.
    pub nozzle_wall_contact: bool,
    /// Coulomb friction in the contacts, with shot spin.
    pub friction: bool,
    /// Turbulent velocity fluctuations of the jet (random eddies) acting through drag.
    pub turbulent_dispersion: bool,
    /// Every decision with its reason, in [`EFFECT_NAMES`] order.
    pub decisions: Vec<EffectDecision>,
}

impl Scene {
    /// Resolves `auto` effects from the scene.
    pub fn effects(&self) -> Effects {
        let count = self.feed.expected_count();
        let in_bore = match &self.feed {
            Feed::Batch { .. } | Feed::Stream { .. } => true,
            Feed::Box { .. } | Feed::Bed { .. } => false,
            Feed::List(list) => {
                // In the nozzle's frame (the axis may be tilted; session 27: before, a
                // list shot in a tilted bore was taken for one outside it).
                let tube = self.nozzle.tube();
                list.iter().any(|s| {
                    let along = (s.position - tube.exit).dot(&tube.axis);
                    let inlet = -tube.length - crate::flow::jet::INLET_TOLERANCE;
                    (inlet..=0.0).contains(&along)
                        && tube.radial_distance(&s.position) < tube.bore_radius
                })
            }
        };
        let body = self.nozzle.outer > self.nozzle.bore;
        let fr = &self.friction;
        let any_friction = fr.shot_specimen > 0.0 || fr.shot_shot > 0.0 || fr.shot_nozzle > 0.0;
        let turbulent = self.jet.turbulence_intensity > 0.0;
        let auto: [(bool, String); 8] = [
            (true, "auto: shots fly through the air jet".into()),
            (
                self.jet.lift_coefficient > 0.0 && self.jet.divergence_tan > 0.0,
                if self.jet.lift_coefficient > 0.0 && self.jet.divergence_tan > 0.0 {
                    "auto: the jet diverges (jet.lift_coefficient > 0)".into()
                } else {
                    "auto: jet.lift_coefficient or jet.divergence_tan is zero".into()
                },
            ),
            (
                self.gravity > 0.0,
                if self.gravity > 0.0 {
                    "auto: gravity_m_s2 > 0".into()
                } else {
                    "auto: gravity_m_s2 = 0".into()
                },
            ),
            (true, "auto: the specimen is in every scene".into()),
            (
                count > 1.0,
                if count > 1.0 {
                    if matches!(self.feed, Feed::Stream { .. }) {
                        format!(
                            "auto: about {} shots fed (rate x duration) can meet",
                            count.round()
                        )
                    } else {
                        format!("auto: {} shots can meet", count.round())
                    }
                } else {
                    "auto: only one shot".into()
                },
            ),
            (
                in_bore || body,
                if in_bore {
                    "auto: shots start inside the bore".into()
                } else if body {
                    "auto: the nozzle has a body (nozzle.outer_diameter_mm) that shots can meet"
                        .into()
                } else {
                    "auto: no shot starts inside the bore".into()
                },
            ),
            (
                any_friction,
                if any_friction {
                    "auto: a [friction] coefficient is above zero".into()
                } else {
                    "auto: every [friction] coefficient is zero (frictionless, as the paper)".into()
                },
            ),
            (
                turbulent,
                if turbulent {
                    "auto: jet.turbulence_intensity > 0".into()
                } else {
                    "auto: jet.turbulence_intensity = 0 (mean flow only, as the paper)".into()
                },
            ),
        ];
        let mut decisions = Vec::new();
        for (i, name) in EFFECT_NAMES.iter().enumerate() {
            let (on, reason) = match self.effects.switches[i] {
                Switch::On => (true, "on in the scene".to_string()),
                Switch::Off => (false, "off in the scene".to_string()),
                Switch::Auto => auto[i].clone(),
            };
            decisions.push(EffectDecision { name, on, reason });
        }
        // The air's stagnation layer above the plate or the bar and its wall jet (beyond the
        // paper):
        // the drag and the lateral force see them.
        if let Some(delta) = self.jet.stagnation_layer
            && let Some(force) = decisions[..2].iter_mut().find(|d| d.on)
        {
            force.reason += &format!(
                "; the air slows in a stagnation layer {} mm above the {}",
                super::validate::num(delta * 1e3),
                if self.specimen_shape.is_plane() {
                    "plate"
                } else {
                    "bar"
                }
            );
            if self.jet.wall_jet {
                force.reason += " and flows out along it (wall jet)";
            }
        }
        // The shot-specimen law, when it is not one constant: say so where the run lists
        // its effects.
        if let (Some(curve), true) = (&self.restitution.shot_specimen_curve, decisions[3].on) {
            let pts: Vec<(f64, f64)> = curve.points().collect();
            let ((v0, e0), (v1, e1)) = (pts[0], pts[pts.len() - 1]);
            decisions[3].reason += &format!(
                "; restitution against impact speed ({} points: {e0} at {v0} m/s to {e1} at {v1} m/s)",
                pts.len()
            );
        }
        if let (crate::contact::specimen::SpecimenShape::Cylinder { radius, axis }, true) =
            (&self.specimen_shape, decisions[3].on)
        {
            decisions[3].reason += &format!(
                "; a cylinder of radius {} mm, its axis at {} degrees from +x",
                super::validate::num(radius * 1e3),
                super::validate::num(axis.y.atan2(axis.x).to_degrees())
            );
        }
        if let (crate::contact::specimen::SpecimenShape::Groove(g), true) =
            (&self.specimen_shape, decisions[3].on)
            && let Some(gear) = g.gear()
        {
            let z = g.size();
            let n = super::validate::num;
            let (r_p, r_f, r_a, _) = gear.radii();
            decisions[3].reason += &format!(
                "; a spur gear of {} teeth, module {} mm, pressure angle {} degrees, root, \
                 pitch and tip circles {} / {} / {} mm in diameter, root fillets cut by a \
                 {} mm tool radius, tip edges of {} mm, its axis at {} degrees from +x{}",
                gear.teeth(),
                n(z.pitch.unwrap_or(0.0) / std::f64::consts::PI * 1e3),
                n(z.flank.to_degrees()),
                n(2e3 * r_f),
                n(2e3 * r_p),
                n(2e3 * r_a),
                n(z.radius * 1e3),
                n(z.edge_radius * 1e3),
                n(z.axis_angle.to_degrees()),
                if z.offset != 0.0 {
                    format!(
                        ", turned {} mm along its pitch circle from a tooth space's middle under \
                         the jet axis' foot",
                        n(z.offset * 1e3)
                    )
                } else {
                    String::new()
                }
            );
        } else if let (crate::contact::specimen::SpecimenShape::Groove(g), true) =
            (&self.specimen_shape, decisions[3].on)
        {
            let z = g.size();
            let n = super::validate::num;
            decisions[3].reason += &format!(
                "; a groove {} mm deep, root fillets of {} mm, a {} mm bottom, flanks {} degrees \
                 from the vertical, edges of {} mm, its axis at {} degrees from +x{}{}",
                n(z.depth * 1e3),
                n(z.radius * 1e3),
                n(z.bottom * 1e3),
                n(z.flank.to_degrees()),
                n(z.edge_radius * 1e3),
                n(z.axis_angle.to_degrees()),
                z.pitch
                    .map(|p| format!(", repeated every {} mm", n(p * 1e3)))
                    .unwrap_or_default(),
                if z.offset != 0.0 {
                    format!(
                        ", its middle {} mm across from the jet axis' foot",
                        n(z.offset * 1e3)
                    )
                } else {
                    String::new()
                }
            );
        }
        Effects {
            drag: decisions[0].on,
            lateral_force: decisions[1].on,
            gravity: decisions[2].on,
            specimen_contact: decisions[3].on,
            shot_shot_contact: decisions[4].on,
            nozzle_wall_contact: decisions[5].on,
            friction: decisions[6].on,
            turbulent_dispersion: decisions[7].on,
            decisions,
        }
    }
}
