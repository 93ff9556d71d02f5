//! Scene stage: reading a TOML scene, checking it, and turning it into SI values.
//!
//! `file.rs` mirrors the file (`SceneFile`), `validate.rs` checks it and builds [`Scene`],
//! `effects.rs` resolves which effects run, `material.rs` holds the material library.
//! The paper's Table 2 scene is embedded ([`DEFAULT_SCENE`]) and is what `peenflow run`
//! runs without a file and what `peenflow init` writes.

pub mod effects;
pub mod error;
pub mod examples;
pub mod file;
pub mod material;
pub mod validate;

pub use effects::{EffectDecision, EffectRequest, Effects, Switch};
pub use error::SceneError;
pub use file::SceneFile;
pub use material::Material;

use crate::Vec3;
use crate::flow::{AirState, JetModel};
use crate::state::Domain;

/// The paper's Table 2 scene, commented: the default scene.
pub const DEFAULT_SCENE: &str = include_str!("default_scene.toml");

/// Air-supply inputs, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AirInputs {
    /// Gauge pressure `P`, Pa.
    pub gauge_pressure: f64,
    /// Ambient pressure `P_b`, Pa.
    pub ambient_pressure: f64,
    /// Temperature, K.
    pub temperature: f64,
    /// Ratio of specific heats.
    pub kappa: f64,
    /// Specific gas constant, J/(kg K).
    pub gas_constant: f64,
    /// Ambient density, kg/m^3.
    pub ambient_density: f64,
}

/// Nozzle geometry, m. The jet axis meets the specimen plane at the origin (the axis
/// foot); the exit centre lies `standoff` back along the axis, the inlet `length` further.
/// At the default 90 degrees the axis is the world -z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NozzleGeometry {
    /// Bore diameter `d`, m.
    pub bore: f64,
    /// Bore length `l_n`, m.
    pub length: f64,
    /// Outer diameter of the nozzle body, m (`bore` for a thin-walled tube).
    pub outer: f64,
    /// Stand-off `l` along the axis, m.
    pub standoff: f64,
    /// Angle between the axis and the specimen surface, rad (pi/2: normal).
    pub angle: f64,
    /// Tilt direction in the specimen plane, rad from +x.
    pub azimuth: f64,
}

impl NozzleGeometry {
    /// Unit vector along the jet axis, downstream.
    pub fn axis(&self) -> Vec3 {
        let tilt = std::f64::consts::FRAC_PI_2 - self.angle;
        if tilt == 0.0 {
            return Vec3::new(0.0, 0.0, -1.0);
        }
        Vec3::new(
            self.azimuth.cos() * tilt.sin(),
            self.azimuth.sin() * tilt.sin(),
            -tilt.cos(),
        )
    }

    /// Two unit vectors across the axis (a right-handed frame with the axis); the world
    /// x and y axes at 90 degrees.
    pub fn cross_axes(&self) -> (Vec3, Vec3) {
        let tilt = std::f64::consts::FRAC_PI_2 - self.angle;
        if tilt == 0.0 {
            return (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        }
        let (ca, sa) = (self.azimuth.cos(), self.azimuth.sin());
        let e1 = Vec3::new(ca * tilt.cos(), sa * tilt.cos(), tilt.sin());
        let e2 = Vec3::new(-sa, ca, 0.0);
        (e1, e2)
    }

    /// Centre of the exit plane, m.
    pub fn exit(&self) -> Vec3 {
        let tilt = std::f64::consts::FRAC_PI_2 - self.angle;
        if tilt == 0.0 {
            return Vec3::new(0.0, 0.0, self.standoff);
        }
        -self.axis() * self.standoff
    }

    /// Centre of the inlet plane, m.
    pub fn inlet(&self) -> Vec3 {
        let tilt = std::f64::consts::FRAC_PI_2 - self.angle;
        if tilt == 0.0 {
            return Vec3::new(0.0, 0.0, self.standoff + self.length);
        }
        -self.axis() * (self.standoff + self.length)
    }

    /// The tube the shots meet (nozzle wall contact).
    pub fn tube(&self) -> crate::contact::Tube {
        crate::contact::Tube {
            exit: self.exit(),
            axis: self.axis(),
            bore_radius: 0.5 * self.bore,
            outer_radius: 0.5 * self.outer,
            length: self.length,
        }
    }
}

/// Which density fills the bore and the potential core (model-notes defect 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoreDensity {
    /// `rho*` (Eq 12): the default.
    RhoStar,
    /// `rho_0` (Eq 4).
    Rho0,
}

/// Jet-model settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JetSettings {
    /// Density laws.
    pub model: JetModel,
    /// Core density choice.
    pub core_density: CoreDensity,
    /// Cap of the Eq 5 density, kg/m^3.
    pub lip_density_cap: f64,
    /// `C_D`.
    pub drag_coefficient: f64,
    /// `C_L`.
    pub lift_coefficient: f64,
    /// `tan(alpha)`.
    pub divergence_tan: f64,
    /// Turbulence intensity (fraction of the local mean speed; 0: none).
    pub turbulence_intensity: f64,
    /// Thickness of the stagnation layer above the flat specimen or round the bar, m
    /// (`None`: the free jet runs on into the part; `flow::jet::JetField::layer`).
    pub stagnation_layer: Option<f64>,
    /// Whether the layer's air flows out along the plate (`flow::jet::JetField::wall_jet`).
    pub wall_jet: bool,
    /// Whether the shots slow the jet (`flow::coupling`).
    pub coupling: crate::flow::coupling::Coupling,
}

/// Shot diameters, m.
#[derive(Debug, Clone, PartialEq)]
pub enum SizeDistribution {
    /// Every shot alike.
    Fixed(f64),
    /// Truncated normal.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        std: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Uniform.
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// A sieve analysis: diameters uniform within each sieve interval, intervals drawn
    /// with number weights converted from the retained mass fractions.
    Sieve {
        /// Interval edges, ascending (one more than the weights).
        edges: Vec<f64>,
        /// Number weight of each interval.
        weights: Vec<f64>,
    },
    /// Discrete sizes with number weights.
    Discrete {
        /// Diameters.
        diameters: Vec<f64>,
        /// Weights.
        weights: Vec<f64>,
    },
}

impl SizeDistribution {
    /// Largest possible diameter, m.
    pub fn max_diameter(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(d) => *d,
            SizeDistribution::Normal { max, .. } | SizeDistribution::Uniform { max, .. } => *max,
            SizeDistribution::Discrete { diameters, .. } => {
                diameters.iter().cloned().fold(0.0, f64::max)
            }
            SizeDistribution::Sieve { edges, .. } => *edges.last().expect("BUG: validated"),
        }
    }

    /// Smallest possible diameter, m.
    pub fn min_diameter(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(d) => *d,
            SizeDistribution::Normal { min, .. } | SizeDistribution::Uniform { min, .. } => *min,
            SizeDistribution::Discrete { diameters, .. } => {
                diameters.iter().cloned().fold(f64::INFINITY, f64::min)
            }
            SizeDistribution::Sieve { edges, .. } => edges[0],
        }
    }

    /// Mean shot volume, m^3 (for converting a mass flow into a shot rate).
    pub fn mean_volume(&self) -> f64 {
        let v = |d: f64| std::f64::consts::PI / 6.0 * d * d * d;
        match self {
            SizeDistribution::Fixed(d) => v(*d),
            SizeDistribution::Normal { .. } => self.classes().iter().map(|(d, w)| v(*d) * w).sum(),
            SizeDistribution::Uniform { min, max } => {
                // E[d^3] for d uniform on [min, max].
                if max > min {
                    std::f64::consts::PI / 6.0 * (max.powi(4) - min.powi(4)) / (4.0 * (max - min))
                } else {
                    v(*min)
                }
            }
            SizeDistribution::Discrete { diameters, weights } => {
                let w: f64 = weights.iter().sum();
                diameters
                    .iter()
                    .zip(weights)
                    .map(|(d, wi)| v(*d) * wi / w)
                    .sum()
            }
            SizeDistribution::Sieve { edges, weights } => {
                let w: f64 = weights.iter().sum();
                weights
                    .iter()
                    .enumerate()
                    .map(|(k, wk)| {
                        uniform_d3(edges[k], edges[k + 1]) * std::f64::consts::PI / 6.0 * wk / w
                    })
                    .sum()
            }
        }
    }
}

/// Equal-width bins a normal's or a uniform's range is cut into by
/// [`SizeDistribution::classes`].
pub const SIZE_BINS: usize = 4;

impl SizeDistribution {
    /// Size classes standing for the distribution, as `(diameter, number weight)` with the
    /// weights summing to 1 and each diameter the cube root of its class's mean `d^3`, so
    /// `sum w pi/6 d^3` is the mean shot volume: one class per discrete size or sieve
    /// interval, [`SIZE_BINS`] equal-width bins across a normal's (truncated, as drawn)
    /// or a uniform's range.
    pub fn classes(&self) -> Vec<(f64, f64)> {
        let normalised = |c: Vec<(f64, f64)>| {
            let total: f64 = c.iter().map(|x| x.1).sum();
            c.into_iter()
                .filter(|x| x.1 > 0.0)
                .map(|(d, w)| (d, w / total))
                .collect()
        };
        let bins = |min: f64, max: f64| {
            (0..SIZE_BINS).map(move |k| {
                let at = |j: usize| min + (max - min) * j as f64 / SIZE_BINS as f64;
                (at(k), at(k + 1))
            })
        };
        match self {
            SizeDistribution::Fixed(d) => vec![(*d, 1.0)],
            SizeDistribution::Uniform { min, max } if max > min => normalised(
                bins(*min, *max)
                    .map(|(a, b)| (uniform_d3(a, b).cbrt(), 1.0))
                    .collect(),
            ),
            SizeDistribution::Normal {
                mean,
                std,
                min,
                max,
            } if *std > 0.0 && max > min => normalised(
                bins(*min, *max)
                    .map(|(a, b)| {
                        // The truncated normal's weight and mean d^3 over the bin, by
                        // Simpson's rule on panels of at most a sixteenth of `std`.
                        let n = 2 * ((8.0 * (b - a) / std).ceil() as usize).clamp(32, 1 << 15);
                        let h = (b - a) / n as f64;
                        let (mut w, mut d3) = (0.0, 0.0);
                        for i in 0..=n {
                            let d = a + h * i as f64;
                            let s = if i == 0 || i == n {
                                1.0
                            } else {
                                (2 + 2 * (i % 2)) as f64
                            };
                            let p = s * (-0.5 * ((d - mean) / std).powi(2)).exp();
                            w += p;
                            d3 += p * d * d * d;
                        }
                        if w > 0.0 {
                            ((d3 / w).cbrt(), w)
                        } else {
                            (a, 0.0)
                        }
                    })
                    .collect(),
            ),
            SizeDistribution::Normal { mean, .. } => vec![(*mean, 1.0)],
            SizeDistribution::Uniform { min, .. } => vec![(*min, 1.0)],
            SizeDistribution::Sieve { edges, weights } => normalised(
                weights
                    .iter()
                    .enumerate()
                    .map(|(k, w)| (uniform_d3(edges[k], edges[k + 1]).cbrt(), *w))
                    .collect(),
            ),
            SizeDistribution::Discrete { diameters, weights } => normalised(
                diameters
                    .iter()
                    .cloned()
                    .zip(weights.iter().cloned())
                    .collect(),
            ),
        }
    }
}

/// `E[d^3]` for `d` uniform on `[a, b]`.
pub fn uniform_d3(a: f64, b: f64) -> f64 {
    if b > a {
        (b.powi(4) - a.powi(4)) / (4.0 * (b - a))
    } else {
        a * a * a
    }
}

/// Standard sieve grades: (name, openings mm descending, mass % retained between them).
/// Typical new cast steel shot inside the SAE J444 / AMS 2431 limits: S330 all passes
/// 1.40 mm, at most 5 % on 1.18 mm, at least 85 % on 0.85 mm and coarser, at least 96 %
/// on 0.71 mm and coarser; S230 all passes 1.00 mm, at most 10 % on 0.85 mm, at least
/// 85 % on 0.60 mm and coarser, at least 97 % on 0.50 mm and coarser. The pan's lower
/// bound is the next standard sieve. Enter your supplier's analysis for real media.
pub const SIEVE_GRADES: &[(&str, &[f64], &[f64])] = &[
    (
        "S330",
        &[1.40, 1.18, 1.00, 0.85, 0.71, 0.60],
        &[2.0, 38.0, 50.0, 8.0, 2.0],
    ),
    (
        "S230",
        &[1.00, 0.85, 0.71, 0.60, 0.50, 0.425],
        &[5.0, 40.0, 45.0, 8.0, 2.0],
    ),
];

impl SizeDistribution {
    /// Number weights of sieve intervals from mass fractions: `n_k ~ m_k / E[d^3]_k`.
    pub fn sieve(edges_ascending: Vec<f64>, mass: &[f64]) -> SizeDistribution {
        let weights = mass
            .iter()
            .enumerate()
            .map(|(k, m)| m / uniform_d3(edges_ascending[k], edges_ascending[k + 1]))
            .collect();
        SizeDistribution::Sieve {
            edges: edges_ascending,
            weights,
        }
    }
}

/// One shot of a list feed, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct ListShot {
    /// Centre, m.
    pub position: Vec3,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Diameter, m.
    pub diameter: f64,
    /// Entry time, s.
    pub start: f64,
}

/// How shots enter the run, SI.
#[derive(Debug, Clone, PartialEq)]
pub enum Feed {
    /// `count` shots at rest near the inlet.
    Batch {
        /// Number of shots.
        count: u32,
        /// Smallest centre offset from the axis, m.
        radial_min: f64,
        /// Largest centre offset from the axis, m.
        radial_max: f64,
        /// Depth below the inlet over which centres spread, m.
        axial_spread: f64,
    },
    /// Continuous feed.
    Stream {
        /// Shots per second.
        rate: f64,
        /// Feeding time, s.
        duration: f64,
        /// Entry speed along the axis, m/s.
        entry_speed: f64,
        /// Poisson (true) or regular arrivals.
        poisson: bool,
    },
    /// Random pack in a box with one velocity.
    Box {
        /// Number of shots.
        count: u32,
        /// Lower corner, m.
        min: Vec3,
        /// Upper corner, m.
        max: Vec3,
        /// Velocity, m/s.
        velocity: Vec3,
    },
    /// FCC bed resting on the specimen.
    Bed {
        /// Cells along x.
        nx: u32,
        /// Cells along y.
        ny: u32,
        /// Layers.
        layers: u32,
        /// Relative pre-compression.
        squeeze: f64,
    },
    /// Explicit shots.
    List(Vec<ListShot>),
}

impl Feed {
    /// Number of shots the feed will (on average) produce.
    pub fn expected_count(&self) -> f64 {
        match self {
            Feed::Batch { count, .. } => *count as f64,
            Feed::Stream { rate, duration, .. } => rate * duration,
            Feed::List(l) => l.len() as f64,
            Feed::Box { count, .. } => *count as f64,
            Feed::Bed { nx, ny, layers, .. } => 2.0 * *nx as f64 * *ny as f64 * *layers as f64,
        }
    }
}

/// Restitution coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct Restitution {
    /// Shot on specimen. With a curve: the curve's value at its fastest point, which only
    /// sets the base law (`SpecimenContact::law`, whose stiffness every contact uses and
    /// whose damping none does).
    pub shot_specimen: f64,
    /// Shot on specimen against the normal impact speed (`None`: `shot_specimen` at every
    /// speed).
    pub shot_specimen_curve: Option<crate::contact::restitution::RestitutionCurve>,
    /// Shot on shot.
    pub shot_shot: f64,
    /// Shot on nozzle wall.
    pub shot_nozzle: f64,
}

/// Coulomb friction coefficients (the `friction` effect).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrictionCoefficients {
    /// Shot on specimen.
    pub shot_specimen: f64,
    /// Shot on shot.
    pub shot_shot: f64,
    /// Shot on nozzle wall.
    pub shot_nozzle: f64,
    /// The tangential law: `false` Coulomb with viscous stick, no history (the default);
    /// `true` the tangential spring with history (`tangential = "history"`).
    pub history: bool,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegratorSettings {
    /// Relative tolerance.
    pub tolerance: f64,
    /// Minimum steps per contact duration.
    pub contact_steps: f64,
    /// Largest step, s.
    pub max_step: f64,
    /// Integration method.
    pub method: crate::integrate::island::Method,
    /// How shots are scheduled (synchronisation windows or events).
    pub scheduler: crate::sim::Scheduler,
}

/// A checked scene in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// File the scene came from (or `<default scene>`).
    pub path: String,
    /// The scene's full TOML text.
    pub text: String,
    /// Title.
    pub title: String,
    /// Seed.
    pub seed: u64,
    /// Simulated time, s.
    pub duration: f64,
    /// Gravity magnitude, m/s^2 (along -z).
    pub gravity: f64,
    /// Air inputs.
    pub air_inputs: AirInputs,
    /// Derived air state.
    pub air: AirState,
    /// Nozzle.
    pub nozzle: NozzleGeometry,
    /// Jet settings.
    pub jet: JetSettings,
    /// Shot sizes.
    pub sizes: SizeDistribution,
    /// Shot material.
    pub shot_material: Material,
    /// Specimen material.
    pub specimen_material: Material,
    /// Specimen surface (`[specimen] shape`).
    pub specimen_shape: crate::contact::specimen::SpecimenShape,
    /// Nozzle-wall material.
    pub nozzle_material: Material,
    /// Feed.
    pub feed: Feed,
    /// Restitution coefficients.
    pub restitution: Restitution,
    /// Friction coefficients.
    pub friction: FrictionCoefficients,
    /// Integrator settings.
    pub integrator: IntegratorSettings,
    /// Requested effects.
    pub effects: EffectRequest,
    /// Domain.
    pub domain: Domain,
}

impl Scene {
    /// The embedded default scene (the paper's Table 2).
    pub fn default_scene() -> Scene {
        Scene::from_toml(DEFAULT_SCENE, "<default scene>")
            .expect("BUG: the embedded default scene is invalid")
    }

    /// Reads and checks a scene file.
    pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: shown.clone(),
            source,
        })?;
        Scene::from_toml(&text, &shown)
    }

    /// Parses and checks scene text; `path` names it in messages.
    pub fn from_toml(text: &str, path: &str) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| parse_error(path, text, &e))?;
        file.validate(path, text)
    }

    /// Height of the nozzle exit centre above the specimen, m.
    pub fn exit_height(&self) -> f64 {
        self.nozzle.exit().z
    }

    /// Height of the nozzle inlet centre above the specimen, m.
    pub fn inlet_height(&self) -> f64 {
        self.nozzle.inlet().z
    }

    /// Density of the bore and core, kg/m^3, per the `core_density` choice.
    pub fn core_density(&self) -> f64 {
        match self.jet.core_density {
            CoreDensity::RhoStar => self.air.rho_exit,
            CoreDensity::Rho0 => self.air.rho_stagnation,
        }
    }
}

/// Turns a TOML/serde error into one line with position, key and a did-you-mean.
fn parse_error(path: &str, text: &str, e: &toml::de::Error) -> SceneError {
    let offset = e.span().map(|s| s.start).unwrap_or(0).min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    let column = text[line_start..offset].chars().count() + 1;
    // Internally tagged tables (feeds, size distributions) report errors at the table
    // header: find the offending `key = value` line below it by the value in the message.
    let (mut line, line_start, mut column) = locate_value(
        text,
        &e.message().replace('\n', " "),
        line,
        line_start,
        column,
    );
    let here = text[line_start..].lines().next().unwrap_or("").trim();
    let table = if here.starts_with('[') { here } else { "" };
    let table = std::iter::once(table)
        .chain(text[..line_start].lines().rev())
        .find_map(table_name)
        .unwrap_or_default()
        .to_string();
    let where_ = if table.is_empty() {
        "at the top level".to_string()
    } else {
        format!("in [{table}]")
    };
    let msg = e.message().replace('\n', " ").trim().to_string();
    let ticked = |s: &str| -> Vec<String> {
        s.split('`')
            .skip(1)
            .step_by(2)
            .map(|x| x.to_string())
            .collect()
    };
    let message = if let Some(rest) = msg.strip_prefix("unknown field ") {
        let names = ticked(rest);
        let key = names.first().cloned().unwrap_or_default();
        let expected: Vec<String> = names.into_iter().skip(1).collect();
        // A misspelt table's name (`[shotz]`, `[shots.feeed]`) is reported at its header:
        // the unknown key belongs to the table above it.
        let own = here.starts_with('[') && table.rsplit('.').next() == Some(key.as_str());
        let where_ = match table.rsplit_once('.') {
            _ if !own => where_,
            Some((parent, _)) => format!("in [{parent}]"),
            None => "at the top level".to_string(),
        };
        let hint = validate::did_you_mean(&key, expected.iter().map(|s| s.as_str()))
            .map(|s| format!("; did you mean `{s}`?"))
            .unwrap_or_default();
        format!(
            "unknown key `{key}` {where_}{hint} (allowed: {})",
            expected.join(", ")
        )
    } else if let Some(rest) = msg.strip_prefix("missing field ") {
        let key = ticked(rest).first().cloned().unwrap_or_default();
        // A `list` feed's shots are read with the feed (after its `type`): a shot without
        // its centre is reported at the feed's header, and a feed without its `type`
        // (the shots' headers made it) at the first shot's. Each is put where it belongs.
        if key == "position_mm" && table == "shots.feed" {
            if let Some(at) = list_shot_without(text, "position_mm") {
                (line, column) = (at, 1);
            }
            "missing key `position_mm` in [[shots.feed.shots]]: each listed shot needs its \
             centre"
                .to_string()
        } else if key == "type" && table == "shots.feed.shots" {
            "missing key `type` in [shots.feed] (`type = \"list\"` for shots listed one by \
             one)"
                .to_string()
        } else {
            format!("missing key `{key}` {where_}")
        }
    } else if msg.starts_with("unknown variant") {
        let names = ticked(&msg);
        let got = names.first().cloned().unwrap_or_default();
        let allowed: Vec<String> = names.into_iter().skip(1).collect();
        let key = key_on_line(text, line_start);
        let hint = validate::did_you_mean(&got, allowed.iter().map(|s| s.as_str()))
            .map(|s| format!("did you mean \"{s}\"? "))
            .unwrap_or_default();
        format!(
            "key `{key}` {where_}: unknown value \"{got}\"; {hint}allowed: {}",
            allowed.join(", ")
        )
    } else if msg.starts_with("invalid type")
        || msg.starts_with("invalid value")
        || msg.starts_with("invalid length")
    {
        let key = key_on_line(text, line_start);
        format!("key `{key}` {where_}: {msg}")
    } else {
        format!("TOML syntax error: {msg}")
    };
    SceneError::Parse {
        path: path.to_string(),
        line,
        column,
        message,
    }
}

fn locate_value(
    text: &str,
    msg: &str,
    line: usize,
    line_start: usize,
    column: usize,
) -> (usize, usize, usize) {
    let Some(table) = table_name(text[line_start..].lines().next().unwrap_or("")) else {
        return (line, line_start, column);
    };
    // An unknown key of such a table: its own line, found by its name (unless the name
    // is the table's own, misspelt: the error is then the header's).
    if let Some(rest) = msg.strip_prefix("unknown field ") {
        let key = rest.split('`').nth(1).unwrap_or("");
        if key.is_empty() || table.rsplit('.').next() == Some(key) {
            return (line, line_start, column);
        }
        return find_line(text, (line, line_start, column), |k, _| k.trim() == key);
    }
    if !(msg.starts_with("invalid type") || msg.starts_with("invalid value")) {
        return (line, line_start, column);
    }
    let needle = if let Some(i) = msg.find("string \"") {
        let rest = &msg[i + 7..];
        rest.find("\", expected").map(|j| rest[..=j].to_string())
    } else {
        msg.split('`').nth(1).map(str::to_string)
    };
    let Some(needle) = needle else {
        return (line, line_start, column);
    };
    find_line(text, (line, line_start, column), |_, value| {
        value.trim().starts_with(needle.as_str())
    })
}

/// The first `key = value` line of the table whose header is at `line` (starting at byte
/// `line_start`) for which `pick(key, value)` holds: its line, start and column; else the
/// header's `(line, line_start, column)`.
fn find_line(
    text: &str,
    (line, line_start, column): (usize, usize, usize),
    pick: impl Fn(&str, &str) -> bool,
) -> (usize, usize, usize) {
    let mut start = line_start;
    for (k, l) in text[line_start..].lines().enumerate() {
        if k > 0 && l.trim_start().starts_with('[') {
            break;
        }
        if let Some((key, value)) = l.split_once('=')
            && k > 0
            && pick(key, value)
        {
            let col = l.len() - l.trim_start().len() + 1;
            return (line + k, start, col);
        }
        start += l.len() + 1;
    }
    (line, line_start, column)
}

/// The line number of the first `[[shots.feed.shots]]` header of `text` whose table has
/// no `key = ...` line.
fn list_shot_without(text: &str, key: &str) -> Option<usize> {
    let mut open = None;
    for (k, l) in text.lines().enumerate() {
        if let Some(name) = table_name(l) {
            if open.is_some() {
                break;
            }
            if l.trim_start().starts_with("[[") && name == "shots.feed.shots" {
                open = Some(k + 1);
            }
        } else if open.is_some() && l.split_once('=').is_some_and(|(k, _)| k.trim() == key) {
            open = None;
        }
    }
    open
}

/// The table a header line (`[shots.feed]`, `[[shots.feed.shots]]`, a comment after it
/// or not) names; `None` for any other line.
fn table_name(line: &str) -> Option<&str> {
    let line = line.trim();
    if !line.starts_with('[') {
        return None;
    }
    let line = line.split_once('#').map_or(line, |(header, _)| header);
    Some(line.trim().trim_matches(|c| c == '[' || c == ']').trim())
}

fn key_on_line(text: &str, line_start: usize) -> String {
    let line = text[line_start..].lines().next().unwrap_or("");
    line.split('=').next().unwrap_or("").trim().to_string()
}
