//! Shared helpers for the integration tests.
#![allow(dead_code)]

use std::f64::consts::PI;

use peenflow::Vec3;
use peenflow::contact::{ContactSet, HertzLaw, PairContact, SpecimenContact};
use peenflow::forces::{ForceSet, ShotBody};
use peenflow::integrate::Physics;
use peenflow::state::{Domain, ShotId, ShotState};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs the peenflow binary with `args`.
pub fn peenflow(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_peenflow"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("cannot start peenflow")
}

/// A 30 ms stream of 3 kg/min onto A5052 run into `dir/run` (the coverage tests' run).
pub fn coverage_run(dir: &Path) {
    std::fs::write(
        dir.join("s.toml"),
        "duration_ms = 30.0\n[shots.feed]\ntype = \"stream\"\nmass_flow_kg_min = 3.0\nentry_speed_m_s = 5.0\n[specimen]\nmaterial = \"A5052\"\n",
    )
    .unwrap();
    let o = peenflow(&["run", "s.toml", "-q", "--out", "run"], dir);
    assert!(
        o.status.code().unwrap() <= 1,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A sweep of the default scene over seeds 1 and 2 run into `dir/sw`; the path of its
/// one case's impact file, relative to `dir`.
pub fn two_seed_sweep(dir: &Path) -> &'static str {
    std::fs::write(
        dir.join("s.toml"),
        "seeds = [1, 2]\n[vary]\n\"air.gauge_pressure_mpa\" = [0.6]\n",
    )
    .unwrap();
    let o = peenflow(&["sweep", "s.toml", "--out", "sw", "-q"], dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    "sw/case-000_gauge_pressure_mpa-0.6/impacts.h5"
}

/// Whether `cmd` can run (`probe` arguments). In CI a missing tool is a failure.
pub fn have(cmd: &str, probe: &[&str]) -> bool {
    let ok = Command::new(cmd)
        .args(probe)
        .output()
        .is_ok_and(|o| o.status.success() || !o.stdout.is_empty());
    if !ok {
        assert!(
            std::env::var_os("CI").is_none(),
            "{cmd} missing in CI: .ci/run must install it"
        );
        eprintln!("SKIPPED: {cmd} is not installed (bash .ci/run installs it)");
    }
    ok
}

/// Steel of the paper's Table 2.
pub const E_STEEL: f64 = 210e9;
/// Poisson's ratio of the paper's Table 2.
pub const NU_STEEL: f64 = 0.3;
/// Shot density, kg/m^3.
pub const RHO_SHOT: f64 = 7850.0;

/// A steel shot of diameter `d` at `pos` moving at `vel`.
pub fn shot(id: u32, d: f64, pos: Vec3, vel: Vec3) -> ShotState {
    let body = ShotBody {
        radius: 0.5 * d,
        mass: RHO_SHOT * std::f64::consts::PI / 6.0 * d * d * d,
    };
    ShotState::new(ShotId(id), pos, vel, body, 0.0)
}

/// Contact-only physics (no air, no gravity): steel on steel with the given restitutions.
pub fn contact_physics(specimen_e: Option<f64>, pair_e: Option<f64>) -> Physics {
    let law = |e| HertzLaw::new(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL, e);
    Physics {
        forces: ForceSet {
            drag: None,
            lateral: None,
            gravity: None,
            field: None,
            turbulence: None,
        },
        contacts: ContactSet {
            specimen: specimen_e.map(|e| SpecimenContact {
                law: law(e),
                by_speed: None,
                shape: peenflow::contact::specimen::SpecimenShape::Plane,
            }),
            wall: None,
            pair: pair_e.map(|e| PairContact { law: law(e) }),
            friction: None,
        },
        tolerance: 1e-6,
        contact_steps: 50.0,
        domain: Domain {
            radius: 10.0,
            top: 10.0,
            bottom: f64::NEG_INFINITY,
        },
        max_step: 1e-3,
        method: peenflow::integrate::island::Method::Adaptive,
        sliding: true,
        blocks_min: peenflow::integrate::island::BLOCKS_MIN,
        free_steps: true,
    }
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A regular stream through the nozzle (the paper's jet; shots entering the bore at
/// 5 m/s): `rate` shots/s fed for `feed_ms`, a run of `feed_ms + tail_ms`, `seed`.
pub fn nozzle_stream(
    title: &str,
    rate: f64,
    (feed_ms, tail_ms): (f64, f64),
    seed: u64,
) -> peenflow::scene::Scene {
    let end_ms = feed_ms + tail_ms;
    let text = format!(
        "title = \"{title}\"\nseed = {seed}\nduration_ms = {end_ms}\n[shots.feed]\ntype = \"stream\"\nrate_per_s = {rate}\nduration_ms = {feed_ms}\nentry_speed_m_s = 5.0\narrivals = \"regular\"\n"
    );
    peenflow::scene::Scene::from_toml(&text, "stream.toml").unwrap()
}

/// A regular stream through the nozzle without shot-shot contact (the independent
/// scheduler): `rate` shots/s entering at 5 m/s for `feed_ms`, a run of `run_ms`, and
/// `extra` TOML appended (e.g. a `[friction]` table).
pub fn stream_without_contact(
    rate: f64,
    feed_ms: f64,
    run_ms: f64,
    extra: &str,
) -> peenflow::scene::Scene {
    let text = format!(
        "duration_ms = {run_ms}\n[effects]\nshot_shot_contact = false\n[shots.feed]\ntype = \"stream\"\nrate_per_s = {rate}\nduration_ms = {feed_ms}\nentry_speed_m_s = 5.0\narrivals = \"regular\"\n{extra}"
    );
    peenflow::scene::Scene::from_toml(&text, "stream_without_contact.toml").unwrap()
}

/// A colliding nozzle stream run over `seeds` with two settings (`run(scene, false)`,
/// then `run(scene, true)`) that should give the same outcomes (only which shots share a
/// clock differs, or how contacts are stepped): checks
/// that the first hits' distributions agree within their noise (mean normal speed
/// within 2 %, mean radius from the jet's axis, x = y = 0, within 10 %, hit fraction
/// within 0.02; the seed-to-seed spread of the mean speed is about 0.5 %) and that the
/// second setting takes fewer than `step_ratio` times the first one's shot-steps.
pub fn same_hits_for_fewer_steps(
    scene: impl Fn(u64) -> peenflow::scene::Scene,
    run: impl Fn(&peenflow::scene::Scene, bool) -> peenflow::sim::RunOutput,
    seeds: std::ops::RangeInclusive<u64>,
    step_ratio: f64,
) {
    let (mut speeds, mut radii, mut hit, mut steps) = ([0.0; 2], [0.0; 2], [0.0; 2], [0u64; 2]);
    let mut counts = [0usize; 2];
    let n_seeds = seeds.clone().count() as f64;
    for seed in seeds {
        let scene = scene(seed);
        for (k, out) in [run(&scene, false), run(&scene, true)].iter().enumerate() {
            assert!(
                out.events.is_empty(),
                "a shot was stopped: {:?}",
                out.events
            );
            let first: Vec<_> = out.impacts.iter().filter(|i| i.first_hit == 1).collect();
            for i in &first {
                speeds[k] += i.normal_speed_m_s;
                radii[k] += i.x_m.hypot(i.y_m);
            }
            counts[k] += first.len();
            hit[k] += first.len() as f64 / out.shots.len() as f64 / n_seeds;
            steps[k] += out.work.shot_steps;
            assert!(out.shots.iter().map(|s| s.collisions).sum::<u32>() > 100);
        }
    }
    let mean = |x: [f64; 2], k: usize| x[k] / counts[k] as f64;
    let (v0, v1) = (mean(speeds, 0), mean(speeds, 1));
    let (r0, r1) = (mean(radii, 0), mean(radii, 1));
    println!(
        "mean normal speed {v0:.3} / {v1:.3} m/s, mean radius {r0:.5} / {r1:.5} m, hit fraction \
         {:.3} / {:.3}, shot-steps {} / {}",
        hit[0], hit[1], steps[0], steps[1]
    );
    assert!(
        (v1 / v0 - 1.0).abs() < 0.02,
        "mean normal speed {v0} / {v1} m/s"
    );
    assert!((r1 / r0 - 1.0).abs() < 0.10, "mean radius {r0} / {r1} m");
    assert!(
        (hit[1] - hit[0]).abs() < 0.02,
        "hit fraction {} / {}",
        hit[0],
        hit[1]
    );
    assert!(
        (steps[1] as f64) < step_ratio * steps[0] as f64,
        "shot-steps {} / {}",
        steps[0],
        steps[1]
    );
}

/// Two runs of the same shots without any contact (120 shots of a 3 ms nozzle stream)
/// in which only which shots share a clock differs: checks that no shot touched
/// anything, that `b` took fewer than `step_ratio` times `a`'s shot-steps, and that the
/// shots' final states agree within 30 times the tolerance (1e-6), the global-error
/// bound docs/accuracy.md states, relative to the speed and to the flight's length (at
/// most 0.1 m in 3 ms). Returns the largest differences (m, relative).
pub fn same_states_for_fewer_steps(
    a: &peenflow::sim::RunOutput,
    b: &peenflow::sim::RunOutput,
    step_ratio: f64,
) -> (f64, f64) {
    assert_eq!(a.shots.len(), 120);
    assert!(a.impacts.is_empty() && b.impacts.is_empty());
    for s in a.shots.iter().chain(&b.shots) {
        assert_eq!(
            (s.collisions, s.wall_contacts, s.hits),
            (0, 0, 0),
            "shot {}",
            s.id.0
        );
    }
    let (na, nb) = (a.work.shot_steps, b.work.shot_steps);
    assert!(
        (nb as f64) < step_ratio * na as f64,
        "shot-steps: {na} / {nb}"
    );
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for (p, q) in a.shots.iter().zip(&b.shots) {
        assert_eq!(p.id, q.id);
        dx = dx.max((p.pos - q.pos).norm());
        dv = dv.max((p.vel - q.vel).norm() / p.vel.norm());
    }
    assert!(
        dx < 3e-6 && dv < 3e-5,
        "positions {dx:e} m, velocities {dv:e}"
    );
    (dx, dv)
}

/// Runs `scene` with its own effects.
pub fn run_scene(scene: &peenflow::scene::Scene) -> peenflow::sim::RunOutput {
    peenflow::sim::Simulation::new(scene, &scene.effects())
        .unwrap()
        .run(&|_| {})
}

/// [`run_scene`] on a pool of `threads` threads.
pub fn run_scene_on(threads: usize, scene: &peenflow::scene::Scene) -> peenflow::sim::RunOutput {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run_scene(scene))
}

/// A point or direction in the half frame of a tooth space: `x` towards its right
/// flank, `y` from the gear's centre through the space's middle, mm.
pub type Point = (f64, f64);

/// Surface points and outward normals (half frame, mm) of a standard spur gear
/// (`teeth`, `module` mm, pressure angle `alpha_deg`, cut by a rack with corners of
/// `fillet` mm, tip edges of `edge` mm; addendum 1 and dedendum 1.25 modules), from
/// textbook gear geometry: in the middle of the root, on the fillet where the rack's
/// corner cuts it with its normal 45 degrees off straight down (the law of gearing fixes
/// the rolling angle: the normal runs through the pitch point), the flank at the pitch
/// circle (a quarter of the angular pitch off the space's middle, its normal the pitch
/// circle's tangent turned by the pressure angle), the tip edge's middle and the tooth
/// tip's middle.
#[allow(non_snake_case)]
pub fn gear_zone_points(
    teeth: f64,
    module: f64,
    alpha_deg: f64,
    fillet: f64,
    edge: f64,
) -> Vec<(&'static str, Point, Point)> {
    let (z, MODULE, ALPHA, FILLET, EDGE) = (teeth, module, alpha_deg, fillet, edge);
    let tau = 2.0 * PI / z;
    let a = ALPHA.to_radians();
    let r_p = z * MODULE / 2.0;
    let (hf, ha) = (1.25 * MODULE, MODULE);
    let (r_f, r_a, r_b) = (r_p - hf, r_p + ha, r_p * a.cos());
    // The rack's tooth (the gear's space) is half a pitch wide at its pitch line: its
    // flat tip's half width between the corners of radius FILLET.
    let p = PI * MODULE;
    let hb = p / 4.0 - (hf - FILLET * (1.0 - a.sin())) * a.tan() - FILLET * a.cos();
    // Rolling the rack by `phi` puts the pitch point at (r_p phi, r_p) in its frame;
    // gear frame = rack frame less (r_p phi, 0), turned by phi towards +x.
    let to_gear = |q: Point, phi: f64| {
        let (x, y) = (q.0 - r_p * phi, q.1);
        (
            x * phi.cos() + y * phi.sin(),
            -x * phi.sin() + y * phi.cos(),
        )
    };
    let turn = |v: Point, phi: f64| {
        (
            v.0 * phi.cos() + v.1 * phi.sin(),
            -v.0 * phi.sin() + v.1 * phi.cos(),
        )
    };
    // Fillet: the corner (centre (hb, r_f + FILLET)) touching with its normal 45
    // degrees off straight down; the normal runs through the pitch point.
    let theta = 45f64.to_radians();
    let nu = (theta.sin(), -theta.cos());
    let centre = (hb, r_f + FILLET);
    let t = (r_p - centre.1) / theta.cos();
    let phi = (centre.0 - t * theta.sin()) / r_p;
    let fillet = to_gear((centre.0 + FILLET * nu.0, centre.1 + FILLET * nu.1), phi);
    let fillet_n = turn((-nu.0, -nu.1), phi);
    // Flank at the pitch circle: a quarter pitch angle off the middle; the normal is
    // the pitch circle's tangent turned by the pressure angle towards the space's
    // middle and out.
    let ap = tau / 4.0;
    let flank = (r_p * ap.sin(), r_p * ap.cos());
    let psi = ap + a;
    let flank_n = (-psi.cos(), psi.sin());
    // Tip edge: centre EDGE inside the tip circle and the involute. The involute's
    // start angle on the base circle, from the flank at the pitch circle.
    let a_b = ap - (a.tan() - a);
    let q = ((r_a - EDGE).powi(2) - r_b * r_b).sqrt();
    let beta = (q + EDGE) / r_b;
    let psi_e = a_b + beta;
    let e = (
        r_b * psi_e.sin() - q * psi_e.cos(),
        r_b * psi_e.cos() + q * psi_e.sin(),
    );
    // Halfway between the flank's normal there and the radial direction through e.
    let from = psi_e - PI / 2.0;
    let to = e.0.atan2(e.1);
    let mid = 0.5 * (from + to);
    let edge = (e.0 + EDGE * mid.sin(), e.1 + EDGE * mid.cos());
    let edge_n = (mid.sin(), mid.cos());
    let root_a = 0.5 * hb / r_p;
    vec![
        (
            "bottom",
            (r_f * root_a.sin(), r_f * root_a.cos()),
            (root_a.sin(), root_a.cos()),
        ),
        ("fillet", fillet, fillet_n),
        ("flank", flank, flank_n),
        ("edge", edge, edge_n),
        (
            "land",
            (r_a * (tau / 2.0).sin(), r_a * (tau / 2.0).cos()),
            ((tau / 2.0).sin(), (tau / 2.0).cos()),
        ),
    ]
}

/// A stream's run onto a groove or a gear (`out`, on `shape`): every impact on the
/// surface (1e-12 m) with a normal speed in `(0, speed]`, every zone hit, no shot left
/// inside the part.
pub fn check_every_zone_hit(
    out: &peenflow::sim::RunOutput,
    shape: &peenflow::contact::specimen::SpecimenShape,
) {
    let peenflow::contact::specimen::SpecimenShape::Groove(g) = shape else {
        panic!("not a groove")
    };
    let mut zones = std::collections::BTreeMap::new();
    for i in &out.impacts {
        let p = Vec3::new(i.x_m, i.y_m, i.z_m);
        assert!(shape.distance(&p).abs() < 1e-12, "{p:?}");
        assert!(i.normal_speed_m_s > 0.0 && i.normal_speed_m_s <= i.speed_m_s);
        *zones.entry(g.zone(&p).name()).or_insert(0) += 1;
    }
    println!("{} shots, impacts per zone {zones:?}", out.shots.len());
    for zone in ["bottom", "fillet", "flank", "edge", "land"] {
        assert!(
            zones.get(zone).copied().unwrap_or(0) > 0,
            "{zone}: {zones:?}"
        );
    }
    for s in &out.shots {
        assert!(
            shape.distance(&s.pos) > s.body.radius * (1.0 - 1e-3),
            "shot {} inside",
            s.id.0
        );
    }
}

/// A scene without air or gravity onto `specimen` (its TOML lines), restitution 0.7, with
/// shots of `diameter_mm` thrown from a list (`shots`: position mm, velocity m/s), and
/// `extra` TOML lines after `[shots]`; `name` is the file named in errors.
pub fn airless_scene(
    specimen: &str,
    shots: &[(Vec3, Vec3)],
    duration_ms: f64,
    diameter_mm: f64,
    extra: &str,
    name: &str,
) -> peenflow::scene::Scene {
    let mut s = format!(
        "duration_ms = {duration_ms:?}\ngravity_m_s2 = 0.0\n[effects]\ndrag = false\n\
         lateral_force = false\n{specimen}[shots]\ndiameter_mm = {diameter_mm:?}\n{extra}\n\
         [shots.feed]\ntype = \"list\"\n"
    );
    for (p, v) in shots {
        s += &format!(
            "[[shots.feed.shots]]\nposition_mm = [{:?}, {:?}, {:?}]\nvelocity_m_s = [{:?}, {:?}, {:?}]\n",
            p.x, p.y, p.z, v.x, v.y, v.z
        );
    }
    peenflow::scene::Scene::from_toml(&s, name).unwrap()
}
