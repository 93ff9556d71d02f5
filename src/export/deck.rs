//! FE initial-condition decks (Abaqus/Explicit `.inp`, LS-DYNA keyword `.k`, CalculiX
//! `.inp`) rendered from editable minijinja templates (`templates/*.j2`, or the user's
//! own with `--template`).
//!
//! The model ([`FeModel`], the template context) holds the selected shots as meshed
//! spheres (rigid by default) with their recorded velocity vectors, each set back along
//! its velocity so that it touches the target at its recorded time relative to the first
//! selected impact; a target block of the specimen material, meshed finer under the
//! impacts; and an explicit step long enough for the last impact and its rebound.
//! Meshes come from `crate::mesh`; units are SI or mm-tonne-s.

use crate::Vec3;
use crate::contact::groove::Groove;
use crate::contact::hertz;
use crate::contact::specimen::SpecimenShape;
use crate::mesh::{Face, Mesh, block, sphere};
use crate::record::Impact;
use crate::scene::Material;
use minijinja::{Environment, UndefinedBehavior, Value};
use serde::Serialize;
use thiserror::Error;

/// Deck formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeckFormat {
    /// Abaqus/Explicit input file.
    Abaqus,
    /// LS-DYNA keyword file.
    LsDyna,
    /// CalculiX (ccx) input file.
    Calculix,
}

impl DeckFormat {
    /// Built-in template.
    pub fn builtin_template(self) -> &'static str {
        match self {
            DeckFormat::Abaqus => include_str!("../../templates/abaqus.inp.j2"),
            DeckFormat::LsDyna => include_str!("../../templates/lsdyna.k.j2"),
            DeckFormat::Calculix => include_str!("../../templates/calculix.inp.j2"),
        }
    }

    /// Output file name.
    pub fn file_name(self) -> &'static str {
        match self {
            DeckFormat::Abaqus => "abaqus.inp",
            DeckFormat::LsDyna => "lsdyna.k",
            DeckFormat::Calculix => "calculix.inp",
        }
    }

    /// Name as given on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DeckFormat::Abaqus => "abaqus",
            DeckFormat::LsDyna => "lsdyna",
            DeckFormat::Calculix => "calculix",
        }
    }
}

/// Unit systems of the decks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitSystem {
    /// m, kg, s, N, Pa, J.
    Si,
    /// mm, tonne, s, N, MPa, mJ.
    MmTonneS,
}

/// Conversion factors from SI and unit labels.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Units {
    /// "si" or "mm-t-s".
    pub name: &'static str,
    /// Length label.
    pub length: &'static str,
    /// Mass label.
    pub mass: &'static str,
    /// Stress label.
    pub stress: &'static str,
    /// Energy label.
    pub energy: &'static str,
    /// Factor SI -> deck for lengths.
    pub length_factor: f64,
    /// ... masses.
    pub mass_factor: f64,
    /// ... velocities.
    pub velocity_factor: f64,
    /// ... densities.
    pub density_factor: f64,
    /// ... stresses and moduli.
    pub stress_factor: f64,
    /// ... energies.
    pub energy_factor: f64,
}

impl UnitSystem {
    /// Factors and labels.
    pub fn units(self) -> Units {
        match self {
            UnitSystem::Si => Units {
                name: "si",
                length: "m",
                mass: "kg",
                stress: "Pa",
                energy: "J",
                length_factor: 1.0,
                mass_factor: 1.0,
                velocity_factor: 1.0,
                density_factor: 1.0,
                stress_factor: 1.0,
                energy_factor: 1.0,
            },
            UnitSystem::MmTonneS => Units {
                name: "mm-t-s",
                length: "mm",
                mass: "tonne",
                stress: "MPa",
                energy: "mJ",
                length_factor: 1e3,
                mass_factor: 1e-3,
                velocity_factor: 1e3,
                density_factor: 1e-12,
                stress_factor: 1e-6,
                energy_factor: 1e3,
            },
        }
    }
}

/// Deck errors.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum DeckError {
    /// Nothing selected.
    #[error("the selection is empty: {available} impacts in the file, none with {selection}")]
    EmptySelection {
        /// Impacts available.
        available: usize,
        /// The selection.
        selection: String,
    },
    /// The file holds no impacts at all.
    #[error(
        "the file holds no impacts: the run recorded none (no shot reached the specimen in its duration); nothing to export"
    )]
    NoImpacts,
    /// The target material cannot be meshed as elastic-plastic.
    #[error(
        "target material \"{0}\" has no yield strength: pass --target-material A5052 (or another library material with one) or add yield_strength_mpa to [materials.{0}]"
    )]
    NoYield(String),
    /// The target block under the selected impacts would be too large to be useful.
    #[error(
        "{impacts} impacts spread over {width_mm:.1} x {length_mm:.1} mm need a target block of {elements} elements at {element_size_mm} mm; allowed at most {limit}: select fewer or closer impacts (--window, --time-window, --first, --sample) or pass a larger --element-size-mm"
    )]
    TooLarge {
        /// Impacts selected.
        impacts: usize,
        /// Extent of the impacts along x, mm.
        width_mm: f64,
        /// Extent along y, mm.
        length_mm: f64,
        /// Elements the block would have.
        elements: u64,
        /// Element size under the impacts, mm.
        element_size_mm: f64,
        /// [`MAX_TARGET_ELEMENTS`].
        limit: u64,
    },
    /// The target block cannot be bent around the cylindrical specimen.
    #[error("{0}")]
    Bend(String),
    /// The template failed.
    #[error("{template}: {message}")]
    Template {
        /// Template name or file.
        template: String,
        /// What is wrong (line and variable).
        message: String,
    },
}

/// How to build the model.
#[derive(Debug, Clone)]
pub struct DeckSettings {
    /// Unit system.
    pub units: UnitSystem,
    /// Rigid (default) or elastic shots.
    pub rigid_shots: bool,
    /// Cells along each edge of a shot's cube grid (default: 6).
    pub shot_cells: usize,
    /// Element size in the refined zones of the target, m (default: shot radius / 4).
    pub element_size: Option<f64>,
    /// Shot material.
    pub shot_material: Material,
    /// Target material (needs a yield strength).
    pub target_material: Material,
    /// Where the impacts came from (for the deck header).
    pub source: String,
    /// Selection description (for the deck header).
    pub selection: String,
    /// The specimen's surface: on a cylinder the target block is bent around it.
    pub shape: SpecimenShape,
}

/// A node for the templates.
#[derive(Debug, Clone, Serialize)]
pub struct NodeCtx {
    /// Id.
    pub id: u32,
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// An element for the templates.
#[derive(Debug, Clone, Serialize)]
pub struct ElementCtx {
    /// Id.
    pub id: u32,
    /// Node ids.
    pub nodes: [u32; 8],
}

/// A material for the templates (deck units).
#[derive(Debug, Clone, Serialize)]
pub struct MaterialCtx {
    /// Name (upper case, deck-safe).
    pub name: String,
    /// Young's modulus.
    pub youngs_modulus: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Density (for shots: scaled so the meshed ball has the real shot's mass).
    pub density: f64,
    /// Yield strength (targets).
    pub yield_strength: f64,
    /// Linear hardening modulus `H` (targets): `sigma = sigma_y + H eps_p`.
    pub hardening_modulus: f64,
    /// Plastic table rows `[stress, plastic strain]` (targets).
    pub plastic: Vec<[f64; 2]>,
}

/// One shot of the deck.
#[derive(Debug, Clone, Serialize)]
pub struct ShotCtx {
    /// 1-based index in the deck.
    pub n: usize,
    /// Part/set name stem, e.g. `SHOT1`.
    pub name: String,
    /// Part id (LS-DYNA): target is 1, shots 2, 3, ...
    pub part_id: usize,
    /// Element ids.
    pub elements: Vec<ElementCtx>,
    /// First and last element id.
    pub element_range: [u32; 2],
    /// Node ids of the shot mesh.
    pub nodes: Vec<u32>,
    /// First and last node id.
    pub node_range: [u32; 2],
    /// Outer faces.
    pub surface: Vec<Face>,
    /// Reference node at the centre: the rigid body's, or the elastic ball's centre node
    /// (even `shot_cells`; the node nearest the centre otherwise).
    pub ref_node: u32,
    /// Rigid-body rotation node (CalculiX; 0 for elastic shots).
    pub rot_node: u32,
    /// Centre at the start of the step.
    pub start: [f64; 3],
    /// Centre at first contact.
    pub contact_centre: [f64; 3],
    /// Velocity vector.
    pub velocity: [f64; 3],
    /// Angular velocity vector (spin, with friction on), rad per time unit (s in both
    /// unit systems); zero without friction.
    pub omega: [f64; 3],
    /// Spin rate `|omega|`; 0: the shot does not spin and its velocity is one vector.
    pub spin: f64,
    /// Unit vector along `omega` (zero when it does not spin).
    pub spin_axis: [f64; 3],
    /// A spinning shot's rigid-body velocity `v + omega x (x - centre)` at each of its
    /// nodes (and the reference node), for decks that set velocities node by node;
    /// empty when it does not spin.
    pub node_velocities: Vec<NodeVelocity>,
    /// Rotational kinetic energy `I omega^2 / 2`, `I = 2 m r^2 / 5`.
    pub spin_energy: f64,
    /// Speed.
    pub speed: f64,
    /// Normal speed into the target.
    pub normal_speed: f64,
    /// First-contact time after the step starts.
    pub contact_time: f64,
    /// Diameter.
    pub diameter: f64,
    /// Mass of the sphere.
    pub mass: f64,
    /// Kinetic energy `m v^2/2`.
    pub kinetic_energy: f64,
    /// The impact record's shot id in the run.
    pub source_shot: u32,
    /// The impact record's time in the run, s.
    pub source_time_s: f64,
}

/// One node's initial velocity.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct NodeVelocity {
    /// Node id.
    pub node: u32,
    /// Velocity vector.
    pub velocity: [f64; 3],
}

/// The target block.
#[derive(Debug, Clone, Serialize)]
pub struct TargetCtx {
    /// Elements.
    pub elements: Vec<ElementCtx>,
    /// First and last element id.
    pub element_range: [u32; 2],
    /// First and last node id.
    pub node_range: [u32; 2],
    /// Bottom nodes (fixed).
    pub bottom: Vec<u32>,
    /// Side nodes.
    pub sides: Vec<u32>,
    /// Top surface faces.
    pub top: Vec<Face>,
    /// Top faces within 2 shot radii (laterally) of an impact point: the contact
    /// master surface (contact search cost grows with it).
    pub contact_top: Vec<Face>,
    /// Elements within 1.5 shot radii (laterally) and 1 radius (deep) of an impact
    /// point: where plastic strain is printed.
    pub impact_zone: Vec<u32>,
    /// Extent `[x0, x1, y0, y1, z0, z1]`.
    pub extent: [f64; 6],
    /// Finest element size.
    pub element_size: f64,
}

/// Step settings.
#[derive(Debug, Clone, Serialize)]
pub struct StepCtx {
    /// Step duration.
    pub duration: f64,
    /// Estimated stable explicit increment.
    pub increment: f64,
    /// Output interval.
    pub output_interval: f64,
    /// Output frequency in increments (CalculiX).
    pub output_every: u64,
    /// Maximum increments allowed.
    pub max_increments: u64,
}

/// The template context: everything a deck needs, in deck units.
#[derive(Debug, Clone, Serialize)]
pub struct FeModel {
    /// Title.
    pub title: String,
    /// "peenflow X.Y.Z".
    pub generator: String,
    /// Impact file.
    pub source: String,
    /// Selection description.
    pub selection: String,
    /// Units.
    pub units: Units,
    /// Specimen coordinates (deck length unit) of the model origin (on a cylinder: on
    /// its unrolled surface, the arc length around it and the distance along its axis).
    pub origin: [f64; 2],
    /// The target's geometry in model coordinates, for the deck's header (on a
    /// cylinder, the origin's coordinates are on its unrolled surface).
    pub geometry: String,
    /// All nodes.
    pub nodes: Vec<NodeCtx>,
    /// Target.
    pub target: TargetCtx,
    /// Shots in impact order.
    pub shots: Vec<ShotCtx>,
    /// Whether shots are rigid.
    pub rigid_shots: bool,
    /// Shot material.
    pub shot_material: MaterialCtx,
    /// Target material.
    pub target_material: MaterialCtx,
    /// Contact penalty stiffness (stress per length).
    pub contact_penalty: f64,
    /// Explicit step.
    pub step: StepCtx,
    /// Total initial kinetic energy of the shots.
    pub kinetic_energy: f64,
    /// The mesh (deck units) for custom templates.
    pub mesh: Mesh,
}

fn deck_name(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect()
}

/// Largest target block a deck is built with: an explicit impact analysis of a few
/// shots runs on tens to hundreds of thousands of elements; millions mean the selection
/// spans far more of the specimen than one FE model should (building and writing such a
/// deck alone would take minutes).
pub const MAX_TARGET_ELEMENTS: u64 = 2_000_000;

/// Builds the model of `impacts` (already selected, time-ordered, non-empty).
pub fn build(impacts: &[Impact], s: &DeckSettings) -> Result<FeModel, DeckError> {
    let u = s.units.units();
    let yield_strength = s
        .target_material
        .yield_strength
        .ok_or_else(|| DeckError::NoYield(s.target_material.name.clone()))?;
    let r_max = impacts
        .iter()
        .map(|i| 0.5 * i.diameter_m)
        .fold(0.0, f64::max);
    let h = s.element_size.unwrap_or(r_max / 4.0);
    // Where the impacts sit on the specimen's surface: on the plane (x, y); on a
    // cylinder its unrolled surface, where the target block is laid out before it is
    // bent around the bar (`Bend`).
    let at: Vec<(f64, f64)> = impacts
        .iter()
        .map(|i| s.shape.unrolled(&Vec3::new(i.x_m, i.y_m, i.z_m)))
        .collect();
    // Model origin: centre of the impacts' bounding box.
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in &at {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (ox, oy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    // Target block: refined zones (one radius) around every impact, growing by 1.5 per
    // element outside them; margins and depth 2.5 radii. Measured with ccx: the
    // rebound and energy balance barely move with larger blocks, the run time does.
    let zone = r_max;
    let margin = 2.5 * r_max;
    let xz: Vec<(f64, f64)> = at
        .iter()
        .map(|&(x, _)| (x - ox - zone, x - ox + zone))
        .collect();
    let yz: Vec<(f64, f64)> = at
        .iter()
        .map(|&(_, y)| (y - oy - zone, y - oy + zone))
        .collect();
    let xs = block::graded_axis(x0 - ox - margin, x1 - ox + margin, &xz, h, 1.5, r_max);
    let ys = block::graded_axis(y0 - oy - margin, y1 - oy + margin, &yz, h, 1.5, r_max);
    let depth = 2.5 * r_max;
    let zs = block::graded_axis(-depth, 0.0, &[(-r_max, 0.0)], h, 1.5, r_max);
    let elements = [&xs, &ys, &zs]
        .iter()
        .map(|a| a.len().saturating_sub(1) as u64)
        .product::<u64>();
    if elements > MAX_TARGET_ELEMENTS {
        return Err(DeckError::TooLarge {
            impacts: impacts.len(),
            width_mm: (x1 - x0) * 1e3,
            length_mm: (y1 - y0) * 1e3,
            elements,
            element_size_mm: h * 1e3,
            limit: MAX_TARGET_ELEMENTS,
        });
    }
    let bend = Bend::new(&s.shape, ox, oy, xs[0], xs[xs.len() - 1], depth)?;
    let mut mesh = block::graded_block(&xs, &ys, &zs);
    // The impact zones are chosen on the flat block (on the unrolled surface), before
    // it is bent.
    let centroid = |m: &Mesh, id: u32| {
        let e = &m.elements[(id - 1) as usize];
        e.nodes.iter().fold([0.0; 3], |acc, &n| {
            let p = m.nodes[(n - 1) as usize];
            [
                acc[0] + p[0] / 8.0,
                acc[1] + p[1] / 8.0,
                acc[2] + p[2] / 8.0,
            ]
        })
    };
    let near = |c: [f64; 3], d: f64| {
        at.iter()
            .any(|&(x, y)| ((c[0] + ox - x).powi(2) + (c[1] + oy - y).powi(2)).sqrt() < d)
    };
    let n_target_elements = mesh.elements.len() as u32;
    let impact_zone: Vec<u32> = (1..=n_target_elements)
        .filter(|&id| {
            let c = centroid(&mesh, id);
            c[2] > -r_max && near(c, 1.5 * r_max)
        })
        .collect();
    let contact_top: Vec<Face> = mesh.surfaces["TOP"]
        .iter()
        .filter(|f| near(centroid(&mesh, f.element), 2.0 * r_max))
        .copied()
        .collect();
    if let Some(b) = &bend {
        for p in &mut mesh.nodes {
            *p = b.node(*p);
        }
    }
    let n_target_nodes = mesh.nodes.len() as u32;

    // Timing: the first shot starts a small clearance above its contact point.
    let t_first = impacts[0].time_s;
    let first_vn = impacts[0].normal_speed_m_s.max(1e-6);
    let clearance = 0.05 * r_max;
    let t0 = t_first - clearance / first_vn;
    if !s.shape.is_plane() {
        let block = (
            (ox + xs[0], ox + xs[xs.len() - 1]),
            (oy + ys[0], oy + ys[ys.len() - 1]),
        );
        for (k, i) in impacts.iter().enumerate() {
            straight_path_clear(&s.shape, i, i.time_s - t0, block).map_err(|what| {
                DeckError::Bend(format!(
                    "impact {} (shot {} at {:.4} ms) would fly through the part: the deck flies \
                     each shot straight to its contact from the model's start ({:.4} ms), and \
                     this one's path back crosses {what} under the target block (it came off \
                     another face). Select a shorter time (--time-window), first hits only \
                     (--first-hits-only) or a smaller --window",
                    k + 1,
                    i.shot,
                    i.time_s * 1e3,
                    t0 * 1e3
                ))
            })?;
        }
    }
    let mut shots = Vec::new();
    let rho_s = s.shot_material.density;
    for (k, i) in impacts.iter().enumerate() {
        let r = 0.5 * i.diameter_m;
        let centre = [i.center_x_m, i.center_y_m, i.center_z_m];
        let (v, contact, omega) = match &bend {
            None => (
                [i.vx_m_s, i.vy_m_s, i.vz_m_s],
                [centre[0] - ox, centre[1] - oy, centre[2]],
                [i.omega_x_rad_s, i.omega_y_rad_s, i.omega_z_rad_s],
            ),
            Some(b) => (
                b.turn([i.vx_m_s, i.vy_m_s, i.vz_m_s]),
                b.point(centre),
                b.turn([i.omega_x_rad_s, i.omega_y_rad_s, i.omega_z_rad_s]),
            ),
        };
        let dt = i.time_s - t0;
        let start = [
            contact[0] - v[0] * dt,
            contact[1] - v[1] * dt,
            contact[2] - v[2] * dt,
        ];
        let mut ball = sphere::hex_sphere(start, r, s.shot_cells);
        if let Some(b) = &bend {
            // The ball's lowest face centre where it touches the bar (as on the plate,
            // where it touches below the centre): a faceted ball touching off a face
            // centre is pushed sideways (measured with ccx: up to a fifth of the
            // rebound).
            b.face_down(&mut ball.nodes, start, contact);
        }
        let name = format!("SHOT{}", k + 1);
        let (dn, de) = mesh.append(&ball, &format!("{name}_"));
        // Rigid shots get a reference and a rotation node at the centre (free nodes that
        // *RIGID BODY ties to the ball); elastic shots use the ball's own centre node (a
        // massless free node makes an explicit solver divide by zero: ccx segfaults).
        let (ref_node, rot_node) = if s.rigid_shots {
            (mesh.add_node(start), mesh.add_node(start))
        } else {
            let np = s.shot_cells + 1;
            let c = s.shot_cells / 2;
            (dn + 1 + (c + np * (c + np * c)) as u32, 0)
        };
        let mass = rho_s * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let speed = i.speed_m_s;
        let spin = omega.iter().map(|w| w * w).sum::<f64>().sqrt();
        let node_velocities = if spin > 0.0 {
            let rigid = |x: [f64; 3]| {
                let d = [x[0] - start[0], x[1] - start[1], x[2] - start[2]];
                let w = omega;
                [
                    v[0] + w[1] * d[2] - w[2] * d[1],
                    v[1] + w[2] * d[0] - w[0] * d[2],
                    v[2] + w[0] * d[1] - w[1] * d[0],
                ]
                .map(|c| c * u.velocity_factor)
            };
            (dn + 1..=dn + ball.nodes.len() as u32)
                .chain(std::iter::once(ref_node).filter(|&n| n > dn + ball.nodes.len() as u32))
                .map(|n| NodeVelocity {
                    node: n,
                    velocity: rigid(mesh.nodes[(n - 1) as usize]),
                })
                .collect()
        } else {
            Vec::new()
        };
        shots.push(ShotCtx {
            n: k + 1,
            name,
            part_id: k + 2,
            elements: Vec::new(),
            element_range: [de + 1, de + ball.elements.len() as u32],
            nodes: (dn + 1..=dn + ball.nodes.len() as u32).collect(),
            node_range: [dn + 1, dn + ball.nodes.len() as u32],
            surface: ball.surfaces["SURFACE"]
                .iter()
                .map(|f| Face {
                    element: f.element + de,
                    face: f.face,
                })
                .collect(),
            ref_node,
            rot_node,
            start: start.map(|c| c * u.length_factor),
            contact_centre: contact.map(|c| c * u.length_factor),
            velocity: v.map(|c| c * u.velocity_factor),
            omega,
            spin,
            spin_axis: if spin > 0.0 {
                omega.map(|w| w / spin)
            } else {
                [0.0; 3]
            },
            node_velocities,
            spin_energy: 0.2 * mass * r * r * spin * spin * u.energy_factor,
            speed: speed * u.velocity_factor,
            normal_speed: i.normal_speed_m_s * u.velocity_factor,
            contact_time: dt,
            diameter: i.diameter_m * u.length_factor,
            mass: mass * u.mass_factor,
            kinetic_energy: 0.5 * mass * speed * speed * u.energy_factor,
            source_shot: i.shot,
            source_time_s: i.time_s,
        });
    }
    let scaled = mesh.scaled(u.length_factor);
    let elements_of = |lo: u32, hi: u32| -> Vec<ElementCtx> {
        (lo..=hi)
            .map(|id| ElementCtx {
                id,
                nodes: scaled.elements[(id - 1) as usize].nodes,
            })
            .collect()
    };
    for sh in &mut shots {
        sh.elements = elements_of(sh.element_range[0], sh.element_range[1]);
    }

    // Materials.
    let tm = &s.target_material;
    let hardening = 0.005 * tm.youngs_modulus;
    let target_material = MaterialCtx {
        name: deck_name(&tm.name),
        youngs_modulus: tm.youngs_modulus * u.stress_factor,
        poisson_ratio: tm.poisson_ratio,
        density: tm.density * u.density_factor,
        yield_strength: yield_strength * u.stress_factor,
        hardening_modulus: hardening * u.stress_factor,
        plastic: vec![
            [yield_strength * u.stress_factor, 0.0],
            [(yield_strength + hardening * 0.5) * u.stress_factor, 0.5],
        ],
    };
    let sm = &s.shot_material;
    // Straight-edged hexes under-fill the ball: scale the density so each meshed shot
    // has the real shot's mass (and kinetic energy).
    let unit_ball = sphere::hex_sphere([0.0; 3], 1.0, s.shot_cells).volume(None);
    let fill = 4.0 / 3.0 * std::f64::consts::PI / unit_ball;
    let shot_material = MaterialCtx {
        name: deck_name(&sm.name),
        youngs_modulus: sm.youngs_modulus * u.stress_factor,
        poisson_ratio: sm.poisson_ratio,
        density: sm.density * fill * u.density_factor,
        yield_strength: sm.yield_strength.unwrap_or(0.0) * u.stress_factor,
        hardening_modulus: 0.0,
        plastic: Vec::new(),
    };

    // Step: the last impact plus 2.5 elastic Hertz contact times (measured with ccx: an
    // elastic-plastic contact at 70 m/s lasts about 1.5 of them).
    let last = impacts.last().expect("BUG: non-empty selection");
    let m_last = rho_s * std::f64::consts::PI / 6.0 * last.diameter_m.powi(3);
    let law = hertz::HertzLaw::new(
        sm.youngs_modulus,
        sm.poisson_ratio,
        tm.youngs_modulus,
        tm.poisson_ratio,
        1.0,
    );
    let k = law.stiffness(0.5 * last.diameter_m);
    let tc = hertz::contact_time(m_last, k, last.normal_speed_m_s.max(1.0));
    let duration = (last.time_s - t0) + 2.5 * tc;
    // Stable increment: smallest element over the fastest dilatational wave speed.
    let c_target = (tm.youngs_modulus / tm.density).sqrt();
    let c_shot = (sm.youngs_modulus / sm.density).sqrt();
    let h_shot = 2.0 * r_max / s.shot_cells as f64 * 0.5;
    let increment = 0.5
        * (h / c_target).min(if s.rigid_shots {
            f64::INFINITY
        } else {
            h_shot / c_shot
        });
    let output_interval = duration / 50.0;
    let step = StepCtx {
        duration,
        increment,
        output_interval,
        output_every: ((output_interval / increment).ceil() as u64).max(1),
        max_increments: ((duration / increment) * 20.0).ceil() as u64 + 1000,
    };
    // Penalty stiffness E/h of the target: measured with ccx on a 70 m/s impact, 10 E/h
    // gains up to 5 % energy, E/h keeps the balance within 0.2 %.
    let contact_penalty = tm.youngs_modulus / h * u.stress_factor / u.length_factor;
    let kinetic_energy = shots.iter().map(|s| s.kinetic_energy).sum();
    Ok(FeModel {
        title: format!("peenflow impacts: {} shot(s)", shots.len()),
        generator: format!("peenflow {}", env!("CARGO_PKG_VERSION")),
        source: s.source.clone(),
        selection: s.selection.clone(),
        origin: [ox * u.length_factor, oy * u.length_factor],
        geometry: match &bend {
            None => "specimen surface at z = 0; target below it".into(),
            Some(b) => b.geometry(u.length_factor),
        },
        nodes: scaled
            .nodes
            .iter()
            .enumerate()
            .map(|(k, p)| NodeCtx {
                id: k as u32 + 1,
                x: p[0],
                y: p[1],
                z: p[2],
            })
            .collect(),
        target: TargetCtx {
            elements: elements_of(1, n_target_elements),
            element_range: [1, n_target_elements],
            node_range: [1, n_target_nodes],
            bottom: scaled.node_sets["BOTTOM"].clone(),
            sides: scaled.node_sets["SIDES"].clone(),
            top: scaled.surfaces["TOP"].clone(),
            contact_top,
            impact_zone,
            extent: [
                xs[0] * u.length_factor,
                xs[xs.len() - 1] * u.length_factor,
                ys[0] * u.length_factor,
                ys[ys.len() - 1] * u.length_factor,
                -depth * u.length_factor,
                0.0,
            ],
            element_size: h * u.length_factor,
        },
        shots,
        rigid_shots: s.rigid_shots,
        shot_material,
        target_material,
        contact_penalty,
        step,
        kinetic_energy,
        units: u,
        mesh: scaled,
    })
}

/// Formats `x` in at most `width` characters with as many significant digits as fit.
pub fn fit(x: f64, width: usize) -> Option<String> {
    if x == 0.0 {
        return Some("0.0".into());
    }
    for prec in (0..=15).rev() {
        let e = format!("{x:.prec$e}");
        let (mant, exp) = e.split_once('e').expect("BUG: exponent format");
        let mant = if mant.contains('.') {
            mant.trim_end_matches('0').trim_end_matches('.')
        } else {
            mant
        };
        let mant = if mant.contains('.') {
            mant.to_string()
        } else {
            format!("{mant}.")
        };
        let exp: i32 = exp.parse().expect("BUG: exponent");
        let sci = format!("{mant}e{exp}");
        // Plain decimal when it is shorter and exact to the same digits.
        let plain = if (-4..15).contains(&exp) {
            let digits = (prec as i32 - exp).max(1) as usize;
            let p = format!("{x:.digits$}");
            let p = if p.contains('.') {
                p.trim_end_matches('0').to_string()
            } else {
                p
            };
            Some(p)
        } else {
            None
        };
        // Plain decimals read best; exponents only when the plain form does not fit.
        if let Some(p) = plain
            && p.len() <= width
        {
            return Some(p);
        }
        if sci.len() <= width {
            return Some(sci);
        }
    }
    None
}

/// Number in the shortest round-trip form, with a decimal point (free-format decks):
/// plain for magnitudes in [1e-4, 1e15), else with an exponent.
pub fn num(x: f64) -> String {
    let a = x.abs();
    let s = if x == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    };
    if s.contains('.') || s.contains("inf") || s.contains("NaN") {
        s
    } else if let Some((m, e)) = s.split_once('e') {
        format!("{m}.e{e}")
    } else {
        format!("{s}.")
    }
}

/// Number with at most 12 significant digits (at most 19 characters): CalculiX rejects
/// longer number fields; 12 digits are far beyond any FE input's accuracy.
pub fn g12(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return num(x);
    }
    let e = format!("{x:.11e}");
    let v: f64 = e.parse().expect("BUG: formatted number parses");
    num(v)
}

/// Renders `model` with `template` (its text; `name` for messages). Undefined variables
/// are errors.
pub fn render(model: &FeModel, name: &str, template: &str) -> Result<String, DeckError> {
    let mut env = Environment::new();
    env.set_undefined_behavior(UndefinedBehavior::Strict);
    env.set_syntax(
        minijinja::syntax::SyntaxConfig::builder()
            .keep_trailing_newline(true)
            .build()
            .expect("BUG: syntax config"),
    );
    env.add_filter("num", |x: f64| num(x));
    env.add_filter("g", |x: f64| g12(x));
    let fixed = |w: usize| {
        move |v: Value| -> Result<String, minijinja::Error> {
            let s = if let Some(i) = v.as_i64() {
                i.to_string()
            } else {
                let x = f64::try_from(v.clone()).map_err(|_| {
                    minijinja::Error::new(
                        minijinja::ErrorKind::InvalidOperation,
                        format!("not a number: {v}"),
                    )
                })?;
                fit(x, w).ok_or_else(|| {
                    minijinja::Error::new(
                        minijinja::ErrorKind::InvalidOperation,
                        format!("{x} does not fit {w} columns"),
                    )
                })?
            };
            if s.len() > w {
                return Err(minijinja::Error::new(
                    minijinja::ErrorKind::InvalidOperation,
                    format!("{s} does not fit {w} columns"),
                ));
            }
            Ok(format!("{s:>w$}"))
        }
    };
    env.add_filter("w6", fixed(6));
    env.add_filter("w8", fixed(8));
    env.add_filter("w9", fixed(9));
    env.add_filter("w15", fixed(15));
    env.add_filter("w11", fixed(11));
    env.add_filter("w14", fixed(14));
    env.add_filter("w10", fixed(10));
    env.add_filter("w16", fixed(16));
    env.add_filter("w20", fixed(20));
    let err = |e: minijinja::Error| {
        let mut message = e.to_string().replace('\n', " ");
        if let Some(line) = e.line() {
            message = format!("line {line}: {message}");
        }
        DeckError::Template {
            template: name.to_string(),
            message,
        }
    };
    env.add_template_owned(name.to_string(), template.to_string())
        .map_err(err)?;
    let tmpl = env.get_template(name).map_err(err)?;
    tmpl.render(Value::from(minijinja::value::Serde(model)))
        .map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_respects_width_and_keeps_digits() {
        assert_eq!(fit(7.85e-9, 8).unwrap(), "7.85e-9");
        assert_eq!(fit(0.3, 8).unwrap(), "0.3");
        assert_eq!(fit(-0.123456789, 16).unwrap(), "-0.123456789");
        assert_eq!(fit(210000.0, 10).unwrap(), "210000.");
        assert!(fit(1.0 / 3.0, 8).unwrap().len() <= 8);
        let s = fit(-1.234567890123e-5, 16).unwrap();
        assert!(
            s.len() <= 16 && (s.parse::<f64>().unwrap() + 1.234567890123e-5).abs() < 1e-15,
            "{s}"
        );
    }

    #[test]
    fn g12_is_short_and_close() {
        for x in [
            9.762470596521017e-9,
            1.0 / 3.0,
            -123456.789012345,
            70000.60035375765,
        ] {
            let s = g12(x);
            assert!(s.len() <= 19, "{s}");
            assert!(((s.parse::<f64>().unwrap() - x) / x).abs() < 1e-11, "{s}");
        }
    }

    #[test]
    fn num_round_trips() {
        for x in [7.85e-9, 70.0, -0.5, 1e20, 123.456] {
            let s = num(x);
            assert!(s.contains('.'), "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), x);
        }
    }
}

/// Whether impact `i`'s shot, flown straight back from its contact for `back` seconds
/// (where the deck starts it), stays clear of the specimen's surface wherever that lies
/// under the target block (`block`: its extent on the unrolled surface, m); `Err` names
/// the zone it crosses. Sphere-traced on the surface's exact distance, so no face thinner
/// than a step is jumped.
fn straight_path_clear(
    shape: &SpecimenShape,
    i: &Impact,
    back: f64,
    block: ((f64, f64), (f64, f64)),
) -> Result<(), String> {
    let r = 0.5 * i.diameter_m;
    let c = Vec3::new(i.center_x_m, i.center_y_m, i.center_z_m);
    let v = Vec3::new(i.vx_m_s, i.vy_m_s, i.vz_m_s);
    let speed = v.norm();
    if speed <= 0.0 || back <= 0.0 {
        return Ok(());
    }
    let ((u0, u1), (w0, w1)) = block;
    let mut t = 1e-3 * r / speed;
    loop {
        let t_at = t.min(back);
        let p = c - v * t_at;
        let d = shape.distance(&p);
        if d < r * (1.0 - 1e-6) {
            let foot = p - shape.normal(&p) * d;
            let (u, w) = shape.unrolled(&foot);
            if (u0 - r..=u1 + r).contains(&u) && (w0 - r..=w1 + r).contains(&w) {
                return Err(match shape {
                    SpecimenShape::Groove(g) => format!(
                        "the {}'s {}",
                        if g.gear().is_some() { "gear" } else { "groove" },
                        g.zone(&p).name()
                    ),
                    _ => "the bar".into(),
                });
            }
            t += 0.1 * r / speed;
        } else {
            t += (d - r).max(0.02 * r) / speed;
        }
        if t_at >= back {
            return Ok(());
        }
    }
}

/// Turns a ball's `nodes` about its `centre` in the model's x-z plane (about the y axis)
/// by `phi` (rad), so that its `-z` points along `-(sin phi, 0, cos phi)`.
fn tilt_ball(nodes: &mut [[f64; 3]], centre: [f64; 3], phi: f64) {
    let (c, s) = (phi.cos(), phi.sin());
    for p in nodes {
        let d = [p[0] - centre[0], p[2] - centre[2]];
        p[0] = centre[0] + d[0] * c + d[1] * s;
        p[2] = centre[2] - d[0] * s + d[1] * c;
    }
}

/// How the flat target block (laid out on the specimen's unrolled surface) becomes the
/// specimen's: bent around a bar ([`BarBend`]) or laid into a groove ([`GrooveLay`]).
#[derive(Debug, Clone)]
enum Bend {
    Bar(BarBend),
    Groove(Box<GrooveLay>),
}

impl Bend {
    /// `None` on the plane (the block stays flat); see [`BarBend::new`] and
    /// [`GrooveLay::new`] for what each refuses.
    fn new(
        shape: &SpecimenShape,
        u0: f64,
        v0: f64,
        u_lo: f64,
        u_hi: f64,
        depth: f64,
    ) -> Result<Option<Bend>, DeckError> {
        Ok(match shape {
            SpecimenShape::Plane => None,
            SpecimenShape::Cylinder { radius, axis } => Some(Bend::Bar(BarBend::new(
                *radius, *axis, u0, v0, u_lo, u_hi, depth,
            )?)),
            SpecimenShape::Groove(g) => Some(Bend::Groove(Box::new(GrooveLay::new(
                g, u0, v0, u_lo, u_hi, depth,
            )?))),
        })
    }

    fn node(&self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Bend::Bar(b) => b.node(p),
            Bend::Groove(g) => g.node(p),
        }
    }

    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Bend::Bar(b) => b.point(p),
            Bend::Groove(g) => g.point(p),
        }
    }

    fn face_down(&self, nodes: &mut [[f64; 3]], centre: [f64; 3], contact: [f64; 3]) {
        match self {
            Bend::Bar(b) => b.face_down(nodes, centre, contact),
            Bend::Groove(g) => g.face_down(nodes, centre, contact),
        }
    }

    fn turn(&self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Bend::Bar(b) => b.turn(v),
            Bend::Groove(g) => g.turn(v),
        }
    }

    /// The deck header's line on the geometry (`f`: metres to the deck's length unit;
    /// short: LS-DYNA's comment line holds it within 80 columns).
    fn geometry(&self, f: f64) -> String {
        let n = |x: f64| crate::scene::validate::num(x * f);
        match self {
            Bend::Bar(b) => format!(
                "bar R = {}, axis y, top at origin; target bent under it",
                n(b.radius)
            ),
            Bend::Groove(g) => match g.groove.gear() {
                Some(gear) => format!(
                    "gear Z = {}, m = {}, axis y, centre at x,z = {}, {}",
                    gear.teeth(),
                    n(g.groove.size().pitch.unwrap_or(0.0) / std::f64::consts::PI),
                    n(-g.origin.0),
                    n(-gear.radii().1 - g.origin.1)
                ),
                None => format!(
                    "groove along y, bottom middle at x,z = {}, {}",
                    n(g.groove.size().offset - g.origin.0),
                    n(-g.origin.1)
                ),
            },
        }
    }
}

/// The target block laid under a groove's surface. The block is laid out flat on the
/// unrolled surface, as on the bar, and `node` puts each node at its depth under the
/// surface point of its arc length, along the normal there: the fillets, flanks, edges
/// and lands it spans are followed. Model coordinates: the world's, its x across the
/// groove (`Groove::across`), y along its axis from the origin's axial coordinate, z up,
/// shifted so that the surface point at the model origin's arc length is `(0, 0, 0)`.
#[derive(Debug, Clone, Copy)]
struct GrooveLay {
    groove: Groove,
    /// The origin's arc length and axial coordinate, m.
    u0: f64,
    v0: f64,
    /// The surface point at the origin, world `(across, z)`, m.
    origin: (f64, f64),
}

impl GrooveLay {
    /// Refuses a block deeper than 0.8 of an edge's radius where it spans an edge (its
    /// nodes would cross under the edge's centre).
    fn new(
        groove: &Groove,
        u0: f64,
        v0: f64,
        u_lo: f64,
        u_hi: f64,
        depth: f64,
    ) -> Result<GrooveLay, DeckError> {
        let rho = groove.edge_radius();
        if depth >= 0.8 * rho {
            let (a, b) = (u0 + u_lo, u0 + u_hi);
            let samples = ((b - a) / (0.25 * rho)).ceil().max(1.0) as usize;
            // The sharpest convex piece spanned (an edge; on a gear also the flanks near
            // the fillets and the root and tip circles).
            let sharpest = (0..=samples)
                .map(|k| {
                    let u = a + (b - a) * k as f64 / samples as f64;
                    let (p, _) = groove.point_at(u, v0);
                    (groove.curvature_across(&p), groove.zone_at(u))
                })
                .fold((0.0, crate::contact::groove::Zone::Edge), |m, c| {
                    if c.0 > m.0 { c } else { m }
                });
            if sharpest.0 * depth >= 0.8 {
                return Err(DeckError::Bend(format!(
                    "the target block is {:.3} mm deep (2.5 shot radii) and spans a convex {} of \
                     the {}, whose {:.3} mm radius needs it shallower than 0.8 times that: \
                     select impacts away from it (--window on the unrolled surface, mm of arc \
                     across the {} and along it)",
                    depth * 1e3,
                    sharpest.1.name(),
                    if groove.gear().is_some() {
                        "gear"
                    } else {
                        "groove"
                    },
                    1e3 / sharpest.0,
                    if groove.gear().is_some() {
                        "teeth"
                    } else {
                        "groove"
                    },
                )));
            }
        }
        let (p, _) = groove.point_at(u0, v0);
        Ok(GrooveLay {
            groove: *groove,
            u0,
            v0,
            origin: (p.dot(&groove.across()), p.z),
        })
    }

    /// A world point's model coordinates.
    fn model_of(&self, q: Vec3) -> [f64; 3] {
        let g = &self.groove;
        [
            q.dot(&g.across()) - self.origin.0,
            q.dot(&g.axis()) - self.v0,
            q.z - self.origin.1,
        ]
    }

    /// A node of the flat block (relative to the origin) under the groove's surface.
    fn node(&self, p: [f64; 3]) -> [f64; 3] {
        let (at, n) = self.groove.point_at(self.u0 + p[0], self.v0 + p[1]);
        self.model_of(at + n * p[2])
    }

    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        self.model_of(Vec3::new(p[0], p[1], p[2]))
    }

    /// Turns `nodes` about `centre` (a ball's) about the axis' direction so that the
    /// ball's `-z` points along the inward normal at its contact (`contact`: the ball's
    /// centre at the touch, model coordinates).
    fn face_down(&self, nodes: &mut [[f64; 3]], centre: [f64; 3], contact: [f64; 3]) {
        let g = &self.groove;
        let world = g.across() * (contact[0] + self.origin.0)
            + g.axis() * (contact[1] + self.v0)
            + Vec3::z() * (contact[2] + self.origin.1);
        let n = g.foot(&world).normal;
        let phi = n.dot(&g.across()).atan2(n.z);
        tilt_ball(nodes, centre, phi);
    }

    /// A world vector (velocity, spin) in model coordinates.
    fn turn(&self, v: [f64; 3]) -> [f64; 3] {
        let w = Vec3::new(v[0], v[1], v[2]);
        let g = &self.groove;
        [w.dot(&g.across()), w.dot(&g.axis()), w.z]
    }
}

/// The target block bent around a cylindrical specimen. The block is laid out flat on
/// the unrolled surface (x: arc length around the bar from the model origin's, y:
/// along the axis from the origin's, z: height above the surface, negative inside);
/// `node` wraps it around the bar. Model coordinates: the world turned about the bar's
/// axis so that the model origin (the middle of the impacts on the unrolled surface)
/// is the crest: z along the surface normal there, y along the axis from the origin's
/// axial coordinate, x across it; the axis runs through `(0, 0, -R)`. Shots and their
/// velocities are only turned into this frame (`point`, `turn`): rigid motions.
#[derive(Debug, Clone, Copy)]
struct BarBend {
    radius: f64,
    axis: Vec3,
    across: Vec3,
    /// The origin's angle around the axis from the crest, rad: `(cos, sin)`.
    turn0: (f64, f64),
    /// The origin's axial coordinate, m.
    v0: f64,
}

impl BarBend {
    /// The block under a bar of `radius` along `axis`; refuses a block whose depth
    /// reaches the axis or that would wrap around the bar (`u_lo..u_hi` about the
    /// origin's arc length `u0`).
    fn new(
        radius: f64,
        axis: Vec3,
        u0: f64,
        v0: f64,
        u_lo: f64,
        u_hi: f64,
        depth: f64,
    ) -> Result<BarBend, DeckError> {
        if depth >= 0.8 * radius {
            return Err(DeckError::Bend(format!(
                "the target block is {:.3} mm deep (2.5 shot radii), too deep for the {:.3} mm \
                 bar: a deck of a cylinder needs its radius above 1.25 times the depth, {:.3} mm",
                depth * 1e3,
                radius * 1e3,
                depth * 1e3 / 0.8
            )));
        }
        let (lo, hi) = ((u0 + u_lo) / radius, (u0 + u_hi) / radius);
        if lo < -0.9 * std::f64::consts::PI || hi > 0.9 * std::f64::consts::PI {
            return Err(DeckError::Bend(format!(
                "the selected impacts and the block's margins span {:.0} to {:.0} degrees around \
                 the bar, beyond the +-162 degrees a bent block may reach: select impacts on \
                 one part of it (--window on the unrolled surface, mm of arc and along the axis)",
                lo.to_degrees(),
                hi.to_degrees()
            )));
        }
        let theta0 = u0 / radius;
        Ok(BarBend {
            radius,
            axis,
            across: axis.cross(&Vec3::z()),
            turn0: (theta0.cos(), theta0.sin()),
            v0,
        })
    }

    /// A node of the flat block (relative to the origin) on the bar.
    fn node(&self, p: [f64; 3]) -> [f64; 3] {
        let theta = p[0] / self.radius;
        let r = self.radius + p[2];
        [r * theta.sin(), p[1], r * theta.cos() - self.radius]
    }

    /// `(x, z)` (across the axis and up, about the axis) turned so that the origin's
    /// direction from the axis becomes +z.
    fn rot(&self, x: f64, z: f64) -> (f64, f64) {
        let (c, s) = self.turn0;
        (x * c - z * s, x * s + z * c)
    }

    /// A world point in model coordinates.
    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        let q = Vec3::new(p[0], p[1], p[2]);
        let (x, z) = self.rot(q.dot(&self.across), q.z + self.radius);
        [x, q.dot(&self.axis) - self.v0, z - self.radius]
    }

    /// Turns `nodes` about `centre` (a ball's) about the axis' direction so that the
    /// ball's `-z` points at the bar's axis from `contact` (the ball's centre at the
    /// touch, model coordinates).
    fn face_down(&self, nodes: &mut [[f64; 3]], centre: [f64; 3], contact: [f64; 3]) {
        let phi = contact[0].atan2(contact[2] + self.radius);
        tilt_ball(nodes, centre, phi);
    }

    /// A world vector (velocity, spin) in model coordinates.
    fn turn(&self, v: [f64; 3]) -> [f64; 3] {
        let w = Vec3::new(v[0], v[1], v[2]);
        let (x, z) = self.rot(w.dot(&self.across), w.z);
        [x, w.dot(&self.axis), z]
    }
}
