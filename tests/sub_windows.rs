//! Sub-windows (session 31): the window scheduler runs an island of three or more shots
//! in sub-windows, each with its own groups, instead of over the whole window with one
//! clock. Only which shots share a clock changes: without shot-shot contact the states
//! agree with whole-window islands to the integrator's tolerance, shot by shot; with
//! collisions (chaotic) the distributions agree within their sampling noise, for fewer
//! shot-steps.

use crate::common;

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

fn stream(duration_ms: f64, seed: u64) -> Scene {
    common::nozzle_stream("sub-window test", 40_000.0, (duration_ms, 0.0), seed)
}

fn run(scene: &Scene, sub_windows: bool) -> RunOutput {
    let effects = scene.effects();
    let sim = Simulation::new(scene, &effects)
        .unwrap()
        .with_sub_windows(sub_windows)
        // Members that keep apart on separate clocks (session 32) would take most of
        // what the sub-windows save here: one clock per group, as when they were built.
        .with_separate_clocks(false);
    assert_eq!(sim.scheduler_in_use(), "windows");
    sim.run(&|_| {})
}

/// 120 shots in the bore and the jet for 3 ms, fed 25 us apart: they share islands (the
/// bore wall may kick them), but none touches another, the wall or the specimen.
#[test]
fn without_contacts_sub_windows_give_the_same_states_to_the_tolerance() {
    let scene = stream(3.0, 1);
    // The islands really were cut: fewer shot-steps. Same motion to the tolerance.
    // Measured (session 31): 1.2e-6 m and 2.3e-5.
    common::same_states_for_fewer_steps(&run(&scene, false), &run(&scene, true), 1.0);
}

/// A colliding stream (1,000 shots, 30 ms; rebounds meet incoming shots), three seeds:
/// the first hits' distributions agree within their noise, for at least 20 % fewer
/// shot-steps. Measured (session 31): mean normal speed 45.70 / 45.13 m/s on seed 1,
/// shot-steps 363,817 / 228,353; the seed-to-seed spread of the mean is about 0.5 %.
#[test]
fn with_collisions_sub_windows_keep_the_distributions_for_fewer_steps() {
    common::same_hits_for_fewer_steps(|seed| stream(30.0, seed), run, 1..=3, 0.8);
}
