//! Separate clocks (session 32): the window scheduler steps the members of an island that
//! keep apart each on its own clock (`sim::advance_apart`), and a lone shot's step that
//! would run into an event (a jet region's boundary, the specimen) is cut short of it
//! instead of stepping window by window up to it. Only the steps change: without
//! shot-shot contact the states agree with one clock per island to the integrator's
//! tolerance, shot by shot; with collisions (chaotic) the distributions agree within
//! their sampling noise, for fewer shot-steps.

mod common;

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

/// A stream fed for `feed_ms`, run until `feed_ms` plus `tail_ms`.
fn stream(rate_per_s: f64, (feed_ms, tail_ms): (f64, f64), seed: u64) -> Scene {
    let (duration_ms, end_ms) = (feed_ms, feed_ms + tail_ms);
    let text = format!(
        r#"
title = "separate clocks test"
seed = {seed}
duration_ms = {end_ms}
[shots.feed]
type = "stream"
rate_per_s = {rate_per_s}
duration_ms = {duration_ms}
entry_speed_m_s = 5.0
arrivals = "regular"
"#
    );
    Scene::from_toml(&text, "stream.toml").unwrap()
}

fn run(scene: &Scene, separate: bool) -> RunOutput {
    let effects = scene.effects();
    let sim = Simulation::new(scene, &effects)
        .unwrap()
        .with_separate_clocks(separate);
    assert_eq!(sim.scheduler_in_use(), "windows");
    sim.run(&|_| {})
}

/// A run with no windows at all: one shot flies alone from its entry to the end.
fn run_single(scene: &Scene) -> RunOutput {
    let effects = scene.effects();
    let sim = Simulation::new(scene, &effects).unwrap();
    let out = sim.run(&|_| {});
    assert_eq!((out.shots.len(), out.windows), (1, 1));
    out
}

/// 120 shots in the bore and the jet for 3 ms, fed 25 us apart: they share islands (the
/// bore wall may kick them), but none touches another, the wall or the specimen.
#[test]
fn without_contacts_separate_clocks_give_the_same_states_to_the_tolerance() {
    let scene = stream(40_000.0, (3.0, 0.0), 1);
    // Measured (session 32): 4,161 / 2,602 shot-steps; 7.8e-7 m and 1.4e-5.
    common::same_states_for_fewer_steps(&run(&scene, false), &run(&scene, true), 0.8);
}

/// A lone shot steps across window ends; a step that runs into an event is cut short
/// of it. Four shots fed 2.5 ms apart fly through the windows alone: each takes about
/// the steps it takes in a run with no windows at all (one shot), and hits the same.
#[test]
fn a_lone_shot_through_windows_takes_the_steps_of_a_run_without_them() {
    let alone = run_single(&stream(400.0, (2.5, 4.0), 1));
    let four = run(&stream(400.0, (10.0, 4.0), 1), true);
    assert_eq!(four.shots.len(), 4);
    assert!(four.windows > 100, "{} windows", four.windows);
    let flight = |o: &RunOutput| -> Vec<u64> {
        o.shots
            .iter()
            .map(|s| s.steps_to_first_contact.expect("every shot hits"))
            .collect()
    };
    let (single, windowed) = (flight(&alone)[0], flight(&four));
    // Measured (session 32): 26 steps alone, 29-31 through windows (59-65 before the
    // cut, window after window up to each jet region's boundary and the specimen).
    assert!(
        windowed.iter().all(|&n| n <= single + single / 4),
        "steps to the first contact: {single} alone, {windowed:?} through windows"
    );
    // Same flight: the first shot's impact, to the integrator's tolerance. Measured:
    // 1.2e-6 in normal speed, 9e-11 m, 2e-9 s.
    let (a, b) = (&alone.impacts[0], &four.impacts[0]);
    assert_eq!((a.shot, b.shot), (0, 0));
    assert!((a.normal_speed_m_s / b.normal_speed_m_s - 1.0).abs() < 3e-5);
    assert!((a.x_m - b.x_m).hypot(a.y_m - b.y_m) < 3e-6);
    assert!((a.time_s - b.time_s).abs() < 1e-7);
}

/// A colliding stream (1,000 shots fed over 25 ms, 30 ms; rebounds meet incoming shots),
/// three seeds:
/// the first hits' distributions agree within their noise, for at least 15 % fewer
/// shot-steps. Measured (session 32), over the three seeds: mean normal speed 44.91 /
/// 44.68 m/s, mean radius 12.19 / 12.35 mm, hit fraction 0.804 / 0.812, shot-steps
/// 563,937 / 435,384 (one clock per island / separate clocks; both cut steps short of
/// events).
#[test]
fn with_collisions_separate_clocks_keep_the_distributions_for_fewer_steps() {
    let scene = |seed| stream(40_000.0, (25.0, 5.0), seed);
    common::same_hits_for_fewer_steps(scene, run, 1..=3, 0.85);
}
