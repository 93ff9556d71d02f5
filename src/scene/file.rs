//! `SceneFile`: the scene TOML as written, with per-field types and defaults only.
//! Every dimensional key carries its unit in its name (`_mm`, `_mpa`, `_k`, `_ms`,
//! `_m_s`, `_gpa`, `_kg_m3`); a key without a suffix is dimensionless. Omitted keys take
//! the paper's Table 2 values. Cross-field checks and SI conversion live in `validate.rs`.

use serde::Deserialize;
use std::collections::BTreeMap;

/// The whole scene file.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SceneFile {
    /// Free text shown in outputs.
    pub title: String,
    /// Seed of every random draw (placement, sizes, stream arrivals).
    pub seed: u64,
    /// Simulated time, ms (paper: 10).
    pub duration_ms: f64,
    /// Gravitational acceleration magnitude, m/s^2, acting along -z.
    pub gravity_m_s2: f64,
    /// Compressed-air supply.
    pub air: AirFile,
    /// Nozzle geometry.
    pub nozzle: NozzleFile,
    /// Jet model.
    pub jet: JetFile,
    /// Shots and how they are fed.
    pub shots: ShotsFile,
    /// Specimen (flat plane z = 0).
    pub specimen: SpecimenFile,
    /// Restitution coefficients per pair.
    pub restitution: RestitutionFile,
    /// Coulomb friction coefficients per pair (the `friction` effect).
    pub friction: FrictionFile,
    /// Integrator accuracy settings.
    pub integrator: IntegratorFile,
    /// Effects: `"auto"` or a table of `name = true | false | "auto"`.
    pub effects: Option<toml::Value>,
    /// User materials, by name (added to the built-in library).
    pub materials: BTreeMap<String, MaterialFile>,
    /// Region outside which shots are dropped.
    pub domain: DomainFile,
}

impl Default for SceneFile {
    fn default() -> Self {
        SceneFile {
            title: "peenflow scene".into(),
            seed: 1,
            duration_ms: 10.0,
            gravity_m_s2: 9.80665,
            air: AirFile::default(),
            nozzle: NozzleFile::default(),
            jet: JetFile::default(),
            shots: ShotsFile::default(),
            specimen: SpecimenFile::default(),
            restitution: RestitutionFile::default(),
            friction: FrictionFile::default(),
            integrator: IntegratorFile::default(),
            effects: None,
            materials: BTreeMap::new(),
            domain: DomainFile::default(),
        }
    }
}

/// `[air]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct AirFile {
    /// Compressor gauge pressure `P`, MPa (paper: 0.6).
    pub gauge_pressure_mpa: f64,
    /// Ambient (absolute) pressure `P_b`, MPa (paper: 0.1).
    pub ambient_pressure_mpa: f64,
    /// Supply (stagnation) temperature, K (paper: 293).
    pub temperature_k: f64,
    /// Ratio of specific heats (air: 1.4).
    pub kappa: f64,
    /// Specific gas constant, J/(kg K) (air: 287.05).
    pub gas_constant_j_kg_k: f64,
    /// Ambient density `rho_ab`, kg/m^3 (paper: 1.205).
    pub ambient_density_kg_m3: f64,
}

impl Default for AirFile {
    fn default() -> Self {
        AirFile {
            gauge_pressure_mpa: 0.6,
            ambient_pressure_mpa: 0.1,
            temperature_k: 293.0,
            kappa: 1.4,
            gas_constant_j_kg_k: 287.05,
            ambient_density_kg_m3: 1.205,
        }
    }
}

/// `[nozzle]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct NozzleFile {
    /// Bore diameter `d`, mm (paper: 6).
    pub bore_mm: f64,
    /// Bore (acceleration) length `l_n`, mm (paper: 40).
    pub length_mm: f64,
    /// Outer diameter of the nozzle body, mm: the tube's wall then has this thickness,
    /// and a flat annular face at each end. Left out: a thin-walled tube (the paper gives
    /// no outer diameter).
    pub outer_diameter_mm: Option<f64>,
    /// Stand-off `l` from the nozzle exit to the specimen, mm (paper: 100).
    pub standoff_mm: f64,
    /// Material of the bore wall (library name).
    pub material: String,
    /// Peening angle between the nozzle axis and the specimen surface, degrees (90:
    /// normal to the specimen).
    pub angle_deg: f64,
    /// Direction of the tilt in the specimen plane, degrees from +x (the nozzle leans
    /// away from that direction and shots travel towards it).
    pub azimuth_deg: f64,
}

impl Default for NozzleFile {
    fn default() -> Self {
        NozzleFile {
            bore_mm: 6.0,
            length_mm: 40.0,
            outer_diameter_mm: None,
            standoff_mm: 100.0,
            material: "table2-steel".into(),
            angle_deg: 90.0,
            azimuth_deg: 0.0,
        }
    }
}

/// Which density laws the jet uses.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum JetModelFile {
    /// The paper's Eqs 5 and 7 (Eq 5 capped at the lip).
    Paper,
    /// Bounded densities relaxing to ambient.
    Consistent,
}

/// Whether the shots slow the air down.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum CouplingFile {
    /// The paper's: the air is a prescribed field (default).
    #[default]
    OneWay,
    /// Beyond the paper: the jet slowed by the momentum the shots take from it.
    Momentum,
}

/// Density of the bore and potential core.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum CoreDensityFile {
    /// Exit (critical) density `rho*` (Eq 12; default).
    RhoStar,
    /// Stagnation density `rho_0` (Eq 4).
    #[serde(rename = "rho_0")]
    Rho0,
}

/// `[jet]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct JetFile {
    /// `"paper"` or `"consistent"`.
    pub model: JetModelFile,
    /// `"rho_star"` (default) or `"rho_0"`.
    pub core_density: CoreDensityFile,
    /// Cap of the Eq 5 mixing density in the paper model, kg/m^3 (default: `rho_0`).
    pub lip_density_cap_kg_m3: Option<f64>,
    /// Drag coefficient `C_D` (paper: 0.47).
    pub drag_coefficient: f64,
    /// Lift coefficient `C_L` (paper: 0.15).
    pub lift_coefficient: f64,
    /// Streamline divergence `tan(alpha)` (paper: 0.10).
    pub divergence_tan: f64,
    /// Turbulence intensity of the mixing layer and developed jet, a fraction of the
    /// local mean air speed (beyond the paper; 0: off). Drives `turbulent_dispersion`.
    pub turbulence_intensity: f64,
    /// Thickness of the stagnation layer above a flat specimen or round a bar, mm (beyond
    /// the paper; left out: the free jet runs on into the part, as the paper's).
    pub stagnation_layer_mm: Option<f64>,
    /// Whether the air the stagnation layer stops flows out along the plate (beyond the
    /// paper; only with `stagnation_layer_mm`, the plate and a jet normal to it).
    pub wall_jet: bool,
    /// `"one_way"` (the paper's, default) or `"momentum"` (beyond the paper: the jet
    /// slowed by what a stream's or a batch's shots take from it).
    pub coupling: CouplingFile,
}

impl Default for JetFile {
    fn default() -> Self {
        JetFile {
            model: JetModelFile::Paper,
            core_density: CoreDensityFile::RhoStar,
            lip_density_cap_kg_m3: None,
            drag_coefficient: 0.47,
            lift_coefficient: 0.15,
            divergence_tan: 0.1,
            turbulence_intensity: 0.0,
            stagnation_layer_mm: None,
            wall_jet: false,
            coupling: CouplingFile::OneWay,
        }
    }
}

/// `[shots]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ShotsFile {
    /// One diameter for every shot, mm (paper: 0.8). Exclusive with `size_distribution`.
    pub diameter_mm: Option<f64>,
    /// Diameters drawn from a distribution.
    pub size_distribution: Option<SizeDistributionFile>,
    /// Shot material (library name).
    pub material: String,
    /// How shots enter the run.
    pub feed: FeedFile,
}

impl Default for ShotsFile {
    fn default() -> Self {
        ShotsFile {
            diameter_mm: None,
            size_distribution: None,
            material: "table2-steel".into(),
            feed: FeedFile::default(),
        }
    }
}

/// `[shots.size_distribution]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum SizeDistributionFile {
    /// Normal distribution truncated to `[min_mm, max_mm]`.
    Normal {
        /// Mean, mm.
        mean_mm: f64,
        /// Standard deviation, mm.
        std_mm: f64,
        /// Smallest diameter, mm.
        min_mm: f64,
        /// Largest diameter, mm.
        max_mm: f64,
    },
    /// Uniform between two diameters.
    Uniform {
        /// Smallest diameter, mm.
        min_mm: f64,
        /// Largest diameter, mm.
        max_mm: f64,
    },
    /// A sieve analysis: a standard grade (`grade = "S330"`) or your supplier's sieve
    /// openings and the mass percent retained on each.
    Sieve {
        /// `"S230"` or `"S330"` (typical new shot within the SAE J444 limits).
        grade: Option<String>,
        /// Sieve openings, mm, descending: the first sieve passes everything, the last is
        /// the smallest size kept (the pan's lower bound).
        openings_mm: Option<Vec<f64>>,
        /// Mass percent retained between consecutive openings (one fewer than openings).
        retained_percent: Option<Vec<f64>>,
    },
    /// A sieve-style list of diameters with their number fractions.
    Discrete {
        /// Diameters, mm.
        diameters_mm: Vec<f64>,
        /// Relative weights (need not sum to 1).
        weights: Vec<f64>,
    },
}

/// `[shots.feed]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum FeedFile {
    /// `count` shots at rest near the inlet at random radial offsets and azimuths.
    Batch {
        /// Number of shots (paper: 30).
        count: u32,
        /// Range of the shot centres' distance from the axis, mm (paper: 1.5-3.0,
        /// which the bore wall limits to 3.0 - D/2).
        #[serde(default = "default_radial_offset")]
        radial_offset_mm: [f64; 2],
        /// Depth below the inlet plane over which centres are spread, mm.
        #[serde(default = "default_axial_spread")]
        axial_spread_mm: f64,
    },
    /// A continuous feed entering the bore at random positions in the inlet plane.
    Stream {
        /// Shots per second (exclusive with `mass_flow_kg_min`).
        rate_per_s: Option<f64>,
        /// Media mass flow, kg/min (exclusive with `rate_per_s`).
        mass_flow_kg_min: Option<f64>,
        /// How long shots are fed, ms (default: the whole run).
        duration_ms: Option<f64>,
        /// Axial speed of shots entering the bore, m/s.
        #[serde(default)]
        entry_speed_m_s: f64,
        /// `"poisson"` (random, default) or `"regular"` arrivals.
        #[serde(default = "default_arrivals")]
        arrivals: String,
    },
    /// `count` shots at random non-overlapping places in a box, all with one velocity
    /// (a "pack", as LIGGGHTS' insert/pack).
    Box {
        /// Number of shots.
        count: u32,
        /// Lower corner `[x, y, z]`, mm.
        min_mm: [f64; 3],
        /// Upper corner `[x, y, z]`, mm.
        max_mm: [f64; 3],
        /// Velocity of every shot, m/s.
        #[serde(default)]
        velocity_m_s: [f64; 3],
    },
    /// An FCC bed of `2 nx ny layers` shots at rest on the specimen, (001) layers parallel
    /// to it, nearest neighbours `D (1 - squeeze)` apart (as LIGGGHTS' dense.in).
    Bed {
        /// Conventional cells along x.
        nx: u32,
        /// Conventional cells along y.
        ny: u32,
        /// (001) layers.
        layers: u32,
        /// Relative pre-compression of the nearest-neighbour distance (0: touching).
        #[serde(default)]
        squeeze: f64,
    },
    /// Shots placed one by one.
    List {
        /// The shots.
        shots: Vec<ListShotFile>,
    },
}

fn default_radial_offset() -> [f64; 2] {
    [1.5, 2.6]
}
fn default_axial_spread() -> f64 {
    10.0
}
fn default_arrivals() -> String {
    "poisson".into()
}

impl Default for FeedFile {
    fn default() -> Self {
        FeedFile::Batch {
            count: 30,
            radial_offset_mm: default_radial_offset(),
            axial_spread_mm: default_axial_spread(),
        }
    }
}

/// One shot of a `list` feed.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ListShotFile {
    /// Centre `[x, y, z]`, mm (z: height above the specimen; the jet axis is x = y = 0).
    pub position_mm: [f64; 3],
    /// Initial velocity, m/s.
    #[serde(default)]
    pub velocity_m_s: [f64; 3],
    /// Diameter, mm (default: `shots.diameter_mm`).
    pub diameter_mm: Option<f64>,
    /// Time the shot enters the run, ms.
    #[serde(default)]
    pub start_ms: f64,
}

/// `[specimen]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SpecimenFile {
    /// Specimen material (library name). Table 2: steel E = 210 GPa.
    pub material: String,
    /// Surface: "plane" (the paper's flat plate, `z = 0`), "cylinder" (beyond the
    /// paper: a bar or a spring's wire, its crest line at `z = 0` through the origin),
    /// "groove" (beyond the paper: a slot, or a rack's tooth spaces, its bottom's middle
    /// line at `z = 0` through the origin) or "gear" (beyond the paper: a spur gear, the
    /// top of its root circle at `z = 0` through the origin).
    pub shape: String,
    /// Cylinder radius, or a groove's root fillet radius, mm.
    pub radius_mm: Option<f64>,
    /// Direction of the cylinder's or the groove's horizontal axis, degrees from +x
    /// (default 90: along y).
    pub axis_deg: Option<f64>,
    /// A groove's flat bottom width between its fillets, mm (default 0: a round bottom).
    pub bottom_mm: Option<f64>,
    /// A groove's flanks' lean from the vertical, degrees (default 0).
    pub flank_deg: Option<f64>,
    /// A groove's depth, bottom to lands, mm.
    pub depth_mm: Option<f64>,
    /// A groove's edge radius between flanks and lands, mm (default: `radius_mm`).
    pub edge_radius_mm: Option<f64>,
    /// Distance between neighbouring grooves, mm (a rack; default: one groove).
    pub pitch_mm: Option<f64>,
    /// Where the groove's middle lies across from the jet axis' foot, mm (default 0:
    /// the jet aims at the middle of the bottom); on a gear, the arc along its pitch
    /// circle it is turned by.
    pub offset_mm: Option<f64>,
    /// A gear's number of teeth.
    pub teeth: Option<i64>,
    /// A gear's module, mm.
    pub module_mm: Option<f64>,
    /// A gear's pressure angle, degrees (default 20).
    pub pressure_angle_deg: Option<f64>,
    /// A gear's addendum, pitch to tip circle, mm (default: the module).
    pub addendum_mm: Option<f64>,
    /// A gear's dedendum, root to pitch circle, mm (default: 1.25 modules).
    pub dedendum_mm: Option<f64>,
}

impl Default for SpecimenFile {
    fn default() -> Self {
        SpecimenFile {
            material: "table2-steel".into(),
            shape: "plane".into(),
            radius_mm: None,
            axis_deg: None,
            bottom_mm: None,
            flank_deg: None,
            depth_mm: None,
            edge_radius_mm: None,
            pitch_mm: None,
            offset_mm: None,
            teeth: None,
            module_mm: None,
            pressure_angle_deg: None,
            addendum_mm: None,
            dedendum_mm: None,
        }
    }
}

/// `[restitution]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RestitutionFile {
    /// Shot on specimen (paper: 0.70); `None`: 0.70, or the curve when one is given.
    pub shot_specimen: Option<f64>,
    /// Shot on specimen against the normal impact speed (beyond the paper).
    pub shot_specimen_curve: Option<RestitutionCurveFile>,
    /// Shot on shot (paper: 0.90).
    pub shot_shot: f64,
    /// Shot on the nozzle bore wall.
    pub shot_nozzle: f64,
}

impl Default for RestitutionFile {
    fn default() -> Self {
        RestitutionFile {
            shot_specimen: None,
            shot_specimen_curve: None,
            shot_shot: 0.9,
            shot_nozzle: 0.7,
        }
    }
}

/// `[restitution] shot_specimen_curve`: restitution at a few normal impact speeds.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RestitutionCurveFile {
    /// Normal impact speeds, m/s, increasing.
    pub speed_m_s: Vec<f64>,
    /// Restitution at each speed.
    pub restitution: Vec<f64>,
}

/// `[friction]`: Coulomb coefficients. All zero (the paper: frictionless contacts)
/// unless set; any coefficient above zero turns the `friction` effect on under "auto".
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct FrictionFile {
    /// Shot on specimen.
    pub shot_specimen: f64,
    /// Shot on shot.
    pub shot_shot: f64,
    /// Shot on the nozzle bore wall.
    pub shot_nozzle: f64,
    /// The tangential law: `"viscous"` (Coulomb with viscous stick, no history; the
    /// default) or `"history"` (tangential spring with history, as LIGGGHTS' `tangential
    /// history`; with `method = "hybrid"` or `"verlet"`).
    pub tangential: String,
}

impl Default for FrictionFile {
    fn default() -> Self {
        FrictionFile {
            shot_specimen: 0.0,
            shot_shot: 0.0,
            shot_nozzle: 0.0,
            tangential: "viscous".into(),
        }
    }
}

/// `[integrator]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct IntegratorFile {
    /// Relative error tolerance per step: the accuracy knob.
    pub tolerance: f64,
    /// Minimum steps per Hertz contact duration.
    pub contact_steps: f64,
    /// Largest step, ms.
    pub max_step_ms: f64,
    /// `"adaptive"` (error-controlled, default), `"verlet"` (fixed step, a baseline) or
    /// `"hybrid"` (adaptive in flight, the fixed step inside contacts).
    pub method: String,
    /// The fixed step of `method = "verlet"` and `"hybrid"`, ns.
    pub fixed_step_ns: Option<f64>,
    /// `"auto"` (default), `"windows"` or `"events"`: how shots are scheduled.
    pub scheduler: String,
}

impl Default for IntegratorFile {
    fn default() -> Self {
        IntegratorFile {
            tolerance: 1e-6,
            contact_steps: 10.0,
            max_step_ms: 0.5,
            method: "adaptive".into(),
            fixed_step_ns: None,
            scheduler: "auto".into(),
        }
    }
}

/// `[materials.NAME]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Young's modulus, GPa.
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Density, kg/m^3.
    pub density_kg_m3: f64,
    /// Yield strength, MPa (used by FE exports).
    pub yield_strength_mpa: Option<f64>,
}

/// `[domain]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct DomainFile {
    /// Shots farther than this from the vertical through the jet axis' foot are dropped,
    /// mm (default: 250, or more to take in a tilted nozzle's inlet with 50 mm to spare).
    pub radius_mm: Option<f64>,
    /// Shots higher than this above the nozzle inlet are dropped, mm.
    pub above_inlet_mm: f64,
}

impl Default for DomainFile {
    fn default() -> Self {
        DomainFile {
            radius_mm: None,
            above_inlet_mm: 50.0,
        }
    }
}
