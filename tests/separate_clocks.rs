//! Separate clocks (session 32, taken out then and back in session 34): the window
//! scheduler steps the members of an island that keep apart each on its own clock
//! (`sim::advance_apart`), checked pair by pair afterwards. Only the steps change:
//! without shot-shot contact the states agree with one clock per island to the
//! integrator's tolerance, shot by shot; with collisions (chaotic) the distributions
//! agree within their sampling noise, for fewer shot-steps. (Over 96 seeds of the
//! 10,000-shot stream both sit within 0.1 % of the converged reference:
//! docs/performance-history.md, session 33.)

use crate::common;

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

/// A stream fed for `feed_ms`, run until `feed_ms` plus `tail_ms`.
fn stream(rate_per_s: f64, feed_tail_ms: (f64, f64), seed: u64) -> Scene {
    common::nozzle_stream("separate clocks test", rate_per_s, feed_tail_ms, seed)
}

fn run(scene: &Scene, separate: bool) -> RunOutput {
    let effects = scene.effects();
    let sim = Simulation::new(scene, &effects)
        .unwrap()
        .with_separate_clocks(separate);
    assert_eq!(sim.scheduler_in_use(), "windows");
    sim.run(&|_| {})
}

/// 120 shots in the bore and the jet for 3 ms, fed 25 us apart: they share islands (the
/// bore wall may kick them), but none touches another, the wall or the specimen.
#[test]
fn without_contacts_separate_clocks_give_the_same_states_to_the_tolerance() {
    let scene = stream(40_000.0, (3.0, 0.0), 1);
    // Measured (session 32): 4,161 / 2,602 shot-steps; 7.8e-7 m and 1.4e-5.
    common::same_states_for_fewer_steps(&run(&scene, false), &run(&scene, true), 0.8);
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
