//! Session 39: a bed's or a pile's contacts, opening and closing at millimetres per
//! second, no longer cut their island's steps one by one.
//! - A contact's kink (where its damped force would turn to pulling and is clamped at
//!   zero) ends a step only where a step that ran over it could miss more than a tenth of
//!   what the tolerance allows (`HertzLaw::kink_slope`, `dopri::KINK_MISS`).
//! - A slow touch (closing below 0.1 m/s, not located) caps the step it falls in, and the
//!   step after it, to its span (`HertzLaw::touch_span`), not to 0.1 % of a contact time.
//!
//! The runs are compared with converged ones (tolerance 1e-10, 40 steps per contact).

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

fn bed(nx: usize, diameter_mm: f64, squeeze: f64, ms: f64, friction: bool) -> String {
    let friction = if friction {
        "[friction]\nshot_specimen = 0.3\nshot_shot = 0.3\n"
    } else {
        ""
    };
    format!(
        "title = \"bed\"\nduration_ms = {ms}\n[shots]\ndiameter_mm = {diameter_mm}\n\
        [shots.feed]\ntype = \"bed\"\nnx = {nx}\nny = {nx}\nlayers = 6\nsqueeze = {squeeze}\n\
        [restitution]\nshot_specimen = 0.7\nshot_shot = 0.9\n{friction}\
        [effects]\ndrag = false\nlateral_force = false\ngravity = true\n\
        specimen_contact = true\nshot_shot_contact = true\nnozzle_wall_contact = false\n"
    )
}

/// The run of `text`, and the converged one.
fn with_reference(text: &str) -> (RunOutput, RunOutput) {
    let run = |t: &str| {
        let scene = Scene::from_toml(t, "bed.toml").unwrap();
        Simulation::new(&scene, &scene.effects())
            .unwrap()
            .run(&|_| {})
    };
    let tight = format!("{text}[integrator]\ntolerance = 1e-10\ncontact_steps = 40\n");
    (run(text), run(&tight))
}

/// Largest velocity error (m/s) over the shots, each over its own scale `|v| + 1 m/s`
/// (the tolerance's), and largest position error (m).
fn errors(a: &RunOutput, r: &RunOutput) -> (f64, f64, f64) {
    let (mut v, mut w, mut x) = (0.0f64, 0.0f64, 0.0f64);
    assert_eq!(a.shots.len(), r.shots.len());
    for (s, t) in a.shots.iter().zip(&r.shots) {
        let scale = t.vel.norm() + 1.0;
        v = v.max((s.vel - t.vel).norm() / scale);
        w = w.max((s.omega - t.omega).norm() * s.body.radius / scale);
        x = x.max((s.pos - t.pos).norm());
    }
    (v, w, x)
}

#[test]
fn a_squeezed_beds_slow_kinks_do_not_cut_its_steps() {
    // LIGGGHTS' dense.in with its squeeze (all twelve neighbours preloaded by 0.8 nm),
    // 768 shots of 0.8 mm with friction, 0.05 ms: its contacts chatter at millimetres
    // per second. Measured: 245 steps before session 39, 103 since; the velocity error
    // 8.2e-7 m/s before, 1.5e-7 since (spin 6.7e-8 of the contact point's speed).
    let (run, reference) = with_reference(&bed(8, 0.8, 1e-6, 0.05, true));
    assert_eq!(run.shots.len(), 768);
    assert!(
        run.work.steps_accepted <= 150,
        "{} steps: are the slow kinks located again?",
        run.work.steps_accepted
    );
    let (v, w, x) = errors(&run, &reference);
    eprintln!("velocity {v:.3e}, spin {w:.3e}, position {x:.3e} m");
    assert!(v < 1e-6, "velocity error {v:.3e} of |v| + 1 m/s");
    assert!(w < 1e-6, "spin error {w:.3e} of |v| + 1 m/s");
    assert!(x < 1e-6 * 0.8e-3, "position error {x:.3e} m");
}

#[test]
fn an_exploding_beds_kinks_are_still_located() {
    // Squeezed by 0.2 % of a diameter (1.2 um), 192 shots of 0.6 mm burst apart at up to
    // 4 m/s: their kinks are an impact's, and every one that matters ends a step.
    // Measured: the velocity error 2.4e-7 of |v| + 1 m/s (1.7e-7 before session 39); with no
    // kink located, 1e-4 m/s on the 4,800-shot version of this bed.
    let (run, reference) = with_reference(&bed(4, 0.6, 0.002, 0.002, false));
    let (v, _, x) = errors(&run, &reference);
    eprintln!("velocity {v:.3e}, position {x:.3e} m");
    let fastest = reference
        .shots
        .iter()
        .map(|s| s.vel.norm())
        .fold(0.0, f64::max);
    assert!(fastest > 2.0, "the bed must burst: {fastest} m/s");
    assert!(v < 1e-6, "velocity error {v:.3e} of |v| + 1 m/s");
    assert!(x < 1e-6 * 0.6e-3, "position error {x:.3e} m");
}
