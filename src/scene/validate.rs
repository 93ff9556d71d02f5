//! `SceneFile` -> `Scene`: range checks, cross-field checks, SI conversion.
//! Validation finishes before the first step; a run never meets a bad value.

use super::error::SceneError;
use super::file::*;
use super::material::{LIBRARY, Material, builtin};
use super::*;
use crate::contact::restitution::{MAX_POINTS, RestitutionCurve};
use crate::contact::specimen::SpecimenShape;
use crate::flow::coupling::Coupling;
use crate::flow::{AirState, JetModel};
use crate::state::Domain;

/// The domain's radius when the scene leaves it out, m (unless the nozzle reaches
/// farther: [`DOMAIN_SPARE`]).
pub const DEFAULT_DOMAIN_RADIUS: f64 = 0.25;

/// How far the default domain reaches beyond a tilted nozzle, m.
pub const DOMAIN_SPARE: f64 = 0.05;

/// A closed or open interval bound for range checks.
#[derive(Clone, Copy)]
enum B {
    /// Inclusive.
    In(f64),
    /// Exclusive.
    Ex(f64),
}

struct Checker<'a> {
    path: &'a str,
}

impl Checker<'_> {
    fn range(&self, key: &str, v: f64, lo: B, hi: B, unit: &str) -> Result<f64, SceneError> {
        // A bound computed from other keys carries their rounding (0.6410000000000001):
        // it is shown to 12 significant digits, and a value passes that meets the bound
        // either as computed or as shown (so the value the message allows passes, and so
        // does one at the computed bound itself).
        let tidy = |b: B| {
            let round = |x: f64| format!("{x:.11e}").parse().unwrap_or(x);
            match b {
                B::In(x) => B::In(round(x)),
                B::Ex(x) => B::Ex(round(x)),
            }
        };
        let above = |b: B| match b {
            B::In(l) => v >= l,
            B::Ex(l) => v > l,
        };
        let below = |b: B| match b {
            B::In(h) => v <= h,
            B::Ex(h) => v < h,
        };
        let ok_lo = above(lo) || above(tidy(lo));
        let ok_hi = below(hi) || below(tidy(hi));
        let (lo, hi) = (tidy(lo), tidy(hi));
        if ok_lo && ok_hi && v.is_finite() {
            return Ok(v);
        }
        let (lb, l) = match lo {
            B::In(l) => ('[', l),
            B::Ex(l) => ('(', l),
        };
        let (hb, h) = match hi {
            B::In(h) => (']', h),
            B::Ex(h) => (')', h),
        };
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        Err(SceneError::OutOfRange {
            path: self.path.to_string(),
            key: key.to_string(),
            value: written(v),
            allowed: format!("{lb}{}, {}{hb}{unit}", bound(l), bound(h)),
        })
    }

    fn invalid(&self, key: &str, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            path: self.path.to_string(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    fn material(&self, key: &str, name: &str, user: &[Material]) -> Result<Material, SceneError> {
        if let Some(m) = user.iter().find(|m| m.name == name) {
            return Ok(m.clone());
        }
        if let Some(m) = builtin(name) {
            return Ok(m);
        }
        let names: Vec<String> = LIBRARY
            .iter()
            .map(|m| m.name.to_string())
            .chain(user.iter().map(|m| m.name.clone()))
            .collect();
        let hint = did_you_mean(name, names.iter().map(|s| s.as_str()))
            .map(|s| format!("did you mean \"{s}\"? "))
            .unwrap_or_default();
        Err(self.invalid(
            key,
            format!(
                "unknown material \"{name}\"; {hint}known: {} (or define [materials.{name}])",
                names.join(", ")
            ),
        ))
    }
}

/// A range bound for messages: plain for ordinary magnitudes, with an exponent for tiny
/// or huge ones (`1e-12`, not `0.000000000001`).
/// `[specimen] shape = "groove"`: its dimensions, checked (`r_max`: the largest shot's
/// radius, m).
fn groove(
    c: &Checker,
    sf: &super::file::SpecimenFile,
    r_max: f64,
) -> Result<SpecimenShape, SceneError> {
    use crate::contact::groove::{Groove, GrooveError, GrooveSize};
    let r_mm = r_max * 1e3;
    let need = |key: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            c.invalid(
                key,
                "shape = \"groove\" needs radius_mm (the root fillet's) and depth_mm (bottom to \
                 lands)",
            )
        })
    };
    // Hertz's contact needs the fillet clearly wider than the shot: a shot in a fillet
    // barely larger than itself touches it along an arc (and the usual rule of peening
    // wants shots no larger than half the fillet radius).
    let radius = c.range(
        "specimen.radius_mm",
        need("specimen.radius_mm", sf.radius_mm)?,
        B::In(1.5 * r_mm),
        B::In(1e4),
        "mm (from 1.5 times the largest shot's radius: a shot in a tighter fillet touches it \
         along an arc, beyond Hertz's contact)",
    )?;
    let depth = c.range(
        "specimen.depth_mm",
        need("specimen.depth_mm", sf.depth_mm)?,
        B::Ex(0.0),
        B::In(1e4),
        "mm",
    )?;
    let bottom = c.range(
        "specimen.bottom_mm",
        sf.bottom_mm.unwrap_or(0.0),
        B::In(0.0),
        B::In(1e4),
        "mm",
    )?;
    let flank = c.range(
        "specimen.flank_deg",
        sf.flank_deg.unwrap_or(0.0),
        B::In(0.0),
        B::In(60.0),
        "degrees from the vertical",
    )?;
    let edge_radius = c.range(
        "specimen.edge_radius_mm",
        sf.edge_radius_mm.unwrap_or(radius),
        B::In(r_mm),
        B::In(1e4),
        "mm (from the largest shot's radius: a sharper edge is not modelled)",
    )?;
    let pitch = match sf.pitch_mm {
        None => None,
        Some(p) => Some(c.range("specimen.pitch_mm", p, B::Ex(0.0), B::In(1e5), "mm")? * 1e-3),
    };
    let (axis, offset) = axis_and_offset(c, sf, "mm across the groove from the jet axis' foot")?;
    let size = GrooveSize {
        radius: radius * 1e-3,
        bottom: bottom * 1e-3,
        flank: flank.to_radians(),
        depth: depth * 1e-3,
        edge_radius: edge_radius * 1e-3,
        pitch,
        axis_angle: axis.to_radians(),
        offset: offset * 1e-3,
        gear: None,
    };
    match Groove::new(size) {
        Ok(g) => Ok(SpecimenShape::Groove(std::sync::Arc::new(g))),
        Err(GrooveError::TooShallow { needed }) => Err(c.invalid(
            "specimen.depth_mm",
            format!(
                "a groove {} mm deep cannot hold its fillets and edges: they take (radius_mm + \
                 edge_radius_mm) x (1 - sin flank_deg) = {} mm; deepen it, or make the radii \
                 smaller",
                num(depth),
                num(needed * 1e3)
            ),
        )),
        Err(GrooveError::PitchTooSmall { needed }) => Err(c.invalid(
            "specimen.pitch_mm",
            format!(
                "the grooves are {} mm wide at their lands: a pitch of {} mm would overlap \
                 them; use pitch_mm >= {} mm",
                num(needed * 1e3),
                num(pitch.unwrap_or(0.0) * 1e3),
                num(needed * 1e3)
            ),
        )),
        Err(GrooveError::Undercut { .. } | GrooveError::GearTooSmall { .. }) => {
            unreachable!("BUG: a groove without teeth is not a gear")
        }
    }
}

/// A groove's or a gear's `axis_deg` and `offset_mm` (`offset`: the latter's unit and
/// meaning, for the message).
fn axis_and_offset(
    c: &Checker,
    sf: &super::file::SpecimenFile,
    offset: &str,
) -> Result<(f64, f64), SceneError> {
    let axis = c.range(
        "specimen.axis_deg",
        sf.axis_deg.unwrap_or(90.0),
        B::In(0.0),
        B::Ex(180.0),
        "degrees from +x",
    )?;
    let offset = c.range(
        "specimen.offset_mm",
        sf.offset_mm.unwrap_or(0.0),
        B::In(-1e4),
        B::In(1e4),
        offset,
    )?;
    Ok((axis, offset))
}

/// A spur gear's `[specimen]` keys (`shape = "gear"`): the gear an ISO 53 style rack
/// cuts ([`crate::contact::involute`]); `r_max` the largest shot's radius, m.
fn gear(
    c: &Checker,
    sf: &super::file::SpecimenFile,
    r_max: f64,
) -> Result<SpecimenShape, SceneError> {
    use crate::contact::groove::{GearTeeth, Groove, GrooveError, GrooveSize};
    let r_mm = r_max * 1e3;
    let (Some(teeth), Some(module)) = (sf.teeth, sf.module_mm) else {
        return Err(c.invalid(
            if sf.teeth.is_none() {
                "specimen.teeth"
            } else {
                "specimen.module_mm"
            },
            "shape = \"gear\" needs teeth (the number of teeth) and module_mm",
        ));
    };
    let teeth = c.range(
        "specimen.teeth",
        teeth as f64,
        B::In(6.0),
        B::In(1000.0),
        "teeth",
    )? as u32;
    let m = c.range("specimen.module_mm", module, B::Ex(0.0), B::In(100.0), "mm")?;
    let alpha = c.range(
        "specimen.pressure_angle_deg",
        sf.pressure_angle_deg.unwrap_or(20.0),
        B::In(10.0),
        B::In(35.0),
        "degrees",
    )?;
    let addendum = c.range(
        "specimen.addendum_mm",
        sf.addendum_mm.unwrap_or(m),
        B::Ex(0.0),
        B::In(2.0 * m),
        "mm (up to 2 modules; 1 module when left out)",
    )?;
    // The rack's corner must fit under its pitch line and the shot in the fillet (as
    // in a groove).
    let radius = c.range(
        "specimen.radius_mm",
        sf.radius_mm.unwrap_or(0.38 * m),
        B::In(1.5 * r_mm),
        B::In(m),
        "mm (the root fillets, the cutter's tip radius; 0.38 modules when left out: from \
         1.5 times the largest shot's radius, a shot in a tighter fillet touches it along an \
         arc, up to a module)",
    )?;
    let dedendum = c.range(
        "specimen.dedendum_mm",
        sf.dedendum_mm.unwrap_or(1.25 * m),
        B::Ex(radius),
        B::In(2.0 * m),
        "mm (above the root fillets' radius_mm, up to 2 modules; 1.25 modules when left out)",
    )?;
    let edge_radius = c.range(
        "specimen.edge_radius_mm",
        sf.edge_radius_mm.unwrap_or(0.2 * m),
        B::In(r_mm),
        B::In(m),
        "mm (the tip edges; 0.2 modules when left out: from the largest shot's radius, a \
         sharper edge is not modelled, up to a module)",
    )?;
    let (axis, offset) = axis_and_offset(
        c,
        sf,
        "mm along the pitch circle, the tooth space's middle from the jet axis' foot",
    )?;
    let (a, pitch) = (alpha.to_radians(), std::f64::consts::PI * m);
    let (sa, ca) = a.sin_cos();
    // The rack's tooth tip (the groove's bottom) between its corners, for a tooth space
    // half a pitch wide at the pitch line.
    let hb = pitch / 4.0 - (dedendum - radius * (1.0 - sa)) * sa / ca - radius * ca;
    if hb < 0.0 {
        let most = (pitch / 4.0 - dedendum * sa / ca) / (ca - (1.0 - sa) * sa / ca);
        return Err(c.invalid(
            "specimen.radius_mm",
            format!(
                "root fillets of {} mm do not fit the cutter's tooth tip with module_mm = {}, \
                 pressure_angle_deg = {} and dedendum_mm = {}: use radius_mm <= {} mm",
                num(radius),
                num(m),
                num(alpha),
                num(dedendum),
                num(most)
            ),
        ));
    }
    let size = GrooveSize {
        radius: radius * 1e-3,
        bottom: 2.0 * hb * 1e-3,
        flank: a,
        depth: (addendum + dedendum) * 1e-3,
        edge_radius: edge_radius * 1e-3,
        pitch: Some(pitch * 1e-3),
        axis_angle: axis.to_radians(),
        offset: offset * 1e-3,
        gear: Some(GearTeeth {
            teeth,
            dedendum: dedendum * 1e-3,
        }),
    };
    let g = match Groove::new(size) {
        Ok(g) => g,
        Err(GrooveError::Undercut { needed_teeth }) => {
            return Err(c.invalid(
                "specimen.teeth",
                format!(
                    "{teeth} teeth: the cutter would undercut the flanks (not modelled); use \
                     teeth >= {needed_teeth}, or a smaller dedendum_mm (a positive profile \
                     shift)"
                ),
            ));
        }
        Err(GrooveError::GearTooSmall { why }) => {
            return Err(c.invalid("specimen.teeth", format!("{teeth} teeth: {why}")));
        }
        Err(GrooveError::TooShallow { .. } | GrooveError::PitchTooSmall { .. }) => {
            return Err(c.invalid(
                "specimen.edge_radius_mm",
                format!(
                    "tip edges of {} mm and root fillets of {} mm do not fit a tooth of \
                     module {}: make them smaller",
                    num(edge_radius),
                    num(radius),
                    num(m)
                ),
            ));
        }
    };
    // Hertz's contact on a convex surface needs it no sharper than the shot (as on a
    // groove's edges): the involute is sharpest where the fillets end.
    let flank = g.gear().map(|g| g.flank_radius()).unwrap_or(f64::INFINITY);
    if flank < r_max {
        return Err(c.invalid(
            "specimen.teeth",
            format!(
                "{teeth} teeth: the flanks' radius of curvature where the fillets end is {} mm, \
                 below the largest shot's radius ({} mm; Hertz's contact is not modelled on a \
                 sharper convex surface): use more teeth or a smaller dedendum_mm",
                num(flank * 1e3),
                num(r_mm)
            ),
        ));
    }
    Ok(SpecimenShape::Groove(std::sync::Arc::new(g)))
}

fn bound(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e9) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A value as the scene wrote it; in exponent form where that runs long (`1e300`, not
/// 301 digits).
fn written(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() > 16 {
        format!("{x:e}")
    } else {
        plain
    }
}

/// A number for messages: up to 6 significant digits, no trailing zeros.
pub fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (6 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Closest candidate to `word`, if one is close enough to be a likely typo: Jaro-Winkler
/// similarity >= 0.8 (transpositions, dropped letters) or Sorensen-Dice bigram
/// similarity >= 0.6 (a missing prefix such as `gauge_`).
pub fn did_you_mean<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let w = word.to_lowercase();
    candidates
        .map(|c| {
            let lc = c.to_lowercase();
            let jw = strsim::jaro_winkler(&w, &lc);
            let dice = strsim::sorensen_dice(&w, &lc);
            let score = if jw >= 0.8 { jw } else { 0.0 }.max(if dice >= 0.6 { dice } else { 0.0 });
            (score, c)
        })
        .filter(|(s, _)| *s > 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

impl SceneFile {
    /// Checks every value and builds the SI [`Scene`]. `path` names the file in messages;
    /// `text` is kept for provenance in the outputs.
    pub fn validate(self, path: &str, text: &str) -> Result<Scene, SceneError> {
        let c = Checker { path };
        let f = self;
        let duration = c.range("duration_ms", f.duration_ms, B::Ex(0.0), B::In(1e5), "ms")? * 1e-3;
        let gravity = c.range(
            "gravity_m_s2",
            f.gravity_m_s2,
            B::In(0.0),
            B::In(100.0),
            "m/s^2",
        )?;

        // Materials first: the rest refers to them.
        let mut user = Vec::new();
        for (name, m) in &f.materials {
            let k = |s: &str| format!("materials.{name}.{s}");
            user.push(Material {
                name: name.clone(),
                youngs_modulus: c.range(
                    &k("youngs_modulus_gpa"),
                    m.youngs_modulus_gpa,
                    B::Ex(0.0),
                    B::In(2000.0),
                    "GPa",
                )? * 1e9,
                poisson_ratio: c.range(
                    &k("poisson_ratio"),
                    m.poisson_ratio,
                    B::Ex(-1.0),
                    B::Ex(0.5),
                    "",
                )?,
                density: c.range(
                    &k("density_kg_m3"),
                    m.density_kg_m3,
                    B::Ex(0.0),
                    B::In(1e5),
                    "kg/m^3",
                )?,
                yield_strength: match m.yield_strength_mpa {
                    Some(y) => Some(
                        c.range(&k("yield_strength_mpa"), y, B::Ex(0.0), B::In(1e5), "MPa")? * 1e6,
                    ),
                    None => None,
                },
            });
        }

        let a = &f.air;
        let air_inputs = AirInputs {
            gauge_pressure: c.range(
                "air.gauge_pressure_mpa",
                a.gauge_pressure_mpa,
                B::Ex(0.0),
                B::In(5.0),
                "MPa",
            )? * 1e6,
            ambient_pressure: c.range(
                "air.ambient_pressure_mpa",
                a.ambient_pressure_mpa,
                B::In(0.01),
                B::In(1.0),
                "MPa",
            )? * 1e6,
            temperature: c.range(
                "air.temperature_k",
                a.temperature_k,
                B::In(150.0),
                B::In(600.0),
                "K",
            )?,
            kappa: c.range("air.kappa", a.kappa, B::Ex(1.0), B::In(1.67), "")?,
            gas_constant: c.range(
                "air.gas_constant_j_kg_k",
                a.gas_constant_j_kg_k,
                B::In(100.0),
                B::In(5000.0),
                "J/(kg K)",
            )?,
            ambient_density: c.range(
                "air.ambient_density_kg_m3",
                a.ambient_density_kg_m3,
                B::Ex(0.0),
                B::In(10.0),
                "kg/m^3",
            )?,
        };
        let air = AirState::new(
            air_inputs.gauge_pressure,
            air_inputs.ambient_pressure,
            air_inputs.temperature,
            air_inputs.kappa,
            air_inputs.gas_constant,
            air_inputs.ambient_density,
        );

        let n = &f.nozzle;
        let angle = c
            .range(
                "nozzle.angle_deg",
                n.angle_deg,
                B::In(30.0),
                B::In(90.0),
                "deg",
            )?
            .to_radians();
        let azimuth = c
            .range(
                "nozzle.azimuth_deg",
                n.azimuth_deg,
                B::In(-360.0),
                B::In(360.0),
                "deg",
            )?
            .to_radians();
        let bore_mm = c.range("nozzle.bore_mm", n.bore_mm, B::Ex(0.0), B::In(100.0), "mm")?;
        let outer_mm = match n.outer_diameter_mm {
            Some(v) => c.range(
                "nozzle.outer_diameter_mm",
                v,
                B::In(bore_mm),
                B::In(500.0),
                "mm",
            )?,
            None => bore_mm,
        };
        let nozzle = NozzleGeometry {
            angle,
            azimuth,
            bore: bore_mm * 1e-3,
            length: c.range(
                "nozzle.length_mm",
                n.length_mm,
                B::Ex(0.0),
                B::In(2000.0),
                "mm",
            )? * 1e-3,
            outer: outer_mm * 1e-3,
            standoff: c.range(
                "nozzle.standoff_mm",
                n.standoff_mm,
                B::Ex(0.0),
                B::In(5000.0),
                "mm",
            )? * 1e-3,
        };
        // The exit's rim is the nozzle's lowest point: it must stay above the specimen
        // (before session 27 a tilted nozzle close to the part was run with its lip
        // inside the specimen).
        let rim = 0.5 * nozzle.outer * angle.cos();
        if nozzle.standoff * angle.sin() - rim <= 0.0 {
            let (what, key) = if n.outer_diameter_mm.is_some() {
                ("outer radius", "outer_diameter_mm")
            } else {
                ("bore radius", "bore_mm")
            };
            return Err(c.invalid(
                "nozzle.standoff_mm",
                format!(
                    "{} mm at angle_deg = {} puts the exit's rim ({what} {} mm) {} mm into the specimen: use standoff_mm > {} mm, a steeper angle_deg or a smaller {key}",
                    num(n.standoff_mm),
                    num(n.angle_deg),
                    num(0.5 * outer_mm),
                    num((rim - nozzle.standoff * angle.sin()) * 1e3),
                    num(rim / angle.sin() * 1e3),
                ),
            ));
        }
        let nozzle_material = c.material("nozzle.material", &n.material, &user)?;

        let j = &f.jet;
        let lip_cap = match j.lip_density_cap_kg_m3 {
            Some(v) => c.range(
                "jet.lip_density_cap_kg_m3",
                v,
                B::Ex(0.0),
                B::In(1000.0),
                "kg/m^3",
            )?,
            None => air.rho_stagnation,
        };
        let jet = JetSettings {
            model: match j.model {
                JetModelFile::Paper => JetModel::Paper,
                JetModelFile::Consistent => JetModel::Consistent,
            },
            core_density: match j.core_density {
                CoreDensityFile::RhoStar => CoreDensity::RhoStar,
                CoreDensityFile::Rho0 => CoreDensity::Rho0,
            },
            lip_density_cap: lip_cap,
            drag_coefficient: c.range(
                "jet.drag_coefficient",
                j.drag_coefficient,
                B::Ex(0.0),
                B::In(10.0),
                "",
            )?,
            lift_coefficient: c.range(
                "jet.lift_coefficient",
                j.lift_coefficient,
                B::In(0.0),
                B::In(10.0),
                "",
            )?,
            divergence_tan: c.range(
                "jet.divergence_tan",
                j.divergence_tan,
                B::In(0.0),
                B::In(1.0),
                "",
            )?,
            turbulence_intensity: c.range(
                "jet.turbulence_intensity",
                j.turbulence_intensity,
                B::In(0.0),
                B::In(0.5),
                "",
            )?,
            stagnation_layer: match j.stagnation_layer_mm {
                Some(v) => Some(
                    c.range(
                        "jet.stagnation_layer_mm",
                        v,
                        B::Ex(0.0),
                        B::In(n.standoff_mm),
                        "mm (up to nozzle.standoff_mm)",
                    )? * 1e-3,
                ),
                None => None,
            },
            wall_jet: j.wall_jet,
            coupling: match j.coupling {
                CouplingFile::OneWay => Coupling::OneWay,
                CouplingFile::Momentum => Coupling::Momentum,
            },
        };

        // Shot sizes.
        let s = &f.shots;
        let dia = |key: &str, v: f64| {
            c.range(key, v, B::Ex(0.0), B::In(20.0), "mm")
                .map(|v| v * 1e-3)
        };
        let sizes = match (&s.diameter_mm, &s.size_distribution) {
            (Some(_), Some(_)) => {
                return Err(c.invalid(
                    "shots.diameter_mm",
                    "give either shots.diameter_mm or [shots.size_distribution], not both",
                ));
            }
            (Some(d), None) => SizeDistribution::Fixed(dia("shots.diameter_mm", *d)?),
            (None, None) => SizeDistribution::Fixed(0.8e-3),
            (
                None,
                Some(SizeDistributionFile::Normal {
                    mean_mm,
                    std_mm,
                    min_mm,
                    max_mm,
                }),
            ) => {
                let k = "shots.size_distribution";
                let mean = dia(&format!("{k}.mean_mm"), *mean_mm)?;
                let std = c.range(
                    &format!("{k}.std_mm"),
                    *std_mm,
                    B::In(0.0),
                    B::In(10.0),
                    "mm",
                )? * 1e-3;
                let min = dia(&format!("{k}.min_mm"), *min_mm)?;
                let max = dia(&format!("{k}.max_mm"), *max_mm)?;
                if !(min <= mean && mean <= max) {
                    return Err(c.invalid(k, "need min_mm <= mean_mm <= max_mm"));
                }
                SizeDistribution::Normal {
                    mean,
                    std,
                    min,
                    max,
                }
            }
            (None, Some(SizeDistributionFile::Uniform { min_mm, max_mm })) => {
                let k = "shots.size_distribution";
                let min = dia(&format!("{k}.min_mm"), *min_mm)?;
                let max = dia(&format!("{k}.max_mm"), *max_mm)?;
                if min > max {
                    return Err(c.invalid(k, "need min_mm <= max_mm"));
                }
                SizeDistribution::Uniform { min, max }
            }
            (
                None,
                Some(SizeDistributionFile::Sieve {
                    grade,
                    openings_mm,
                    retained_percent,
                }),
            ) => {
                let k = "shots.size_distribution";
                let (openings, retained): (Vec<f64>, Vec<f64>) = match (
                    grade,
                    openings_mm,
                    retained_percent,
                ) {
                    (Some(g), None, None) => {
                        let Some((_, o, r)) = SIEVE_GRADES
                            .iter()
                            .find(|(n, _, _)| n.eq_ignore_ascii_case(g))
                        else {
                            let names: Vec<&str> =
                                SIEVE_GRADES.iter().map(|(n, _, _)| *n).collect();
                            return Err(c.invalid(
                                    &format!("{k}.grade"),
                                    format!(
                                        "unknown grade \"{g}\"; built in: {} (or give openings_mm and retained_percent)",
                                        names.join(", ")
                                    ),
                                ));
                        };
                        (o.to_vec(), r.to_vec())
                    }
                    (None, Some(o), Some(r)) => (o.clone(), r.clone()),
                    _ => {
                        return Err(c.invalid(
                                k,
                                "a sieve distribution takes either grade = \"S330\" or both openings_mm and retained_percent",
                            ));
                    }
                };
                if openings.len() < 2 || retained.len() + 1 != openings.len() {
                    return Err(c.invalid(
                        k,
                        format!(
                            "openings_mm has {} sieves and retained_percent {} values: give one more opening than retained values (the first opening passes everything)",
                            openings.len(),
                            retained.len()
                        ),
                    ));
                }
                let mut edges = Vec::with_capacity(openings.len());
                for (i, &o) in openings.iter().enumerate() {
                    let d = dia(&format!("{k}.openings_mm[{i}]"), o)?;
                    if i > 0 && d >= edges[i - 1] {
                        return Err(c.invalid(
                            &format!("{k}.openings_mm[{i}]"),
                            format!(
                                "{} mm is not smaller than the sieve before it: list openings from the largest down",
                                num(o)
                            ),
                        ));
                    }
                    edges.push(d);
                }
                let mut mass = Vec::with_capacity(retained.len());
                for (i, &r) in retained.iter().enumerate() {
                    mass.push(c.range(
                        &format!("{k}.retained_percent[{i}]"),
                        r,
                        B::In(0.0),
                        B::In(100.0),
                        "%",
                    )?);
                }
                let total: f64 = mass.iter().sum();
                if !(99.0..=101.0).contains(&total) {
                    return Err(c.invalid(
                        &format!("{k}.retained_percent"),
                        format!(
                            "adds up to {} %; a sieve analysis adds up to 100 %",
                            num(total)
                        ),
                    ));
                }
                edges.reverse();
                mass.reverse();
                SizeDistribution::sieve(edges, &mass)
            }
            (
                None,
                Some(SizeDistributionFile::Discrete {
                    diameters_mm,
                    weights,
                }),
            ) => {
                let k = "shots.size_distribution";
                if diameters_mm.is_empty() || diameters_mm.len() != weights.len() {
                    return Err(c.invalid(
                        k,
                        format!(
                            "diameters_mm ({}) and weights ({}) must be non-empty lists of equal length",
                            diameters_mm.len(),
                            weights.len()
                        ),
                    ));
                }
                let mut d = Vec::new();
                let mut w = Vec::new();
                for (i, (&di, &wi)) in diameters_mm.iter().zip(weights).enumerate() {
                    d.push(dia(&format!("{k}.diameters_mm[{i}]"), di)?);
                    w.push(c.range(
                        &format!("{k}.weights[{i}]"),
                        wi,
                        B::In(0.0),
                        B::In(1e9),
                        "",
                    )?);
                }
                if w.iter().sum::<f64>() <= 0.0 {
                    return Err(c.invalid(k, "weights must not all be zero"));
                }
                SizeDistribution::Discrete {
                    diameters: d,
                    weights: w,
                }
            }
        };
        let d_max = sizes.max_diameter();
        if d_max >= nozzle.bore {
            return Err(c.invalid(
                "shots.diameter_mm",
                format!(
                    "shots of {} mm do not fit the {} mm bore (nozzle.bore_mm): use shots smaller than the bore",
                    num(d_max * 1e3),
                    num(nozzle.bore * 1e3)
                ),
            ));
        }
        let shot_material = c.material("shots.material", &s.material, &user)?;
        let r_max = 0.5 * d_max;

        let sf = &f.specimen;
        let groove_keys = [
            ("specimen.bottom_mm", sf.bottom_mm.is_some()),
            ("specimen.flank_deg", sf.flank_deg.is_some()),
            ("specimen.depth_mm", sf.depth_mm.is_some()),
            ("specimen.edge_radius_mm", sf.edge_radius_mm.is_some()),
            ("specimen.pitch_mm", sf.pitch_mm.is_some()),
            ("specimen.offset_mm", sf.offset_mm.is_some()),
        ];
        let gear_keys = [
            ("specimen.teeth", sf.teeth.is_some()),
            ("specimen.module_mm", sf.module_mm.is_some()),
            (
                "specimen.pressure_angle_deg",
                sf.pressure_angle_deg.is_some(),
            ),
            ("specimen.addendum_mm", sf.addendum_mm.is_some()),
            ("specimen.dedendum_mm", sf.dedendum_mm.is_some()),
        ];
        if sf.shape != "gear"
            && let Some((key, _)) = gear_keys.iter().find(|(_, given)| *given)
        {
            return Err(c.invalid(
                key,
                format!(
                    "only a gear has this dimension: set shape = \"gear\" (shape is \"{}\")",
                    sf.shape
                ),
            ));
        }
        let specimen_shape = match sf.shape.as_str() {
            "plane" => {
                for (key, given) in [
                    ("specimen.radius_mm", sf.radius_mm.is_some()),
                    ("specimen.axis_deg", sf.axis_deg.is_some()),
                ]
                .into_iter()
                .chain(groove_keys)
                {
                    if given {
                        return Err(c.invalid(
                            key,
                            "the flat specimen has no dimensions: set shape = \"cylinder\", \
                             \"groove\" or \"gear\", or leave the key out for the flat specimen",
                        ));
                    }
                }
                SpecimenShape::Plane
            }
            "cylinder" => {
                for (key, given) in groove_keys {
                    if given {
                        return Err(c.invalid(
                            key,
                            "only a groove has this dimension: a cylinder takes radius_mm and \
                             axis_deg",
                        ));
                    }
                }
                let Some(radius_mm) = sf.radius_mm else {
                    return Err(c.invalid(
                        "specimen.radius_mm",
                        "shape = \"cylinder\" needs the cylinder's radius_mm (at least the \
                         largest shot's radius)",
                    ));
                };
                // The elliptic contact's equivalent radius is good to 1e-3 of the load
                // for a cylinder at least as large as the shot (`SpecimenShape::effective_radius`).
                let r_max = 0.5 * sizes.max_diameter() * 1e3;
                let radius = c.range(
                    "specimen.radius_mm",
                    radius_mm,
                    B::In(r_max),
                    B::In(1e4),
                    "mm (from the largest shot's radius)",
                )? * 1e-3;
                let axis = c.range(
                    "specimen.axis_deg",
                    sf.axis_deg.unwrap_or(90.0),
                    B::In(0.0),
                    B::Ex(180.0),
                    "degrees from +x",
                )?;
                SpecimenShape::cylinder(radius, axis.to_radians())
            }
            "groove" => groove(&c, sf, 0.5 * sizes.max_diameter())?,
            "gear" => {
                for (key, given) in [
                    ("specimen.bottom_mm", sf.bottom_mm.is_some()),
                    ("specimen.flank_deg", sf.flank_deg.is_some()),
                    ("specimen.depth_mm", sf.depth_mm.is_some()),
                    ("specimen.pitch_mm", sf.pitch_mm.is_some()),
                ] {
                    if given {
                        return Err(c.invalid(
                            key,
                            "a gear's tooth spaces follow from module_mm, teeth, \
                             pressure_angle_deg, addendum_mm, dedendum_mm, radius_mm (root \
                             fillets) and edge_radius_mm (tip edges): leave this key out",
                        ));
                    }
                }
                gear(&c, sf, 0.5 * sizes.max_diameter())?
            }
            other => {
                return Err(c.invalid(
                    "specimen.shape",
                    format!(
                        "unknown value \"{other}\"; allowed: \"plane\", \"cylinder\", \"groove\", \"gear\""
                    ),
                ));
            }
        };
        // The nozzle stays above a groove's lands, as above the plate.
        if let SpecimenShape::Groove(g) = &specimen_shape {
            let depth = g.size().depth;
            if nozzle.standoff * angle.sin() - rim <= depth {
                let (what, key) = if g.gear().is_some() {
                    ("gear's tooth tips", "addendum_mm + dedendum_mm")
                } else {
                    ("groove's lands", "depth_mm")
                };
                return Err(c.invalid(
                    "nozzle.standoff_mm",
                    format!(
                        "{} mm at angle_deg = {} puts the exit's rim {} mm below the {what} \
                         (specimen.{key} = {}): use standoff_mm > {} mm",
                        num(n.standoff_mm),
                        num(n.angle_deg),
                        num((depth + rim - nozzle.standoff * angle.sin()) * 1e3),
                        num(depth * 1e3),
                        num((depth + rim) / angle.sin() * 1e3),
                    ),
                ));
            }
        }
        let feed = match &s.feed {
            FeedFile::Batch {
                count,
                radial_offset_mm,
                axial_spread_mm,
            } => {
                let k = "shots.feed";
                let count = *count;
                if count == 0 || count > 10_000_000 {
                    return Err(SceneError::OutOfRange {
                        path: path.into(),
                        key: format!("{k}.count"),
                        value: count.to_string(),
                        allowed: "[1, 10000000]".into(),
                    });
                }
                let r0 = c.range(
                    &format!("{k}.radial_offset_mm[0]"),
                    radial_offset_mm[0],
                    B::In(0.0),
                    B::In(100.0),
                    "mm",
                )? * 1e-3;
                let r1 = c.range(
                    &format!("{k}.radial_offset_mm[1]"),
                    radial_offset_mm[1],
                    B::In(0.0),
                    B::In(100.0),
                    "mm",
                )? * 1e-3;
                if r0 > r1 {
                    return Err(c.invalid(
                        &format!("{k}.radial_offset_mm"),
                        "need [min, max] with min <= max",
                    ));
                }
                let limit = 0.5 * nozzle.bore - r_max;
                if r1 > limit + 1e-12 {
                    return Err(c.invalid(
                        &format!("{k}.radial_offset_mm"),
                        format!(
                            "shot centres up to {} mm from the axis put {} mm shots into the bore wall (bore radius {} mm): keep radial_offset_mm[1] <= {} mm",
                            num(r1 * 1e3),
                            num(d_max * 1e3),
                            num(0.5 * nozzle.bore * 1e3),
                            num(limit * 1e3)
                        ),
                    ));
                }
                let spread = c.range(
                    &format!("{k}.axial_spread_mm"),
                    *axial_spread_mm,
                    B::In(0.0),
                    B::In(n.length_mm),
                    "mm (0 to the bore length)",
                )? * 1e-3;
                Feed::Batch {
                    count,
                    radial_min: r0,
                    radial_max: r1,
                    axial_spread: spread,
                }
            }
            FeedFile::Stream {
                rate_per_s,
                mass_flow_kg_min,
                duration_ms,
                entry_speed_m_s,
                arrivals,
            } => {
                let k = "shots.feed";
                let rate = match (rate_per_s, mass_flow_kg_min) {
                    (Some(r), None) => c.range(
                        &format!("{k}.rate_per_s"),
                        *r,
                        B::Ex(0.0),
                        B::In(1e9),
                        "shots/s",
                    )?,
                    (None, Some(q)) => {
                        let q = c.range(
                            &format!("{k}.mass_flow_kg_min"),
                            *q,
                            B::Ex(0.0),
                            B::In(1000.0),
                            "kg/min",
                        )?;
                        let mean_mass = shot_material.density * sizes.mean_volume();
                        q / 60.0 / mean_mass
                    }
                    _ => {
                        return Err(c.invalid(
                            k,
                            "a stream feed needs exactly one of rate_per_s or mass_flow_kg_min",
                        ));
                    }
                };
                let feed_duration = match duration_ms {
                    Some(d) => {
                        c.range(
                            &format!("{k}.duration_ms"),
                            *d,
                            B::Ex(0.0),
                            B::In(1e5),
                            "ms",
                        )? * 1e-3
                    }
                    None => duration,
                };
                let count = rate * feed_duration;
                if count > 1e8 {
                    return Err(c.invalid(
                        k,
                        format!("rate x duration = {count:.3e} shots; at most 1e8 are supported"),
                    ));
                }
                let entry = c.range(
                    &format!("{k}.entry_speed_m_s"),
                    *entry_speed_m_s,
                    B::In(0.0),
                    B::In(500.0),
                    "m/s",
                )?;
                let poisson = match arrivals.as_str() {
                    "poisson" => true,
                    "regular" => false,
                    other => {
                        return Err(c.invalid(
                            &format!("{k}.arrivals"),
                            format!("unknown value \"{other}\"; allowed: \"poisson\", \"regular\""),
                        ));
                    }
                };
                Feed::Stream {
                    rate,
                    duration: feed_duration,
                    entry_speed: entry,
                    poisson,
                }
            }
            FeedFile::Box {
                count,
                min_mm,
                max_mm,
                velocity_m_s,
            } => {
                let k = "shots.feed";
                if *count == 0 || *count > 10_000_000 {
                    return Err(SceneError::OutOfRange {
                        path: path.into(),
                        key: format!("{k}.count"),
                        value: count.to_string(),
                        allowed: "[1, 10000000]".into(),
                    });
                }
                let mut lo = [0.0; 3];
                let mut hi = [0.0; 3];
                for a in 0..3 {
                    lo[a] = c.range(
                        &format!("{k}.min_mm[{a}]"),
                        min_mm[a],
                        B::In(-1e5),
                        B::In(1e5),
                        "mm",
                    )? * 1e-3;
                    hi[a] = c.range(
                        &format!("{k}.max_mm[{a}]"),
                        max_mm[a],
                        B::In(-1e5),
                        B::In(1e5),
                        "mm",
                    )? * 1e-3;
                    c.range(
                        &format!("{k}.velocity_m_s[{a}]"),
                        velocity_m_s[a],
                        B::In(-1e4),
                        B::In(1e4),
                        "m/s",
                    )?;
                    if hi[a] - lo[a] < d_max {
                        return Err(c.invalid(&format!("{k}.max_mm"), format!("the box is narrower than a shot along axis {a}: need max_mm - min_mm >= {} mm", num(d_max * 1e3))));
                    }
                }
                if lo[2] < r_max {
                    return Err(c.invalid(
                        &format!("{k}.min_mm"),
                        "min_mm[2] puts shots into the specimen: keep it >= the shot radius",
                    ));
                }
                // In a groove the box stays above the lands (it may be wider than the
                // groove: shots placed in the teeth would start inside the part).
                if let SpecimenShape::Groove(g) = &specimen_shape
                    && lo[2] < g.size().depth + r_max
                {
                    let (what, key) = if g.gear().is_some() {
                        (
                            "gear's teeth: a box is placed above their tips",
                            "addendum_mm + dedendum_mm",
                        )
                    } else {
                        (
                            "groove's teeth: a box is placed above the lands",
                            "depth_mm",
                        )
                    };
                    return Err(c.invalid(
                        &format!("{k}.min_mm"),
                        format!(
                            "min_mm[2] puts shots into the {what}, keep it >= {key} + the shot \
                             radius = {} mm",
                            num((g.size().depth + r_max) * 1e3)
                        ),
                    ));
                }
                Feed::Box {
                    count: *count,
                    min: crate::Vec3::new(lo[0], lo[1], lo[2]),
                    max: crate::Vec3::new(hi[0], hi[1], hi[2]),
                    velocity: crate::Vec3::new(velocity_m_s[0], velocity_m_s[1], velocity_m_s[2]),
                }
            }
            FeedFile::Bed {
                nx,
                ny,
                layers,
                squeeze,
            } => {
                let k = "shots.feed";
                for (name, v) in [("nx", nx), ("ny", ny), ("layers", layers)] {
                    if *v == 0 || *v > 1000 {
                        return Err(SceneError::OutOfRange {
                            path: path.into(),
                            key: format!("{k}.{name}"),
                            value: v.to_string(),
                            allowed: "[1, 1000]".into(),
                        });
                    }
                }
                let squeeze = c.range(
                    &format!("{k}.squeeze"),
                    *squeeze,
                    B::In(0.0),
                    B::In(0.01),
                    "",
                )?;
                if !matches!(sizes, SizeDistribution::Fixed(_)) {
                    return Err(c.invalid(k, "a bed needs one shot size (shots.diameter_mm)"));
                }
                Feed::Bed {
                    nx: *nx,
                    ny: *ny,
                    layers: *layers,
                    squeeze,
                }
            }
            FeedFile::List { shots } => {
                if shots.is_empty() {
                    return Err(c.invalid(
                        "shots.feed.shots",
                        "a list feed needs at least one [[shots.feed.shots]] entry",
                    ));
                }
                let mut list = Vec::new();
                for (i, sh) in shots.iter().enumerate() {
                    let k = format!("shots.feed.shots[{i}]");
                    for (ax, v) in sh.position_mm.iter().enumerate() {
                        c.range(
                            &format!("{k}.position_mm[{ax}]"),
                            *v,
                            B::In(-1e5),
                            B::In(1e5),
                            "mm",
                        )?;
                    }
                    for (ax, v) in sh.velocity_m_s.iter().enumerate() {
                        c.range(
                            &format!("{k}.velocity_m_s[{ax}]"),
                            *v,
                            B::In(-1e4),
                            B::In(1e4),
                            "m/s",
                        )?;
                    }
                    let d = match sh.diameter_mm {
                        Some(d) => dia(&format!("{k}.diameter_mm"), d)?,
                        None => {
                            match &sizes {
                                SizeDistribution::Fixed(d) => *d,
                                _ => {
                                    return Err(c.invalid(&format!("{k}.diameter_mm"), "list shots need a diameter when shots use a size distribution"));
                                }
                            }
                        }
                    };
                    if d >= nozzle.bore {
                        return Err(c.invalid(
                            &format!("{k}.diameter_mm"),
                            format!(
                                "a {} mm shot does not fit the {} mm bore",
                                num(d * 1e3),
                                num(nozzle.bore * 1e3)
                            ),
                        ));
                    }
                    let start = c.range(
                        &format!("{k}.start_ms"),
                        sh.start_ms,
                        B::In(0.0),
                        B::In(1e5),
                        "ms",
                    )? * 1e-3;
                    let pos =
                        crate::Vec3::new(sh.position_mm[0], sh.position_mm[1], sh.position_mm[2])
                            * 1e-3;
                    let above = specimen_shape.distance(&pos);
                    // (On a curved surface the distance carries a square root's rounding:
                    // a shot laid on a bar's crest at z = r must pass.)
                    let slack = if specimen_shape.is_plane() {
                        0.0
                    } else {
                        1e-9 * d
                    };
                    if above < 0.5 * d - slack {
                        let from = if specimen_shape.is_plane() {
                            "above the specimen"
                        } else {
                            "from the specimen's surface"
                        };
                        return Err(c.invalid(
                            &format!("{k}.position_mm"),
                            format!("the shot's centre is {} mm {from}, less than its radius {} mm: it would start inside the specimen", num(above * 1e3), num(0.5 * d * 1e3)),
                        ));
                    }
                    if let Some(g) = nozzle.tube().geometry(&pos, 0.5 * d)
                        && g.gap < 0.0
                    {
                        return Err(c.invalid(
                            &format!("{k}.position_mm"),
                            format!(
                                "the shot would start overlapping the nozzle tube by {} mm (its centre is {} mm from the nozzle axis, the bore radius is {} mm{}): place it inside the bore at most {} mm from the axis, or clear of the tube",
                                num(-g.gap * 1e3),
                                num(nozzle.tube().radial_distance(&pos) * 1e3),
                                num(0.5 * nozzle.bore * 1e3),
                                if nozzle.outer > nozzle.bore {
                                    format!(", the outer radius {} mm", num(0.5 * nozzle.outer * 1e3))
                                } else {
                                    String::new()
                                },
                                num((0.5 * nozzle.bore - 0.5 * d) * 1e3)
                            ),
                        ));
                    }
                    list.push(ListShot {
                        position: pos,
                        velocity: crate::Vec3::new(
                            sh.velocity_m_s[0],
                            sh.velocity_m_s[1],
                            sh.velocity_m_s[2],
                        ),
                        diameter: d,
                        start,
                    });
                }
                Feed::List(list)
            }
        };

        let r = &f.restitution;
        let shot_specimen_curve = match (&r.shot_specimen_curve, r.shot_specimen) {
            (None, _) => None,
            (Some(_), Some(_)) => {
                return Err(c.invalid(
                    "restitution.shot_specimen_curve",
                    "give either shot_specimen (one restitution) or shot_specimen_curve \
                     (restitution against impact speed), not both",
                ));
            }
            (Some(cf), None) => {
                let k = "restitution.shot_specimen_curve";
                let n = cf.speed_m_s.len();
                if n == 0 || n > MAX_POINTS || cf.restitution.len() != n {
                    return Err(c.invalid(
                        k,
                        format!(
                            "speed_m_s has {n} values and restitution {}: give the same \
                             number of each, 1 to {MAX_POINTS}",
                            cf.restitution.len()
                        ),
                    ));
                }
                for (i, (&v, &e)) in cf.speed_m_s.iter().zip(&cf.restitution).enumerate() {
                    let lo = if i == 0 {
                        B::Ex(0.0)
                    } else {
                        B::Ex(cf.speed_m_s[i - 1])
                    };
                    c.range(&format!("{k}.speed_m_s[{i}]"), v, lo, B::In(1000.0), "m/s")
                        .map_err(|e| match (i, e) {
                            (
                                1..,
                                SceneError::OutOfRange {
                                    path,
                                    key,
                                    value,
                                    allowed,
                                },
                            ) => SceneError::OutOfRange {
                                path,
                                key,
                                value,
                                allowed: format!("{allowed} (speeds increase)"),
                            },
                            (_, e) => e,
                        })?;
                    c.range(
                        &format!("{k}.restitution[{i}]"),
                        e,
                        B::Ex(0.0),
                        B::In(1.0),
                        "",
                    )?;
                }
                Some(RestitutionCurve::new(
                    cf.speed_m_s.clone(),
                    cf.restitution.clone(),
                ))
            }
        };
        let restitution = Restitution {
            shot_specimen: match &shot_specimen_curve {
                Some(curve) => curve.at(f64::INFINITY),
                None => c.range(
                    "restitution.shot_specimen",
                    r.shot_specimen.unwrap_or(0.7),
                    B::Ex(0.0),
                    B::In(1.0),
                    "",
                )?,
            },
            shot_specimen_curve,
            shot_shot: c.range(
                "restitution.shot_shot",
                r.shot_shot,
                B::Ex(0.0),
                B::In(1.0),
                "",
            )?,
            shot_nozzle: c.range(
                "restitution.shot_nozzle",
                r.shot_nozzle,
                B::Ex(0.0),
                B::In(1.0),
                "",
            )?,
        };
        let fr = &f.friction;
        let friction = FrictionCoefficients {
            shot_specimen: c.range(
                "friction.shot_specimen",
                fr.shot_specimen,
                B::In(0.0),
                B::In(2.0),
                "",
            )?,
            shot_shot: c.range(
                "friction.shot_shot",
                fr.shot_shot,
                B::In(0.0),
                B::In(2.0),
                "",
            )?,
            shot_nozzle: c.range(
                "friction.shot_nozzle",
                fr.shot_nozzle,
                B::In(0.0),
                B::In(2.0),
                "",
            )?,
            history: match fr.tangential.as_str() {
                "viscous" => false,
                "history" => true,
                other => {
                    return Err(c.invalid(
                        "friction.tangential",
                        format!("unknown value \"{other}\"; allowed: \"viscous\", \"history\""),
                    ));
                }
            },
        };
        let it = &f.integrator;
        let method = match (it.method.as_str(), it.fixed_step_ns) {
            ("adaptive", None) => crate::integrate::island::Method::Adaptive,
            ("adaptive", Some(_)) => {
                return Err(c.invalid(
                    "integrator.fixed_step_ns",
                    "only used with method = \"verlet\" or \"hybrid\"",
                ));
            }
            ("verlet", Some(ns)) => crate::integrate::island::Method::Verlet {
                step: c.range("integrator.fixed_step_ns", ns, B::Ex(0.0), B::In(1e6), "ns")? * 1e-9,
            },
            ("hybrid", Some(ns)) => crate::integrate::island::Method::Hybrid {
                step: c.range("integrator.fixed_step_ns", ns, B::Ex(0.0), B::In(1e6), "ns")? * 1e-9,
            },
            (m @ ("verlet" | "hybrid"), None) => {
                return Err(c.invalid(
                    "integrator.method",
                    format!(
                        "method = \"{m}\" needs fixed_step_ns (the step inside contacts: about a \
                         fiftieth of the shortest Hertz contact time, as in DEM codes)"
                    ),
                ));
            }
            (other, _) => {
                return Err(c.invalid(
                    "integrator.method",
                    format!(
                        "unknown value \"{other}\"; allowed: \"adaptive\", \"verlet\", \"hybrid\""
                    ),
                ));
            }
        };
        let scheduler = match it.scheduler.as_str() {
            "auto" => crate::sim::Scheduler::Auto,
            "windows" => crate::sim::Scheduler::Windows,
            "events" => crate::sim::Scheduler::Events,
            other => {
                return Err(c.invalid(
                    "integrator.scheduler",
                    format!(
                        "unknown value \"{other}\"; allowed: \"auto\", \"windows\", \"events\""
                    ),
                ));
            }
        };
        let integrator = IntegratorSettings {
            method,
            scheduler,
            tolerance: c.range(
                "integrator.tolerance",
                it.tolerance,
                B::In(1e-12),
                B::In(1e-2),
                "",
            )?,
            contact_steps: c.range(
                "integrator.contact_steps",
                it.contact_steps,
                B::In(10.0),
                B::In(1e5),
                "",
            )?,
            max_step: c.range(
                "integrator.max_step_ms",
                it.max_step_ms,
                B::Ex(0.0),
                B::In(100.0),
                "ms",
            )? * 1e-3,
        };
        if let (Feed::Bed { .. }, false) = (&feed, specimen_shape.is_plane()) {
            return Err(c.invalid(
                "shots.feed.type",
                "\"bed\" rests its layers on a flat specimen: use [specimen] shape = \"plane\" \
                 for a bed",
            ));
        }
        match (jet.stagnation_layer, &specimen_shape) {
            (None, _) | (Some(_), SpecimenShape::Plane) => {}
            (Some(delta), SpecimenShape::Cylinder { radius, .. }) => {
                if delta > *radius {
                    return Err(c.invalid(
                        "jet.stagnation_layer_mm",
                        format!(
                            "{} mm is thicker than the bar's radius ({} mm): the air goes \
                             round a bar, and its speed normal to it recovers within about \
                             the radius (potential flow past a cylinder: the layer's slope \
                             at the wall for a layer one radius thick): use \
                             stagnation_layer_mm <= {}, or leave it out",
                            num(delta * 1e3),
                            num(radius * 1e3),
                            num(radius * 1e3)
                        ),
                    ));
                }
            }
            (Some(_), SpecimenShape::Groove(_)) => {
                return Err(c.invalid(
                    "jet.stagnation_layer_mm",
                    "the stagnation layer is modelled above a flat plate or a bar only (in a \
                     groove or a gear's tooth space the air's turn is not a layer's): use \
                     [specimen] shape = \"plane\" or \"cylinder\", or leave \
                     jet.stagnation_layer_mm out",
                ));
            }
        }
        if jet.coupling == Coupling::Momentum
            && !matches!(feed, Feed::Stream { .. } | Feed::Batch { .. })
        {
            return Err(c.invalid(
                "jet.coupling",
                "\"momentum\" slows the jet by what a stream's or a batch's shots take from \
                 it, and this feed is neither: use shots.feed.type = \"stream\" or \"batch\", \
                 or coupling = \"one_way\"",
            ));
        }
        if let (true, None) = (jet.wall_jet, jet.stagnation_layer) {
            return Err(c.invalid(
                "jet.wall_jet",
                "the wall jet is the air the stagnation layer turns aside: set \
                 jet.stagnation_layer_mm too, or leave jet.wall_jet out",
            ));
        }
        if let (true, Some(delta)) = (jet.wall_jet, jet.stagnation_layer) {
            if !specimen_shape.is_plane() {
                return Err(c.invalid(
                    "jet.wall_jet",
                    "the wall jet is modelled over a flat plate only (over a bar the layer \
                     slows the air normal to it and does not send it round): use [specimen] \
                     shape = \"plane\", or set wall_jet = false",
                ));
            }
            if n.angle_deg != 90.0 {
                return Err(c.invalid(
                    "jet.wall_jet",
                    format!(
                        "the wall jet is modelled under a jet normal to the plate only, and \
                         nozzle.angle_deg = {}: use angle_deg = 90, or set wall_jet = false",
                        num(n.angle_deg)
                    ),
                ));
            }
            let ratio =
                crate::flow::JetField::wall_jet_peak_ratio(nozzle.bore, nozzle.standoff, delta);
            if ratio > 1.0 {
                return Err(c.invalid(
                    "jet.stagnation_layer_mm",
                    format!(
                        "{} mm is too thin for the wall jet: its air would leave along the \
                         plate at up to {} times the jet's speed at the plate, and a wall jet \
                         cannot outrun the jet that feeds it: use stagnation_layer_mm >= {} \
                         (with bore_mm = {} and standoff_mm = {}), or wall_jet = false",
                        num(delta * 1e3),
                        num((ratio * 1e3).round() / 1e3),
                        num((ratio * delta * 1e5).ceil() / 1e2),
                        num(bore_mm),
                        num(n.standoff_mm)
                    ),
                ));
            }
        }
        let specimen_material = c.material("specimen.material", &f.specimen.material, &user)?;
        let effects = EffectRequest::from_value(f.effects.as_ref(), path)?;
        let turbulence_asked = effects.switches[7] == super::effects::Switch::On
            || (effects.switches[7] == super::effects::Switch::Auto
                && jet.turbulence_intensity > 0.0);
        if turbulence_asked && method.fixed_step().is_some() {
            return Err(c.invalid(
                "integrator.method",
                format!(
                    "method = \"{}\" does not renew turbulent eddies in its fixed steps: use \
                     method = \"adaptive\" with jet.turbulence_intensity > 0, or set \
                     effects.turbulent_dispersion = false",
                    method.name()
                ),
            ));
        }
        if friction.history && matches!(method, crate::integrate::island::Method::Adaptive) {
            return Err(c.invalid(
                "friction.tangential",
                "\"history\" (the tangential spring) needs a fixed step inside contacts: set \
                 [integrator] method = \"hybrid\" (adaptive in flight; the fast choice with air) \
                 or \"verlet\" (every step fixed, as LIGGGHTS), with fixed_step_ns (a fiftieth of \
                 the contact time, as LIGGGHTS steps), or use tangential = \"viscous\"",
            ));
        }
        let dm = &f.domain;
        // How far the nozzle reaches from the vertical through the jet axis' foot: a
        // tilted nozzle's inlet lies `(standoff + length) cos(angle)` off it.
        let reach = [nozzle.inlet(), nozzle.exit()]
            .iter()
            .map(|p| p.x.hypot(p.y))
            .fold(0.0, f64::max)
            + 0.5 * nozzle.outer.max(nozzle.bore);
        let radius = match dm.radius_mm {
            None => DEFAULT_DOMAIN_RADIUS.max(reach + DOMAIN_SPARE),
            Some(r) => {
                let r = c.range("domain.radius_mm", r, B::Ex(0.0), B::In(1e5), "mm")? * 1e-3;
                if r < reach {
                    return Err(c.invalid(
                        "domain.radius_mm",
                        format!(
                            "{} mm leaves part of the nozzle outside the domain (it reaches {} \
                             mm from the vertical through the jet axis' foot): its shots would \
                             be dropped as they start; set at least {} mm, or leave radius_mm \
                             out",
                            num(r * 1e3),
                            num(reach * 1e3),
                            num((reach * 1e3).ceil())
                        ),
                    ));
                }
                r
            }
        };
        let domain = Domain {
            radius,
            top: nozzle.inlet().z.max(nozzle.exit().z)
                + c.range(
                    "domain.above_inlet_mm",
                    dm.above_inlet_mm,
                    B::In(0.0),
                    B::In(1e5),
                    "mm",
                )? * 1e-3,
            bottom: specimen_shape.floor(0.5 * sizes.max_diameter()),
        };
        Ok(Scene {
            path: path.to_string(),
            text: text.to_string(),
            title: f.title,
            seed: f.seed,
            duration,
            gravity,
            air_inputs,
            air,
            nozzle,
            jet,
            sizes,
            shot_material,
            specimen_material,
            specimen_shape,
            nozzle_material,
            feed,
            restitution,
            friction,
            integrator,
            effects,
            domain,
        })
    }
}
