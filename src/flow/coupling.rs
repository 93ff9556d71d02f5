//! The jet slowed by the shots (beyond the paper, `[jet] coupling = "momentum"`). The
//! paper's air is a prescribed field that the shots take momentum from without slowing it
//! (one-way coupling, the default); at a production feed the shots take a tenth of the
//! jet's momentum or more (`crate::record::loading` measures the share in every run).
//!
//! With `coupling = "momentum"` the run uses the jet that carries what the shots leave
//! it: the nozzle's thrust `J = rho_c u_i^2 A` is set by the supply, the shots take `P`
//! of it per second, and the air, its (choked) mass flow `rho_c u_i A` unchanged, leaves
//! the bore `f = 1 - P / J` as fast and `1 / f` as dense. Every region of the field keeps
//! its shape; its speeds scale by `f` and its densities but the ambient air's by `1 / f`.
//! `P` depends on `f` (a slower jet gives less), so `f` is the fixed point of
//! `f = 1 - P(f) / J`, found by iteration. `P(f)` is read from lone shots flown, in the
//! jet scaled by `f`, to their first hits: one per size class of the feed and ring of
//! starting offsets ([`taken`]). A stream takes its rate times their weighted momentum
//! gain along the axis, a batch its size times that gain over the flight time (the
//! batch's shots fly together). A mean-field, first-order correction: the jet's profile
//! is the paper's, and the shots' drag does not reshape it.

use crate::scene::{Effects, Feed, ListShot, Scene, SceneError};
use crate::sim::Simulation;
use crate::state::ShotStatus;

/// Whether the shots slow the jet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Coupling {
    /// The paper's prescribed field (default).
    #[default]
    OneWay,
    /// The jet slowed by the momentum the shots take (see the module's documentation).
    Momentum,
}

impl Coupling {
    /// The scene file's name for it.
    pub fn name(self) -> &'static str {
        match self {
            Coupling::OneWay => "one_way",
            Coupling::Momentum => "momentum",
        }
    }
}

/// The slowest jet the correction is taken to hold for: half the free jet's speed.
pub const SLOWEST: f64 = 0.5;

/// `scene` with its air `f` times as fast at the same mass flow (the jet's speeds by `f`,
/// its supply, exit and capped densities by `1 / f`; the ambient air's unchanged).
pub fn scaled(scene: &Scene, f: f64) -> Scene {
    let mut s = scene.clone();
    s.air.exit_velocity *= f;
    s.air.rho_exit /= f;
    s.air.rho_stagnation /= f;
    s.jet.lip_density_cap /= f;
    s.jet.coupling = Coupling::OneWay;
    s
}

/// Rings of equal area the feed's disc or ring of starting offsets is cut into, one lone
/// shot per ring and size class.
pub const RINGS: usize = 3;

/// The momentum (N, along the jet's axis) the feed's shots take per second from the jet
/// of `scene` (its air as it stands), read from lone shots flown from the feed's places
/// to their first hits: one per size class ([`crate::scene::SizeDistribution::classes`])
/// and ring of starting offsets ([`RINGS`]), at the feed's mean depth; `None` for feeds
/// other than a stream and a batch.
pub fn taken(scene: &Scene, effects: &Effects) -> Result<Option<f64>, SceneError> {
    let axis = scene.nozzle.axis();
    // The centres spread evenly over the disc or ring they are drawn on: `RINGS` rings of
    // equal area, each at its mean offset (off the axis the free jet is slower: a shot on
    // the axis took 13 % more than a stream's own).
    let rings = |a: f64, b: f64| {
        let at = move |j: usize| (a * a + (b * b - a * a) * j as f64 / RINGS as f64).sqrt();
        (0..RINGS).map(move |j| {
            let (a, b) = (at(j), at(j + 1));
            if b > a {
                2.0 / 3.0 * (b.powi(3) - a.powi(3)) / (b * b - a * a)
            } else {
                a
            }
        })
    };
    let (depth, entry_speed) = match &scene.feed {
        Feed::Stream { entry_speed, .. } => (0.0, *entry_speed),
        Feed::Batch { axial_spread, .. } => (0.5 * axial_spread, 0.0),
        _ => return Ok(None),
    };
    // (diameter, weight, offset) of each lone shot.
    let lone: Vec<(f64, f64, f64)> = scene
        .sizes
        .classes()
        .into_iter()
        .flat_map(|(d, w)| {
            let (a, b) = match &scene.feed {
                Feed::Batch {
                    radial_min,
                    radial_max,
                    ..
                } => (*radial_min, *radial_max),
                _ => (0.0, 0.5 * (scene.nozzle.bore - d)),
            };
            rings(a, b).map(move |r| (d, w / RINGS as f64, r))
        })
        .collect();
    let fx = Effects {
        specimen_contact: true,
        shot_shot_contact: false,
        nozzle_wall_contact: false,
        friction: false,
        turbulent_dispersion: false,
        ..effects.clone()
    };
    // Flown together (they do not meet), long enough to reach the part: the scene's time,
    // doubled until each has hit it or gone (up to 1 s). A shot that misses the part (a
    // thin bar across a tilted jet) is flown again down the axis, which runs through it.
    let fly = |offsets: &[(f64, f64)]| -> Result<Vec<Option<(f64, f64)>>, SceneError> {
        let mut run = scene.clone();
        run.feed = Feed::List(
            offsets
                .iter()
                .map(|&(diameter, offset)| ListShot {
                    position: scene.nozzle.inlet()
                        + axis * depth
                        + scene.nozzle.cross_axes().0 * offset,
                    velocity: axis * entry_speed,
                    diameter,
                    start: 0.0,
                })
                .collect(),
        );
        let mut hits = vec![None; offsets.len()];
        loop {
            let out = Simulation::new(&run, &fx)?.run(&|_| {});
            for i in &out.impacts {
                let first = &mut hits[i.shot as usize];
                if first.is_none_or(|(_, t)| i.time_s < t) {
                    let v = crate::Vec3::new(i.vx_m_s, i.vy_m_s, i.vz_m_s);
                    *first = Some((v.dot(&axis) - entry_speed, i.time_s));
                }
            }
            let waiting = hits
                .iter()
                .zip(&out.shots)
                .any(|(h, s)| h.is_none() && s.status == ShotStatus::Active);
            run.duration *= 2.0;
            if !waiting || run.duration > 1.0 {
                return Ok(hits);
            }
        }
    };
    let mut hits = fly(&lone.iter().map(|l| (l.0, l.2)).collect::<Vec<_>>())?;
    let missed: Vec<usize> = (0..lone.len()).filter(|&i| hits[i].is_none()).collect();
    if !missed.is_empty() {
        let again = fly(&missed.iter().map(|&i| (lone[i].0, 0.0)).collect::<Vec<_>>())?;
        for (&i, hit) in missed.iter().zip(again) {
            hits[i] = hit;
        }
    }
    if hits.iter().any(Option::is_none) {
        let why = if effects.drag {
            ""
        } else {
            " (drag is off in [effects]: the air does not carry the shots)"
        };
        return Err(SceneError::Invalid {
            path: scene.path.clone(),
            key: "jet.coupling".into(),
            message: format!(
                "a shot flown alone from the feed's place, or down the axis, never reaches \
                 the specimen within 1 s{why}, so the momentum the shots take cannot be \
                 measured: use \"one_way\""
            ),
        });
    }
    // Each lone shot's share of a fed shot's momentum gain (and that over its flight).
    let density = scene.shot_material.density;
    let (mut gain, mut per_second) = (0.0, 0.0);
    for (&(d, w, _), hit) in lone.iter().zip(hits) {
        let (g, t) = hit.expect("BUG: checked above");
        let m = density * std::f64::consts::PI / 6.0 * d * d * d;
        gain += w * m * g;
        per_second += w * m * g / t;
    }
    Ok(Some(match &scene.feed {
        Feed::Stream { rate, .. } => rate * gain,
        Feed::Batch { count, .. } => *count as f64 * per_second,
        _ => unreachable!("BUG: only a stream or a batch is measured"),
    }))
}

/// The jet's air mass flow `rho_c u_i A` (kg/s) and momentum flow `rho_c u_i^2 A` (N: the
/// nozzle's thrust in the model) through the bore of `scene`, at its exit state.
pub fn jet_flows(scene: &Scene) -> (f64, f64) {
    let area = std::f64::consts::FRAC_PI_4 * scene.nozzle.bore * scene.nozzle.bore;
    let u = scene.air.exit_velocity;
    let mass = scene.core_density() * u * area;
    (mass, mass * u)
}

/// The scene the run uses and its air's speed factor `f` (1 with one-way coupling, or
/// for a feed neither a stream nor a batch, which validation refuses with coupling).
pub fn coupled(scene: &Scene, effects: &Effects) -> Result<(Scene, f64), SceneError> {
    let thrust = jet_flows(scene).1;
    let mut f = 1.0;
    for _ in 0..100 {
        let Some(p) = taken(&scaled(scene, f), effects)? else {
            return Ok((scene.clone(), 1.0));
        };
        let next = 1.0 - p / thrust;
        if next < SLOWEST && f > SLOWEST {
            // The fixed point may still lie above: try the slowest jet allowed. (`1 - P(f)
            // / J` falls as `f` grows, so if it is below `f` there, so is the fixed point.)
            f = SLOWEST;
            continue;
        }
        if next < SLOWEST {
            return Err(SceneError::Invalid {
                path: scene.path.clone(),
                key: "jet.coupling".into(),
                message: format!(
                    "the shots would slow the jet to below {:.0} % of its speed (slowed that \
                     far, it would still lose {:.0} % of the free jet's momentum flow to them), \
                     beyond what this first-order correction carries: lower the feed, or use \
                     \"one_way\" and read its speeds as upper bounds",
                    100.0 * SLOWEST,
                    100.0 * p / thrust
                ),
            });
        }
        let done = (next - f).abs() < 1e-10;
        f = next;
        if done {
            break;
        }
    }
    Ok((scaled(scene, f), f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slowed_jet_carries_the_same_air_and_what_the_shots_leave_it() {
        // The paper's batch: the fixed point holds to the iteration's tolerance, the air's
        // mass flow is the free jet's and its momentum flow `f` times it.
        let mut scene = Scene::default_scene();
        scene.jet.coupling = Coupling::Momentum;
        let effects = scene.effects();
        let (slowed, f) = coupled(&scene, &effects).unwrap();
        assert!(f > 0.85 && f < 0.99, "{f}");
        let flow = |s: &Scene| {
            let a = std::f64::consts::FRAC_PI_4 * s.nozzle.bore.powi(2);
            (
                s.core_density() * s.air.exit_velocity * a,
                s.core_density() * s.air.exit_velocity.powi(2) * a,
            )
        };
        let ((m0, j0), (m1, j1)) = (flow(&scene), flow(&slowed));
        assert!((m1 / m0 - 1.0).abs() < 1e-12);
        assert!((j1 / j0 - f).abs() < 1e-12);
        assert_eq!(slowed.air.rho_ambient, scene.air.rho_ambient);
        assert_eq!(slowed.jet.coupling, Coupling::OneWay);
        let p = taken(&slowed, &effects).unwrap().unwrap();
        assert!(
            (1.0 - p / j0 - f).abs() < 1e-9,
            "{f} against {}",
            1.0 - p / j0
        );
        // A slower jet gives the shots less: the share at the fixed point is below the
        // free jet's.
        let free = taken(&scene, &effects).unwrap().unwrap();
        assert!(p < free && p > 0.5 * free, "{p} {free}");
    }

    #[test]
    fn a_lone_shot_that_misses_a_thin_bar_is_flown_down_the_axis() {
        // Random scene 23 of `bench/random_scenes.py --seed 696 --cylinder --curves`: its
        // batch's shots start up to 5.1 mm off the axis of a 10.7 mm bore tilted 40
        // degrees over a bar of 3.65 mm radius; from the mean offset (3.4 mm) a lone shot
        // flies past the bar, and the coupling refused the scene until session 64's
        // fallback.
        let text = "seed = 306\nduration_ms = 30\n[air]\ngauge_pressure_mpa = 0.816\n\
                    [nozzle]\nbore_mm = 10.702\nlength_mm = 137.76\nstandoff_mm = 45.30\n\
                    angle_deg = 39.98\nazimuth_deg = 178.1\n[jet]\nmodel = \"consistent\"\n\
                    core_density = \"rho_0\"\ncoupling = \"momentum\"\n[shots]\n\
                    diameter_mm = 0.388\n[shots.feed]\ntype = \"batch\"\ncount = 1\n\
                    radial_offset_mm = [0.0, 5.105]\naxial_spread_mm = 5.96\n[specimen]\n\
                    shape = \"cylinder\"\nradius_mm = 3.654\naxis_deg = 150.99\n";
        let scene = Scene::from_toml(text, "thin_bar.toml").unwrap();
        let effects = scene.effects();
        let p = taken(&scene, &effects).unwrap().unwrap();
        assert!(p > 0.0, "{p}");
        let (_, f) = coupled(&scene, &effects).unwrap();
        assert!(f < 1.0 && f > 0.999, "{f}");
    }

    #[test]
    fn feeds_it_cannot_measure_are_left_as_they_are() {
        let mut scene = Scene::default_scene();
        scene.jet.coupling = Coupling::Momentum;
        scene.feed = Feed::List(vec![ListShot {
            position: scene.nozzle.inlet(),
            velocity: crate::Vec3::zeros(),
            diameter: 0.8e-3,
            start: 0.0,
        }]);
        let effects = scene.effects();
        assert_eq!(taken(&scene, &effects).unwrap(), None);
        assert_eq!(coupled(&scene, &effects).unwrap().1, 1.0);
    }
}
