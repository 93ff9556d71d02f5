//! Cut steps (session 32): a lone shot on the window scheduler lets its step run past the
//! window's end when nothing happens in it; a step that would run into an event is cut
//! and kept (just past a jet region's boundary, short of the specimen), instead of
//! ending at every window's end up to the event. Only the steps change.

use crate::common;

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

/// A stream fed for `feed_ms`, run until `feed_ms` plus `tail_ms` (the default seed).
fn stream(rate_per_s: f64, feed_tail_ms: (f64, f64)) -> Scene {
    common::nozzle_stream("cut steps test", rate_per_s, feed_tail_ms, 1)
}

fn run(scene: &Scene) -> RunOutput {
    let effects = scene.effects();
    Simulation::new(scene, &effects).unwrap().run(&|_| {})
}

/// Four shots fed 10 ms apart fly through the windows alone (none meets another; the
/// earlier ones bounce on the specimen, away from the axis): each takes about the steps
/// it takes in a run with no windows at all (one shot), and hits the same.
#[test]
fn a_lone_shot_through_windows_takes_the_steps_of_a_run_without_them() {
    let alone = run(&stream(400.0, (2.5, 4.0)));
    assert_eq!((alone.shots.len(), alone.windows), (1, 1));
    let four = run(&stream(100.0, (40.0, 4.0)));
    assert_eq!(four.scheduler, "windows");
    assert_eq!(four.shots.len(), 4);
    assert!(four.shots.iter().all(|s| s.collisions == 0));
    assert!(four.windows > 100, "{} windows", four.windows);
    let flight = |o: &RunOutput| -> Vec<u64> {
        o.shots
            .iter()
            .map(|s| s.steps_to_first_contact.expect("every shot hits"))
            .collect()
    };
    let (single, windowed) = (flight(&alone)[0], flight(&four));
    // Measured: 26 steps alone; through windows 59-65 before the cut (session 32:
    // window after window up to the bore's exit, each jet region's boundary and the
    // specimen), 28-31 with it, 31-34 since a kept step proposes the controller's own
    // size (session 35: it no longer brings the bore's long step back after a cut),
    // 28-30 since a step that crosses only jet region boundaries is cut just past the
    // first one and kept (session 36: before, it stopped short and the next window's
    // step ran into the boundary again).
    assert!(
        windowed.iter().all(|&n| n * 100 <= single * 120),
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
