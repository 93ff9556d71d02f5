//! Conservation laws in many-body encounters: a cloud of shots colliding in vacuum (no
//! gravity, no specimen), so that pairs, three-body clusters and the event scheduler's
//! verified chunks all take part, on each scheduler and on the fixed-step method.
//! Contact forces act in equal and opposite pairs at one point, so whatever path resolves
//! a contact (the table, the lean path, an island, a window):
//! * linear momentum is kept to round-off (1e-11 of `sum m |v|`);
//! * angular momentum about the origin, orbital plus spin, to 1e-9 of `sum m |x| |v|`
//!   with friction (the tangential force acts at the contact point);
//! * with restitution 1 and no friction, kinetic energy is kept to the integrator's error
//!   (measured over the cloud's 387 contacts at tolerance 1e-6: 2.1e-7 relative on the
//!   event scheduler, 2.9e-7 on windows; asserted 1e-5), and to the step's on velocity
//!   Verlet at 20 ns and on the hybrid method (adaptive in flight, 20 ns steps in
//!   contacts) (measured 9e-7; asserted 1e-3);
//! * with losses (restitution 0.7, or friction 0.3 on an elastic normal law) it never
//!   grows (measured: 0.68 and 0.77 of the start).

use crate::common;

use common::{contact_physics, shot};
use peenflow::Vec3;
use peenflow::contact::Friction;
use peenflow::contact::friction::Tangential;
use peenflow::integrate::Physics;
use peenflow::integrate::island::Method;
use peenflow::sim::{RunOutput, Scheduler, Simulation};
use peenflow::state::ShotState;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const D: f64 = 0.8e-3;

/// 216 shots of 0.8 mm on a 6 x 6 x 6 lattice 1.3 diameters apart (24 % volume fraction),
/// each nudged by up to a tenth of a diameter, moving at up to 20 m/s in random
/// directions: a few hundred contacts in 0.3 ms, many of them in groups of three or more.
fn cloud(seed: u64) -> Vec<ShotState> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut shots = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            for k in 0..6 {
                let mut jitter = || rng.random_range(-0.1..0.1) * D;
                let p = Vec3::new(
                    1.3 * D * f64::from(i) + jitter(),
                    1.3 * D * f64::from(j) + jitter(),
                    0.01 + 1.3 * D * f64::from(k) + jitter(),
                );
                let v = loop {
                    let v = Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    if v.norm() <= 1.0 {
                        break v * 20.0;
                    }
                };
                shots.push(shot(shots.len() as u32, D, p, v));
            }
        }
    }
    shots
}

fn physics(restitution: f64, friction: f64, law: Tangential, method: Method) -> Physics {
    let mut phys = contact_physics(None, Some(restitution));
    if friction > 0.0 {
        phys.contacts.friction = Some(Friction {
            specimen: friction,
            shot: friction,
            wall: friction,
            law,
        });
    }
    phys.method = method;
    phys
}

fn run(phys: Physics, shots: Vec<ShotState>, scheduler: Scheduler) -> RunOutput {
    let out = Simulation::from_parts(phys, shots, 3e-4)
        .with_scheduler(scheduler)
        .run(&|_| {});
    assert!(out.events.is_empty(), "{:?}", out.events);
    out
}

struct Totals {
    momentum: Vec3,
    angular: Vec3,
    energy: f64,
    /// Scales for the round-off bounds: `sum m |v|` and `sum m |x| |v|`.
    p_scale: f64,
    l_scale: f64,
}

fn totals(shots: &[ShotState]) -> Totals {
    let mut t = Totals {
        momentum: Vec3::zeros(),
        angular: Vec3::zeros(),
        energy: 0.0,
        p_scale: 0.0,
        l_scale: 0.0,
    };
    for s in shots {
        let m = s.body.mass;
        let i = 0.4 * m * s.body.radius * s.body.radius;
        t.momentum += s.vel * m;
        t.angular += s.pos.cross(&(s.vel * m)) + s.omega * i;
        t.energy += 0.5 * m * s.vel.norm_squared() + 0.5 * i * s.omega.norm_squared();
        t.p_scale += m * s.vel.norm();
        t.l_scale += m * s.pos.norm() * s.vel.norm();
    }
    t
}

/// Runs the cloud and checks momentum and angular momentum; returns the run and the
/// kinetic energy at the end over the start.
fn conserved(
    label: &str,
    restitution: f64,
    friction: f64,
    method: Method,
    scheduler: Scheduler,
) -> (RunOutput, f64) {
    conserved_with(
        label,
        restitution,
        (friction, Tangential::Viscous),
        method,
        scheduler,
    )
}

/// [`conserved`] with the tangential law `law`.
fn conserved_with(
    label: &str,
    restitution: f64,
    (friction, law): (f64, Tangential),
    method: Method,
    scheduler: Scheduler,
) -> (RunOutput, f64) {
    let shots = cloud(7);
    let before = totals(&shots);
    let out = run(
        physics(restitution, friction, law, method),
        shots,
        scheduler,
    );
    let after = totals(&out.shots);
    let contacts = out.work.contact_onsets;
    let dp = (after.momentum - before.momentum).norm() / before.p_scale;
    let dl = (after.angular - before.angular).norm() / before.l_scale;
    let ratio = after.energy / before.energy;
    println!(
        "{label}: {} scheduler, {contacts} contacts, {} clusters; momentum {dp:.1e}, angular momentum {dl:.1e}, energy ratio {ratio:.9}",
        out.scheduler, out.work.clusters
    );
    assert!(contacts > 200, "{label}: only {contacts} contacts");
    assert!(dp < 1e-11, "{label}: momentum changed by {dp:e}");
    assert!(dl < 1e-9, "{label}: angular momentum changed by {dl:e}");
    (out, ratio)
}

#[test]
fn a_colliding_cloud_keeps_momentum_and_elastic_energy_on_every_scheduler() {
    let verlet = Method::Verlet { step: 20e-9 };
    let hybrid = Method::Hybrid { step: 20e-9 };
    for (label, method, scheduler, allowed) in [
        ("events", Method::Adaptive, Scheduler::Events, 1e-5),
        ("windows", Method::Adaptive, Scheduler::Windows, 1e-5),
        ("verlet", verlet, Scheduler::Windows, 1e-3),
        ("verlet on events", verlet, Scheduler::Events, 1e-3),
        ("hybrid", hybrid, Scheduler::Windows, 1e-3),
        ("hybrid on events", hybrid, Scheduler::Events, 1e-3),
    ] {
        let (out, ratio) = conserved(label, 1.0, 0.0, method, scheduler);
        assert!(
            (ratio - 1.0).abs() < allowed,
            "{label}: elastic energy ratio {ratio}"
        );
        if scheduler == Scheduler::Events {
            // The cloud's many-body encounters go through verified clusters, not only
            // through binary contacts.
            assert!(out.work.clusters > 10, "{} clusters", out.work.clusters);
        }
    }
}

#[test]
fn a_colliding_cloud_loses_energy_with_losses_and_keeps_its_momenta() {
    for (label, scheduler) in [
        ("events", Scheduler::Events),
        ("windows", Scheduler::Windows),
    ] {
        let (_, lossy) = conserved(label, 0.7, 0.0, Method::Adaptive, scheduler);
        assert!(
            lossy < 1.0,
            "{label}: lossy contacts gained energy ({lossy})"
        );
        // Friction alone (elastic normal law): energy goes into spin and slip, and the
        // total never grows; angular momentum now includes the spins it creates.
        let (out, rough) = conserved(label, 1.0, 0.3, Method::Adaptive, scheduler);
        assert!(
            rough < 1.0 + 1e-5,
            "{label}: friction gained energy ({rough})"
        );
        assert!(
            out.shots.iter().any(|s| s.omega.norm() > 100.0),
            "{label}: friction spun no shot"
        );
    }
}

/// The tangential spring with history (`tangential = "history"`, on the fixed-step and
/// hybrid methods, on windows and on the event scheduler): its
/// force acts in equal and opposite pairs at the contact point, so momentum and angular
/// momentum (orbital plus spin) are kept as with the viscous law; it spins the shots and
/// takes energy out of an elastic normal law (measured: 0.78 of the start, the viscous
/// law 0.77).
#[test]
fn the_history_law_keeps_the_clouds_momenta() {
    // Steel on steel: G* / E* = (1 - nu) / (2 (2 - nu)).
    let g = peenflow::contact::friction::shear_ratio(210e9, 0.3, 210e9, 0.3);
    let law = Tangential::History {
        specimen: g,
        shot: g,
        wall: g,
    };
    let (verlet, hybrid) = (
        Method::Verlet { step: 20e-9 },
        Method::Hybrid { step: 20e-9 },
    );
    for (method, scheduler) in [
        (verlet, Scheduler::Windows),
        (verlet, Scheduler::Events),
        (hybrid, Scheduler::Windows),
        (hybrid, Scheduler::Events),
    ] {
        let label = format!("history, {}", method.name());
        let (out, rough) = conserved_with(&label, 1.0, (0.3, law), method, scheduler);
        assert!(rough < 1.0, "the history law gained energy ({rough})");
        assert!(
            out.shots.iter().any(|s| s.omega.norm() > 100.0),
            "the history law spun no shot"
        );
    }
}
