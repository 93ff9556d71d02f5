//! Hertz contact against theory. A steel shot (0.8 mm, 7850 kg/m^3, E = 210 GPa,
//! nu = 0.3) hits the steel specimen or another shot; no air, no gravity.
//! * undamped: contact time `2.9432 delta_max / v` and peak overlap
//!   `(5 m* v^2 / (4 K))^(2/5)` within 1 %;
//! * damped: restitution 0.3, 0.7, 0.9 returned within 0.5 % at 10, 70, 150 m/s, shot on
//!   specimen and shot on shot;
//! * shot-shot: momentum conserved to round-off (1e-12 relative), energy within 0.1 %
//!   when undamped.

use crate::common;
use common::*;
use peenflow::Vec3;
use peenflow::contact::{HertzLaw, PairContact, effective_mass, hertz};
use peenflow::integrate::island::{IslandOutput, IslandPair, Scratch, advance_observed};

const D: f64 = 0.8e-3;
const R: f64 = 0.4e-3;

struct Trace {
    t: Vec<f64>,
    gap: Vec<f64>,
}

impl Trace {
    /// Linear-interpolated time at which the gap turns positive after the onset.
    fn separation(&self, t_on: f64) -> f64 {
        for k in 1..self.t.len() {
            if self.t[k] > t_on && self.gap[k - 1] <= 0.0 && self.gap[k] > 0.0 {
                let f = -self.gap[k - 1] / (self.gap[k] - self.gap[k - 1]);
                return self.t[k - 1] + f * (self.t[k] - self.t[k - 1]);
            }
        }
        panic!("no separation");
    }

    /// Peak overlap, refined by a parabola through the three samples around the minimum.
    fn peak_overlap(&self) -> f64 {
        let k = (1..self.gap.len() - 1)
            .min_by(|&a, &b| self.gap[a].total_cmp(&self.gap[b]))
            .unwrap();
        let (t0, t1, t2) = (self.t[k - 1], self.t[k], self.t[k + 1]);
        let (g0, g1, g2) = (self.gap[k - 1], self.gap[k], self.gap[k + 1]);
        // Parabola through three points: vertex value.
        let d01 = (g1 - g0) / (t1 - t0);
        let d12 = (g2 - g1) / (t2 - t1);
        let a = (d12 - d01) / (t2 - t0);
        let b = d01 - a * (t0 + t1);
        let tv = -b / (2.0 * a);
        let gv = g1 + (tv - t1) * (b + a * (tv + t1));
        -gv.min(g1)
    }
}

/// Shot on the specimen at normal speed `v`; returns (trace, onset time, final vz).
fn shot_on_specimen(e: f64, v: f64) -> (Trace, f64, f64) {
    let phys = contact_physics(Some(e), None);
    let gap0 = 0.1e-3;
    let mut members = vec![shot(
        0,
        D,
        Vec3::new(0.0, 0.0, R + gap0),
        Vec3::new(0.0, 0.0, -v),
    )];
    let mut tr = Trace {
        t: vec![],
        gap: vec![],
    };
    let mut out = IslandOutput::default();
    let t_end = gap0 / v + 20e-6;
    advance_observed(
        &phys,
        &mut members,
        &mut [],
        0.0,
        t_end,
        &mut Scratch::default(),
        &mut out,
        &mut |t, y| {
            tr.t.push(t);
            tr.gap.push(y[2] - R);
        },
    );
    assert_eq!(out.impacts.len(), 1);
    (tr, out.impacts[0].time_s, members[0].vel.z)
}

/// Head-on pair at closing speed `v` (diameters `d1`, `d2`); returns the trace of the
/// gap, the onset time (from the trace), final states and initial momentum/energy.
fn shot_on_shot(
    e: f64,
    v: f64,
    d1: f64,
    d2: f64,
) -> (Trace, Vec<peenflow::state::ShotState>, Vec3, f64) {
    let phys = contact_physics(None, Some(e));
    let gap0 = 0.1e-3;
    let x2 = 0.5 * (d1 + d2) + gap0;
    let mut members = vec![
        shot(
            0,
            d1,
            Vec3::new(0.0, 0.0, 0.01),
            Vec3::new(0.5 * v, 0.0, 0.0),
        ),
        shot(
            1,
            d2,
            Vec3::new(-x2, 0.0, 0.01),
            Vec3::new(-0.5 * v, 0.0, 0.0),
        ),
    ];
    // Mirror so shot 1 comes from -x: it moves +x, shot 0 moves -x.
    members[0].vel = Vec3::new(-0.5 * v, 0.0, 0.0);
    members[1].vel = Vec3::new(0.5 * v, 0.0, 0.0);
    let p0: Vec3 = members.iter().map(|m| m.vel * m.body.mass).sum();
    let e0: f64 = members
        .iter()
        .map(|m| 0.5 * m.body.mass * m.vel.norm_squared())
        .sum();
    let mut pairs = vec![IslandPair {
        a: 0,
        b: 1,
        touching: false,
        contact_time: 0.0,
        onset: 0.0,
        ..Default::default()
    }];
    let mut tr = Trace {
        t: vec![0.0],
        gap: vec![gap0],
    };
    let mut out = IslandOutput::default();
    let t_end = gap0 / v + 20e-6;
    let (r1, r2) = (0.5 * d1, 0.5 * d2);
    advance_observed(
        &phys,
        &mut members,
        &mut pairs,
        0.0,
        t_end,
        &mut Scratch::default(),
        &mut out,
        &mut |t, y| {
            let dx = Vec3::new(y[0] - y[6], y[1] - y[7], y[2] - y[8]);
            tr.t.push(t);
            tr.gap.push(dx.norm() - r1 - r2);
        },
    );
    assert_eq!(out.work.contact_onsets, 1);
    (tr, members, p0, e0)
}

/// Onset: where the gap crosses zero, linearly interpolated between the two samples
/// around it (steps there are a fiftieth of the contact time).
fn onset_from_trace(tr: &Trace) -> f64 {
    let k = tr.gap.iter().position(|&g| g < 0.0).unwrap();
    let f = tr.gap[k - 1] / (tr.gap[k - 1] - tr.gap[k]);
    tr.t[k - 1] + f * (tr.t[k] - tr.t[k - 1])
}

#[test]
fn undamped_specimen_impact_matches_hertz_time_and_overlap() {
    let law = HertzLaw::new(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL, 1.0);
    let m = shot(0, D, Vec3::zeros(), Vec3::zeros()).body.mass;
    for v in [10.0, 70.0, 150.0] {
        let k = law.stiffness(R);
        let (tr, t_on, vz) = shot_on_specimen(1.0, v);
        let tc = tr.separation(t_on) - t_on;
        let tc_theory = hertz::contact_time(m, k, v);
        let dmax = tr.peak_overlap();
        let dmax_theory = hertz::peak_overlap(m, k, v);
        println!(
            "v {v}: contact {tc:.5e} s (theory {tc_theory:.5e}), peak overlap {dmax:.5e} m (theory {dmax_theory:.5e}), rebound {vz}"
        );
        assert!(
            rel(tc, tc_theory) < 0.01,
            "contact time {tc} vs {tc_theory}"
        );
        assert!(
            rel(dmax, dmax_theory) < 0.01,
            "peak overlap {dmax} vs {dmax_theory}"
        );
        assert!(rel(vz, v) < 1e-3, "undamped rebound {vz} vs {v}");
    }
    // model-notes: 0.8 mm steel at 70 m/s on steel: ~1.2 us, peak overlap ~28 um... with
    // E* of steel on steel; LIGGGHTS measured 1.22 us. Check our theory values are that.
    let k = law.stiffness(R);
    assert!((1.1e-6..1.3e-6).contains(&hertz::contact_time(m, k, 70.0)));
}

#[test]
fn hertz_time_constant_is_the_integral() {
    // 2 * int_0^1 (1 - x^2.5)^(-1/2) dx, by substitution x = 1 - u^2 (removes the
    // endpoint singularity) and composite Simpson.
    let n = 200_000;
    let f = |u: f64| {
        let x: f64 = 1.0 - u * u;
        if u == 0.0 {
            // limit: 2u / sqrt(1 - x^2.5) -> 2 / sqrt(2.5)
            2.0 / 2.5f64.sqrt()
        } else {
            2.0 * u / (1.0 - x.powf(2.5)).sqrt()
        }
    };
    let h = 1.0 / n as f64;
    let mut s = f(0.0) + f(1.0);
    for i in 1..n {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    let integral = s * h / 3.0;
    assert!(
        (2.0 * integral - hertz::HERTZ_TIME_CONSTANT).abs() < 1e-6,
        "{}",
        2.0 * integral
    );
}

#[test]
fn damped_specimen_impacts_return_the_requested_restitution() {
    for e in [0.3, 0.7, 0.9] {
        for v in [10.0, 70.0, 150.0] {
            let (_, _, vz) = shot_on_specimen(e, v);
            let got = vz / v;
            println!("specimen e {e} v {v}: {got:.6}");
            assert!(rel(got, e) < 0.005, "e = {e} at {v} m/s gave {got}");
        }
    }
}

#[test]
fn damped_shot_shot_impacts_return_the_requested_restitution() {
    // Equal shots, and unequal ones (a sieve distribution's mix): the damping is
    // calibrated on the pair's effective mass and radius, so the same e comes back.
    for (d1, d2) in [(D, D), (D, 0.5e-3), (1.2e-3, 0.6e-3)] {
        for e in [0.3, 0.7, 0.9] {
            for v in [10.0, 70.0, 150.0] {
                let (_, m, _, _) = shot_on_shot(e, v, d1, d2);
                // shot 0 came from +x moving -x, shot 1 from -x moving +x, each at v/2.
                let got = (m[0].vel.x - m[1].vel.x) / v;
                println!("pair {d1} / {d2} e {e} v {v}: {got:.6}");
                assert!(rel(got, e) < 0.005, "e = {e} at {v} m/s gave {got}");
            }
        }
    }
}

#[test]
fn shot_shot_collisions_conserve_momentum_and_undamped_energy() {
    for (e, d2) in [(1.0, D), (1.0, 0.5e-3), (0.7, 0.5e-3), (0.9, 1.0e-3)] {
        let (tr, m, p0, e0) = shot_on_shot(e, 70.0, D, d2);
        let p1: Vec3 = m.iter().map(|s| s.vel * s.body.mass).sum();
        let e1: f64 = m
            .iter()
            .map(|s| 0.5 * s.body.mass * s.vel.norm_squared())
            .sum();
        let scale = m[0].body.mass * 70.0;
        println!(
            "e {e} d2 {d2}: |dp|/(m v) = {:.2e}, E1/E0 = {:.8}",
            (p1 - p0).norm() / scale,
            e1 / e0
        );
        assert!(
            (p1 - p0).norm() / scale < 1e-12,
            "momentum drift {}",
            (p1 - p0).norm()
        );
        if e == 1.0 {
            assert!(rel(e1, e0) < 1e-3, "energy {e1} vs {e0}");
            // and the contact matches Hertz with effective mass and radius
            let law = HertzLaw::new(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL, 1.0);
            let k = law.stiffness(PairContact::effective_radius(0.5 * D, 0.5 * d2));
            let meff = effective_mass(m[0].body.mass, m[1].body.mass);
            let t_on = onset_from_trace(&tr);
            let tc = tr.separation(t_on) - t_on;
            assert!(rel(tc, hertz::contact_time(meff, k, 70.0)) < 0.01);
            assert!(rel(tr.peak_overlap(), hertz::peak_overlap(meff, k, 70.0)) < 0.01);
        } else {
            assert!(e1 < e0);
        }
    }
}

/// An impact's rebound through the island integrator (the window and independent
/// schedulers) at the default floor of 10 steps per contact, at loose tolerances too: a
/// head-on 70 m/s impact on the specimen (restitution 0.7) and between two shots (0.9),
/// against the requested restitution, which the Tsuji law returns exactly. Specimen:
/// within a fifth of the tolerance, or 2e-5 (measured since session 13, where the first
/// step after the touch is corrected and grows with the tolerance: 1.4e-4, 1.6e-6,
/// 4.7e-6, 2.3e-6, 7e-8 at tolerances 1e-3 ... 1e-8; with the fixed 1 % first step
/// before, 0.3e-6 to 1.0e-5; before session 6, where the second step after the onset
/// jumped to a whole contact step, 5.4e-4 at tolerances 1e-3 to 1e-5). Pair: within
/// twice the tolerance, or 5e-6 (measured 8.3e-4, 1.7e-5, 1.2e-6, 9.2e-7, 0; before
/// session 6, when a step could carry a pair past both its kink and its parting
/// unlocated and the touch itself was not located: 5.4e-3 at 1e-3, 2.3e-4 at 1e-4,
/// 3.4e-5 at 1e-6).
#[test]
fn impact_rebounds_are_accurate_at_loose_tolerances() {
    use peenflow::sim::{Scheduler, Simulation};
    for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-8] {
        let mut phys = contact_physics(Some(0.7), None);
        phys.tolerance = tol;
        phys.contact_steps = 10.0;
        let shots = vec![shot(
            0,
            D,
            Vec3::new(0.0, 0.0, 0.5e-3),
            Vec3::new(0.0, 0.0, -70.0),
        )];
        let out = Simulation::from_parts(phys, shots, 1e-5).run(&|_| {});
        let e = out.shots[0].vel.z / 70.0;
        println!(
            "specimen, tolerance {tol:e}: restitution {e:.8} ({})",
            out.scheduler
        );
        assert!(rel(e, 0.7) < (0.2 * tol).max(2e-5), "{e}");
        let mut phys = contact_physics(None, Some(0.9));
        phys.tolerance = tol;
        phys.contact_steps = 10.0;
        let shots = vec![
            shot(0, D, Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0)),
            shot(1, D, Vec3::new(0.0, 0.0, 6e-3), Vec3::new(0.0, 0.0, -70.0)),
        ];
        let out = Simulation::from_parts(phys, shots, 2e-5)
            .with_scheduler(Scheduler::Windows)
            .run(&|_| {});
        let e = (out.shots[1].vel.z - out.shots[0].vel.z) / 119.0;
        println!(
            "pair, tolerance {tol:e}: restitution {e:.8} ({})",
            out.scheduler
        );
        assert!(rel(e, 0.9) < (2.0 * tol).max(5e-6), "{e}");
    }
}

/// The same for a shot hitting the nozzle bore at 20 m/s (restitution 0.7, no air): within
/// the tolerance, or 1e-5 (measured since session 13: 9.3e-4, 3.0e-5, 8.7e-6, 6.3e-6,
/// 6e-8 at tolerances 1e-3 ... 1e-8). The 6e-6 at 1e-5 and 1e-6 is the in-contact
/// steps' (10 per contact: 20 give 5.5e-7, 40 give 6e-8; the error estimate underrates
/// it); until session 12 an uncorrected first step of opposite sign hid half of it
/// (7e-4, 2.1e-6, 3.5e-6, 3.3e-6, 1.6e-7). Before session 6, when neither the wall touch
/// nor its kink was located: 3.8e-3, 1.2e-5, 2.9e-4, 5.9e-7, 3.4e-6.
#[test]
fn nozzle_wall_rebounds_are_accurate_at_loose_tolerances() {
    use peenflow::scene::Scene;
    use peenflow::sim::Simulation;
    for tol in [1e-3f64, 1e-4, 1e-5, 1e-6, 1e-8] {
        let text = format!(
            "duration_ms = 0.3\ngravity_m_s2 = 0.0\n[shots]\ndiameter_mm = 0.8\nmaterial = \"table2-steel\"\n[shots.feed]\ntype = \"list\"\n[[shots.feed.shots]]\nposition_mm = [0.0, 0.0, 120.0]\nvelocity_m_s = [20.0, 0.0, 0.0]\n[restitution]\nshot_nozzle = 0.7\n[integrator]\ntolerance = {tol}\n[effects]\ndrag = false\nlateral_force = false\ngravity = false\nspecimen_contact = false\nshot_shot_contact = false\nnozzle_wall_contact = true\n"
        );
        let scene = Scene::from_toml(&text, "wall").unwrap();
        let out = Simulation::new(&scene, &scene.effects())
            .unwrap()
            .run(&|_| {});
        let s = &out.shots[0];
        assert_eq!(s.wall_contacts, 1);
        let e = -s.vel.x / 20.0;
        println!("wall, tolerance {tol:e}: restitution {e:.8}");
        assert!(rel(e, 0.7) < tol.max(1e-5), "{e}");
        assert!(s.vel.y.abs() < 1e-9 && s.vel.z.abs() < 1e-9);
    }
}
