//! Sub-windows (session 31): the window scheduler runs an island of three or more shots
//! in sub-windows, each with its own groups, instead of over the whole window with one
//! clock. Only which shots share a clock changes: without shot-shot contact the states
//! agree with whole-window islands to the integrator's tolerance, shot by shot; with
//! collisions (chaotic) the distributions agree within their sampling noise, for fewer
//! shot-steps.

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

fn stream(duration_ms: f64, seed: u64) -> Scene {
    let text = format!(
        r#"
title = "sub-window test"
seed = {seed}
duration_ms = {duration_ms}
[shots.feed]
type = "stream"
rate_per_s = 40000.0
duration_ms = {duration_ms}
entry_speed_m_s = 5.0
arrivals = "regular"
"#
    );
    Scene::from_toml(&text, "stream.toml").unwrap()
}

fn run(scene: &Scene, sub_windows: bool) -> RunOutput {
    let effects = scene.effects();
    let sim = Simulation::new(scene, &effects)
        .unwrap()
        .with_sub_windows(sub_windows);
    assert_eq!(sim.scheduler_in_use(), "windows");
    sim.run(&|_| {})
}

/// 120 shots in the bore and the jet for 3 ms, fed 25 us apart: they share islands (the
/// bore wall may kick them), but none touches another, the wall or the specimen.
#[test]
fn without_contacts_sub_windows_give_the_same_states_to_the_tolerance() {
    let scene = stream(3.0, 1);
    let (whole, split) = (run(&scene, false), run(&scene, true));
    assert_eq!(whole.shots.len(), 120);
    assert!(whole.impacts.is_empty() && split.impacts.is_empty());
    for s in whole.shots.iter().chain(&split.shots) {
        assert_eq!(
            (s.collisions, s.wall_contacts, s.hits),
            (0, 0, 0),
            "shot {}",
            s.id.0
        );
    }
    // The islands really were cut: fewer shot-steps.
    let (a, b) = (whole.work.shot_steps, split.work.shot_steps);
    assert!(b < a, "shot-steps: {a} whole, {b} in sub-windows");
    // Same motion, to the integrator's global error: within 30 times the tolerance
    // (1e-6), the bound docs/accuracy.md states, relative to the speed and to the
    // flight's length (at most 0.1 m in 3 ms). Measured: 1.2e-6 m and 2.3e-5.
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for (p, q) in whole.shots.iter().zip(&split.shots) {
        assert_eq!(p.id, q.id);
        dx = dx.max((p.pos - q.pos).norm());
        dv = dv.max((p.vel - q.vel).norm() / p.vel.norm());
    }
    assert!(
        dx < 3e-6 && dv < 3e-5,
        "positions {dx:e} m, velocities {dv:e}"
    );
}

/// A colliding stream (1,000 shots, 30 ms; rebounds meet incoming shots), three seeds:
/// the first hits' distributions agree within their noise, for at least 20 % fewer
/// shot-steps. Measured (session 31): mean normal speed 45.70 / 45.13 m/s on seed 1,
/// shot-steps 363,817 / 228,353; the seed-to-seed spread of the mean is about 0.5 %.
#[test]
fn with_collisions_sub_windows_keep_the_distributions_for_fewer_steps() {
    let (mut speeds, mut radii, mut hit, mut steps) = ([0.0; 2], [0.0; 2], [0.0; 2], [0u64; 2]);
    let mut counts = [0usize; 2];
    for seed in 1..=3 {
        let scene = stream(30.0, seed);
        for (k, out) in [run(&scene, false), run(&scene, true)].iter().enumerate() {
            assert!(
                out.events.is_empty(),
                "a shot was stopped: {:?}",
                out.events
            );
            // First hits; the radius from the jet's axis (the vertical nozzle's: x = y = 0).
            let first: Vec<_> = out.impacts.iter().filter(|i| i.first_hit == 1).collect();
            for i in &first {
                speeds[k] += i.normal_speed_m_s;
                radii[k] += i.x_m.hypot(i.y_m);
            }
            counts[k] += first.len();
            hit[k] += first.len() as f64 / out.shots.len() as f64 / 3.0;
            steps[k] += out.work.shot_steps;
            assert!(out.shots.iter().map(|s| s.collisions).sum::<u32>() > 100);
        }
    }
    let mean = |x: [f64; 2], k: usize| x[k] / counts[k] as f64;
    let (v0, v1) = (mean(speeds, 0), mean(speeds, 1));
    let (r0, r1) = (mean(radii, 0), mean(radii, 1));
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
        (steps[1] as f64) < 0.8 * steps[0] as f64,
        "shot-steps {} whole, {} in sub-windows",
        steps[0],
        steps[1]
    );
}
