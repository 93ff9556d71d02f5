//! Shot-specimen restitution against the impact speed (`[restitution]
//! shot_specimen_curve`, beyond the paper):
//! * shots dropped at speeds below, on, between and beyond the curve's points rebound with
//!   the curve's restitution (a power law between points, computed here independently),
//!   on the event scheduler, on windows, with friction, on the fixed-step and hybrid
//!   methods, each within a tolerance stated with its method;
//! * a one-point curve is the constant restitution: the same run to the bit;
//! * a nozzle stream with a curve gives the same results on 1 and 2 threads, and its list
//!   of effects names the curve.

use crate::common;
use common::*;
use peenflow::scene::Scene;

/// The curve of the tests: (normal speed m/s, restitution).
const CURVE: [(f64, f64); 3] = [(20.0, 0.5), (50.0, 0.35), (100.0, 0.25)];

/// The curve's restitution at `v`, written out here: `e_0 (e_1 / e_0)^f` with
/// `f = ln(v / v_0) / ln(v_1 / v_0)` between neighbouring points, the end values beyond.
fn expected(v: f64) -> f64 {
    if v <= CURVE[0].0 {
        return CURVE[0].1;
    }
    for w in CURVE.windows(2) {
        let ((v0, e0), (v1, e1)) = (w[0], w[1]);
        if v <= v1 {
            return e0 * (e1 / e0).powf((v / v0).ln() / (v1 / v0).ln());
        }
    }
    CURVE[2].1
}

/// Normal impact speeds of the dropped shots, m/s (below, between, on and beyond the
/// curve's points); the last shot also moves sideways at 10 m/s.
const SPEEDS: [f64; 6] = [8.0, 30.0, 50.0, 70.0, 160.0, 40.0];

/// Six shots 5 mm apart, 0.2 mm above the specimen, falling at `SPEEDS`; no air, no
/// gravity; `restitution` and `extra` TOML lines appended.
fn drop_scene(restitution: &str, extra: &str) -> Scene {
    let mut s = String::from(
        "duration_ms = 0.1\ngravity_m_s2 = 0.0\n[effects]\ndrag = false\nlateral_force = false\n",
    );
    s += &format!("[restitution]\n{restitution}\n{extra}\n[shots.feed]\ntype = \"list\"\n");
    for (i, v) in SPEEDS.iter().enumerate() {
        let vx = if i == 5 { 10.0 } else { 0.0 };
        s += &format!(
            "[[shots.feed.shots]]\nposition_mm = [{}, 0.0, 0.6]\nvelocity_m_s = [{vx}, 0.0, -{v}]\n",
            5.0 * i as f64
        );
    }
    Scene::from_toml(&s, "drop.toml").unwrap()
}

fn curve_line() -> String {
    let (v, e): (Vec<String>, Vec<String>) = CURVE
        .iter()
        .map(|(v, e)| (format!("{v:?}"), format!("{e:?}")))
        .unzip();
    format!(
        "shot_specimen_curve = {{ speed_m_s = [{}], restitution = [{}] }}",
        v.join(", "),
        e.join(", ")
    )
}

/// Largest relative error of the rebound speeds against the curve.
fn worst_rebound(extra: &str) -> (f64, &'static str) {
    let out = run_scene(&drop_scene(&curve_line(), extra));
    assert!(out.events.is_empty(), "{:?}", out.events);
    let mut worst: f64 = 0.0;
    for (s, v) in out.shots.iter().zip(SPEEDS) {
        assert_eq!(s.hits, 1, "shot {} hits", s.id.0);
        let e = s.vel.z / v;
        worst = worst.max((e / expected(v) - 1.0).abs());
    }
    (worst, out.scheduler)
}

#[test]
fn rebounds_follow_the_curve_on_every_method() {
    // (scene lines, bound, the scheduler that runs it); measured when written: 2.7e-6
    // (events), 1.4e-5 (windows), 2.7e-6 (friction), 4.8e-10 (1e-10), 8.7e-4 and 1.0e-3
    // (fixed steps on windows and events), 8.4e-4 (hybrid).
    let cases = [
        // The adaptive method at its default tolerance.
        ("", 1e-4, "events"),
        ("[integrator]\nscheduler = \"windows\"", 1e-4, "windows"),
        // Friction on the specimen: the normal law is the same (the sideways shot rolls).
        ("[friction]\nshot_specimen = 0.3", 1e-4, "events"),
        // A tight tolerance: the curve to 1e-9 (the damping table is good to 1e-7 in e).
        ("[integrator]\ntolerance = 1e-10", 2e-7, "events"),
        // Fixed steps of 2 ns (a 500th of the fastest contact): as with a constant
        // restitution (1.3e-3 on windows).
        (
            "[integrator]\nmethod = \"verlet\"\nfixed_step_ns = 2",
            3e-3,
            "windows",
        ),
        (
            "[integrator]\nmethod = \"verlet\"\nfixed_step_ns = 2\nscheduler = \"events\"",
            3e-3,
            "events",
        ),
        (
            "[integrator]\nmethod = \"hybrid\"\nfixed_step_ns = 2",
            3e-3,
            "events",
        ),
    ];
    for (extra, tol, scheduler) in cases {
        let (worst, ran) = worst_rebound(extra);
        println!("{extra:?}: worst {worst:.2e} on {ran}");
        assert_eq!(ran, scheduler, "{extra:?}");
        assert!(worst < tol, "{extra:?}: worst {worst:e} against {tol:e}");
    }
}

#[test]
fn a_one_point_curve_is_the_constant_restitution() {
    for extra in [
        "",
        "[integrator]\nscheduler = \"windows\"",
        "[integrator]\nmethod = \"verlet\"\nfixed_step_ns = 5",
    ] {
        let constant = run_scene(&drop_scene("shot_specimen = 0.3", extra));
        let curve = run_scene(&drop_scene(
            "shot_specimen_curve = { speed_m_s = [70.0], restitution = [0.3] }",
            extra,
        ));
        assert_eq!(constant.shots, curve.shots, "{extra:?}");
        assert_eq!(constant.impacts, curve.impacts, "{extra:?}");
    }
}

#[test]
fn a_stream_with_a_curve_is_the_same_on_one_and_two_threads() {
    let text = format!(
        "duration_ms = 8.0\n[restitution]\n{}\n[specimen]\nmaterial = \"A5052\"\n\
         [shots.feed]\ntype = \"stream\"\nrate_per_s = 20000.0\n",
        curve_line()
    );
    let scene = Scene::from_toml(&text, "stream.toml").unwrap();
    // The run's list of effects says which law the specimen contact has.
    let said = &scene.effects().decisions[3];
    assert_eq!(said.name, "specimen_contact");
    assert!(
        said.reason.ends_with(
            "; restitution against impact speed (3 points: 0.5 at 20 m/s to 0.25 at 100 m/s)"
        ),
        "{}",
        said.reason
    );
    let one = run_scene_on(1, &scene);
    let two = run_scene_on(2, &scene);
    println!("{} impacts", one.impacts.len());
    assert!(one.impacts.len() > 50, "{} impacts", one.impacts.len());
    assert!(
        one.impacts.iter().any(|i| i.first_hit == 0),
        "no rebound hits"
    );
    assert_eq!(one.impacts, two.impacts);
    assert_eq!(one.shots, two.shots);
}
