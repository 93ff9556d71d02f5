//! The event scheduler (`peenflow::events`) against the window scheduler and theory:
//! exact free flight, the same contact resolution, the same statistics on a falling pack,
//! free flight without integrator steps, thread independence, and its scene errors.

use crate::common;

use common::{contact_physics, rel, shot};
use peenflow::Vec3;
use peenflow::forces::GravityModel;
use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Scheduler, Simulation};
use peenflow::state::ShotState;

fn run(
    phys: peenflow::integrate::Physics,
    shots: Vec<ShotState>,
    end: f64,
    s: Scheduler,
) -> RunOutput {
    Simulation::from_parts(phys, shots, end)
        .with_scheduler(s)
        .run(&|_| {})
}

/// Two 0.8 mm shots meeting off-centre in vacuum at 70 m/s, run with scheduler `s`
/// (events: on the lean contact path or not) at tolerance `tol`.
fn off_centre_pair(tol: f64, s: Scheduler, lean: bool) -> RunOutput {
    let d = 0.8e-3;
    let shots = vec![
        shot(0, d, Vec3::new(0.0, 0.0, 0.01), Vec3::new(30.0, 0.0, 0.0)),
        shot(
            1,
            d,
            Vec3::new(0.004, 0.0003, 0.01),
            Vec3::new(-40.0, 0.0, 0.0),
        ),
    ];
    let mut phys = contact_physics(None, Some(0.9));
    phys.tolerance = tol;
    Simulation::from_parts(phys, shots, 3e-4)
        .with_scheduler(s)
        .with_lean_contacts(lean)
        .run(&|_| {})
}

/// Two shots meeting off-centre in vacuum: the event scheduler resolves the contact on
/// its lean path (events/binary.rs, the same force law and error control as the island
/// integrator), so at a tight tolerance (1e-10) its outgoing velocities are the window
/// scheduler's to 1e-7 of the closing speed, and at the default tolerance (1e-6) both
/// schedulers are within 1e-4 of the converged result (they take different steps into
/// the contact). Momentum is conserved.
#[test]
fn a_binary_collision_matches_the_window_scheduler() {
    let closing = 70.0;
    let at = |tol: f64, s: Scheduler| off_centre_pair(tol, s, true);
    let (a, b) = (at(1e-6, Scheduler::Events), at(1e-6, Scheduler::Windows));
    let (a_ref, b_ref) = (at(1e-10, Scheduler::Events), at(1e-10, Scheduler::Windows));
    assert_eq!(a.scheduler, "events");
    assert_eq!(b.scheduler, "windows");
    for k in 0..2 {
        let (x, y) = (&a_ref.shots[k], &b_ref.shots[k]);
        assert!(
            (x.vel - y.vel).norm() < 1e-7 * closing,
            "{:?} vs {:?}",
            x.vel,
            y.vel
        );
        for o in [&a, &b] {
            assert_eq!(o.shots[k].collisions, 1);
            let err = (o.shots[k].vel - x.vel).norm() / closing;
            assert!(err < 1e-4, "{}: {err:e}", o.scheduler);
        }
        // The window scheduler integrates free flight to its tolerance (1e-6 per step);
        // the event scheduler's free flight is exact.
        let travel = closing * 3e-4;
        assert!(
            (x.pos - y.pos).norm() < 1e-5 * travel,
            "{:?} vs {:?}",
            x.pos,
            y.pos
        );
    }
    let p = a.shots[0].vel + a.shots[1].vel;
    assert!(
        (p - Vec3::new(-10.0, 0.0, 0.0)).norm() < 1e-9 * closing,
        "{p:?}"
    );
    // Free flight costs no steps: only the contact (and the step before it) does.
    assert!(a.work.shot_steps < b.work.shot_steps);
}

/// A shot dropped onto the specimen under gravity: free flight is exact, so the recorded
/// impact speed is sqrt(v0^2 + 2 g h) to rounding, and the rebound obeys restitution.
#[test]
fn free_fall_onto_the_specimen_is_exact() {
    let d = 0.8e-3;
    let g = 9.81;
    let mut phys = contact_physics(Some(0.7), Some(0.9));
    phys.forces.gravity = Some(GravityModel {
        acceleration: Vec3::new(0.0, 0.0, -g),
    });
    let h0 = 0.02;
    let v0 = -3.0;
    let shots = vec![
        shot(0, d, Vec3::new(0.0, 0.0, h0), Vec3::new(0.5, 0.0, v0)),
        // A far companion so that shot-shot contact is on and the scheduler matters.
        shot(1, d, Vec3::new(0.05, 0.0, 0.05), Vec3::zeros()),
    ];
    let out = run(phys, shots, 8e-3, Scheduler::Events);
    assert_eq!(out.scheduler, "events");
    let first = out.impacts.iter().find(|i| i.shot == 0).expect("no impact");
    let fall = h0 - 0.5 * d;
    let vz = (v0 * v0 + 2.0 * g * fall).sqrt();
    let t = (vz + v0) / g; // v0 < 0: time to fall `fall`
    assert!(rel(-first.vz_m_s, vz) < 1e-12, "{} vs {vz}", first.vz_m_s);
    assert!((first.time_s - t).abs() < 1e-12, "{} vs {t}", first.time_s);
    assert!((first.vx_m_s - 0.5).abs() < 1e-12);
    // The rebound, read at the end after free flight back up: e vz (Tsuji damping gives
    // a speed-independent restitution); gravity during the 1 us contact is negligible.
    let s = &out.shots[0];
    let up = s.vel.z + g * (8e-3 - first.time_s);
    assert!(rel(up, 0.7 * vz) < 2e-3, "{up} vs {}", 0.7 * vz);
    assert!((s.vel.x - 0.5).abs() < 1e-12);
    assert_eq!(out.work.late_contacts, 0);
}

fn pack(count: usize, side_mm: f64, scheduler: &str) -> Scene {
    let text = format!(
        r#"
title = "falling pack"
duration_ms = 0.12
[shots]
diameter_mm = 0.8
material = "table2-steel"
[shots.feed]
type = "box"
count = {count}
min_mm = [0.0, 0.0, 1.0]
max_mm = [{side_mm}, {side_mm}, 8.0]
velocity_m_s = [0.0, 0.0, -70.0]
[restitution]
shot_specimen = 0.7
shot_shot = 0.9
[integrator]
scheduler = "{scheduler}"
[effects]
drag = false
lateral_force = false
gravity = true
specimen_contact = true
shot_shot_contact = true
nozzle_wall_contact = false
"#
    );
    Scene::from_toml(&text, "pack").unwrap()
}

fn simulate(scene: &Scene) -> RunOutput {
    Simulation::new(scene, &scene.effects())
        .unwrap()
        .run(&|_| {})
}

/// Three seeds of a 300-shot falling pack with scheduler `sch`, pooled: impacts, contacts,
/// mean impact speed, contacts on the lean path, contacts found overlapping.
fn pack_stats(sch: &str, lean: bool) -> (f64, f64, f64, f64, f64) {
    let (mut impacts, mut onsets, mut speed, mut on_lean, mut late) = (0usize, 0u64, 0.0, 0, 0);
    for seed in 1..=3 {
        let mut scene = pack(300, 13.0, sch);
        scene.seed = seed;
        let out = Simulation::new(&scene, &scene.effects())
            .unwrap()
            .with_lean_contacts(lean)
            .run(&|_| {});
        assert_eq!(out.scheduler, sch);
        impacts += out.impacts.len();
        onsets += out.work.contact_onsets;
        on_lean += out.work.lean_contacts;
        late += out.work.late_contacts;
        speed += out.impacts.iter().map(|i| i.speed_m_s).sum::<f64>();
    }
    (
        impacts as f64,
        onsets as f64,
        speed / impacts as f64,
        on_lean as f64,
        late as f64,
    )
}

/// A falling pack (LIGGGHTS' stream.in in small): collisions make single trajectories
/// chaotic, so the two schedulers are compared on distributions (seeds pooled): impact
/// and contact counts within 3 %, mean impact speed within 1 %, and the share of
/// contacts the event scheduler found already overlapping below 0.2 %.
#[test]
fn a_falling_pack_has_the_window_schedulers_statistics() {
    let ev = pack_stats("events", true);
    let win = pack_stats("windows", true);
    eprintln!("events {ev:?}\nwindows {win:?}");
    assert!(rel(ev.0, win.0) < 0.03, "impacts {} vs {}", ev.0, win.0);
    assert!(rel(ev.1, win.1) < 0.03, "contacts {} vs {}", ev.1, win.1);
    assert!(
        rel(ev.2, win.2) < 0.01,
        "mean impact speed {} vs {}",
        ev.2,
        win.2
    );
    assert!(ev.4 / ev.1 < 2e-3, "late contacts {} of {}", ev.4, ev.1);
}

/// Sequential and ordered by (time, kind, shots): the same bytes on 1 and 2 threads.
#[test]
fn the_event_scheduler_does_not_depend_on_threads() {
    let scene = pack(200, 11.0, "events");
    let go = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| simulate(&scene))
    };
    let (a, b) = (go(1), go(2));
    assert_eq!(a.impacts, b.impacts);
    assert_eq!(a.shots, b.shots);
    assert_eq!(a.work, b.work);
}

/// Auto picks events for ballistic scenes and windows for the air jet; an explicit
/// "events" on a scene with air is a scene error naming the key and the reason.
#[test]
fn scheduler_choice_and_errors() {
    let scene = pack(20, 6.0, "auto");
    let sim = Simulation::new(&scene, &scene.effects()).unwrap();
    assert_eq!(sim.scheduler_in_use(), "events");
    let def = Scene::default_scene();
    let sim = Simulation::new(&def, &def.effects()).unwrap();
    assert_eq!(sim.scheduler_in_use(), "windows");
    let text = def
        .text
        .replace("scheduler = \"auto\"", "scheduler = \"events\"");
    let bad = Scene::from_toml(&text, "air.toml").unwrap();
    let err = Simulation::new(&bad, &bad.effects())
        .err()
        .expect("events with air must be refused")
        .to_string();
    assert!(
        err.contains("air.toml") && err.contains("integrator.scheduler"),
        "{err}"
    );
    assert!(err.contains("drag"), "{err}");
    let text = def
        .text
        .replace("scheduler = \"auto\"", "scheduler = \"fast\"");
    let err = Scene::from_toml(&text, "x.toml").unwrap_err().to_string();
    assert!(
        err.contains("integrator.scheduler") && err.contains("\"events\""),
        "{err}"
    );
}

/// The lean path (events/binary.rs: lone frictionless contacts in closed form and a
/// two-body frame) against the island integrator it replaces, in the same event
/// scheduler. A binary collision: the same outgoing velocities to 1e-7 of the closing
/// speed at a tight tolerance (1e-10), within 1e-4 of the converged result at the default
/// tolerance. A falling pack (chaotic, seeds pooled): impact and contact counts within
/// 3 %, mean impact speed within 1 %, and most contacts on the lean path.
#[test]
fn the_lean_contact_path_matches_the_island_integrator() {
    let closing = 70.0;
    let at = |tol: f64, lean: bool| off_centre_pair(tol, Scheduler::Events, lean);
    let (lean_ref, island_ref) = (at(1e-10, true), at(1e-10, false));
    let (lean, island) = (at(1e-6, true), at(1e-6, false));
    assert_eq!(lean.work.lean_contacts, 1);
    assert_eq!(island.work.lean_contacts, 0);
    for k in 0..2 {
        let (x, y) = (&lean_ref.shots[k], &island_ref.shots[k]);
        assert!(
            (x.vel - y.vel).norm() < 1e-7 * closing,
            "{:?} vs {:?}",
            x.vel,
            y.vel
        );
        assert!((x.pos - y.pos).norm() < 1e-9, "{:?} vs {:?}", x.pos, y.pos);
        for o in [&lean, &island] {
            assert_eq!(o.shots[k].collisions, 1);
            assert!((o.shots[k].vel - x.vel).norm() < 1e-4 * closing);
        }
    }
    let l = pack_stats("events", true);
    let i = pack_stats("events", false);
    eprintln!("lean {l:?}\nislands {i:?}");
    assert!(rel(l.0, i.0) < 0.03, "impacts {} vs {}", l.0, i.0);
    assert!(rel(l.1, i.1) < 0.03, "contacts {} vs {}", l.1, i.1);
    assert!(rel(l.2, i.2) < 0.01, "mean impact speed {} vs {}", l.2, i.2);
    assert!(l.3 > 0.5 * l.1, "lean contacts {} of {}", l.3, l.1);
    assert_eq!(i.3, 0.0);
}

/// A third shot that reaches a pair while the pair's contact lasts makes it a three-body
/// contact: the event scheduler must not resolve the pair alone (events/lone.rs) but
/// integrate the three together, and end where the island integrator alone does (1e-6 of
/// the fastest speed at tolerance 1e-10). Arriving 2 us later, after the pair has
/// parted, it meets shot 0 flying off: two lone contacts.
#[test]
fn a_shot_arriving_during_a_contact_makes_it_a_three_body_contact() {
    let d = 0.8e-3;
    // Shots 0 and 1 touch at 45.71 us, shot 0 then at x = 1.371 mm; shot 2 comes down y
    // at 50 m/s to reach shot 0 `late` after that touch.
    let run_with = |late: f64, lean: bool| {
        let t_touch = 3.2e-3 / 70.0;
        let y0 = d + 50.0 * (t_touch + late);
        let shots = vec![
            shot(0, d, Vec3::new(0.0, 0.0, 0.01), Vec3::new(30.0, 0.0, 0.0)),
            shot(
                1,
                d,
                Vec3::new(0.004, 0.0, 0.01),
                Vec3::new(-40.0, 0.0, 0.0),
            ),
            shot(
                2,
                d,
                Vec3::new(30.0 * t_touch, y0, 0.01),
                Vec3::new(0.0, -50.0, 0.0),
            ),
        ];
        let mut phys = contact_physics(None, Some(0.9));
        phys.tolerance = 1e-10;
        Simulation::from_parts(phys, shots, 3e-4)
            .with_scheduler(Scheduler::Events)
            .with_lean_contacts(lean)
            .run(&|_| {})
    };
    for (late, lone) in [(0.3e-6, false), (2e-6, true)] {
        let (lean, island) = (run_with(late, true), run_with(late, false));
        assert_eq!(lean.work.contact_onsets, island.work.contact_onsets);
        for (a, b) in lean.shots.iter().zip(&island.shots) {
            assert!(
                (a.vel - b.vel).norm() < 1e-6 * 50.0,
                "{:?} vs {:?}",
                a.vel,
                b.vel
            );
        }
        eprintln!(
            "late {late:e}: {} contacts, {} lean",
            lean.work.contact_onsets, lean.work.lean_contacts
        );
        assert_eq!(lean.work.contact_onsets, 2);
        if lone {
            assert_eq!(lean.work.lean_contacts, 2);
        } else {
            assert!(lean.work.lean_contacts < lean.work.contact_onsets);
            assert!(lean.shots[2].collisions >= 1);
        }
    }
}

/// With friction the lean path carries the shots' spins (events/binary.rs): an oblique
/// collision of two spinning shots and an oblique impact on the specimen end where the
/// island integrator alone ends them (tolerance 1e-10: velocities within 1e-7 of the
/// impact speed, surface spin speeds too), on the lean path; the pair's angular
/// momentum about the origin is kept.
#[test]
fn frictional_lean_contacts_match_the_island_integrator() {
    let d = 0.8e-3;
    let spin = |mut s: ShotState, w: Vec3| {
        s.omega = w;
        s
    };
    let pair = vec![
        spin(
            shot(0, d, Vec3::new(0.0, 0.0, 0.01), Vec3::new(30.0, 0.0, 0.0)),
            Vec3::new(0.0, 0.0, 2e4),
        ),
        spin(
            shot(
                1,
                d,
                Vec3::new(0.004, 0.0003, 0.01),
                Vec3::new(-40.0, 5.0, 0.0),
            ),
            Vec3::new(1e4, 0.0, 0.0),
        ),
    ];
    let lone = vec![spin(
        shot(
            0,
            d,
            Vec3::new(0.0, 0.0, 0.001),
            Vec3::new(35.0, 10.0, -60.0),
        ),
        Vec3::new(0.0, -3e4, 0.0),
    )];
    for (shots, specimen, speed) in [(pair, false, 70.0), (lone, true, 70.0)] {
        let run = |lean: bool| {
            let mut phys = contact_physics(specimen.then_some(0.7), Some(0.9));
            phys.contacts.friction = Some(peenflow::contact::Friction {
                specimen: 0.3,
                shot: 0.3,
                wall: 0.0,
                law: peenflow::contact::friction::Tangential::Viscous,
            });
            phys.tolerance = 1e-10;
            Simulation::from_parts(phys, shots.clone(), 1e-4)
                .with_scheduler(Scheduler::Events)
                .with_lean_contacts(lean)
                .run(&|_| {})
        };
        let (lean, island) = (run(true), run(false));
        assert_eq!(lean.work.lean_contacts, 1, "specimen {specimen}");
        assert_eq!(island.work.lean_contacts, 0);
        assert_eq!(lean.work.contact_onsets, 1);
        for (a, b) in lean.shots.iter().zip(&island.shots) {
            assert!(
                (a.vel - b.vel).norm() < 1e-7 * speed,
                "{:?} vs {:?}",
                a.vel,
                b.vel
            );
            let r = a.body.radius;
            assert!(
                (a.omega - b.omega).norm() * r < 1e-7 * speed,
                "{:?} vs {:?}",
                a.omega,
                b.omega
            );
            // Friction acted: the spin changed.
            let w0 = shots[a.id.0 as usize].omega;
            assert!(
                (a.omega - w0).norm() * r > 0.1,
                "spin {:?} from {:?}",
                a.omega,
                w0
            );
        }
        if !specimen {
            let l = |s: &[ShotState]| {
                s.iter()
                    .map(|s| {
                        let i = 0.4 * s.body.mass * s.body.radius * s.body.radius;
                        s.pos.cross(&(s.vel * s.body.mass)) + s.omega * i
                    })
                    .sum::<Vec3>()
            };
            let (l0, l1) = (l(&shots), l(&lean.shots));
            assert!((l1 - l0).norm() < 1e-9 * l0.norm(), "{l0:?} -> {l1:?}");
        }
    }
}

/// A near miss that a collision turns into a hit: shot 0 strikes shot 1 off-centre and
/// sends it, during their contact, into shot 2, which sits 26 um (3.25 % of contact
/// distance) beyond a touch of either shot's free path. The event scheduler integrates
/// together only the pairs whose free paths come within 3 % of a touch, so the chunk's
/// check of the actual paths must find the hit and redo the chunk with the pair: three
/// contacts, none found late, and the window scheduler's velocities (which integrates
/// every nearby pair together) to 1e-6 of the impact speed at tolerance 1e-10.
#[test]
fn a_near_miss_that_a_collision_bends_into_a_hit_is_resolved() {
    let d: f64 = 0.8e-3;
    let (b, v): (f64, f64) = (0.5e-3, 100.0);
    let p1 = Vec3::new(2e-3, 0.0, 0.01);
    // The direction shot 1 is pushed in, and shot 2 beyond it.
    let n = Vec3::new((d * d - b * b).sqrt(), b, 0.0) / d;
    let p2 = p1 + n * (d + 26e-6);
    let p0 = Vec3::new(0.0, -b, 0.01);
    // Free paths: 1 and 2 stay where they are; 0 passes 2 along y = -b.
    assert!((p2 - p1).norm() > 1.03 * d);
    assert!(p2.y - p0.y > 1.03 * d);
    let go = |s: Scheduler| {
        let shots = vec![
            shot(0, d, p0, Vec3::new(v, 0.0, 0.0)),
            shot(1, d, p1, Vec3::zeros()),
            shot(2, d, p2, Vec3::zeros()),
        ];
        let mut phys = contact_physics(None, Some(0.9));
        phys.tolerance = 1e-10;
        run(phys, shots, 1e-4, s)
    };
    let (ev, win) = (go(Scheduler::Events), go(Scheduler::Windows));
    eprintln!(
        "events: {} contacts, {} redos, {} late; windows: {} contacts",
        ev.work.contact_onsets,
        ev.work.cluster_redos,
        ev.work.late_contacts,
        win.work.contact_onsets
    );
    assert!(ev.work.cluster_redos >= 1);
    assert_eq!(ev.work.late_contacts, 0);
    assert_eq!(ev.work.contact_onsets, win.work.contact_onsets);
    assert!(ev.shots[2].collisions >= 1);
    for (a, w) in ev.shots.iter().zip(&win.shots) {
        assert!(
            (a.vel - w.vel).norm() < 1e-6 * v,
            "{:?} vs {:?}",
            a.vel,
            w.vel
        );
    }
}

/// Runs `text` on auto (the event scheduler must be chosen) and on windows: the auto run
/// must have given up with a note containing `why`, and be the window run record for
/// record.
fn redone_on_windows(text: &str, why: &str) {
    let auto = Scene::from_toml(text, "pile.toml").unwrap();
    let windows = Scene::from_toml(
        &format!("{text}[integrator]\nscheduler = \"windows\"\n"),
        "pile.toml",
    )
    .unwrap();
    let heard = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
    let ear = heard.clone();
    let sim = Simulation::new(&auto, &auto.effects())
        .unwrap()
        .with_notice(Box::new(move |n| ear.lock().unwrap().push(n.to_string())));
    assert_eq!(sim.scheduler_in_use(), "events");
    let a = sim.run(&|_| {});
    // The caller heard it when it happened (the CLI prints it above its progress bar,
    // which starts again), in the words of the note.
    assert_eq!(
        *heard.lock().unwrap(),
        vec![a.scheduler_note.clone().unwrap()]
    );
    let w = simulate(&windows);
    println!("{:?}", a.scheduler_note);
    assert_eq!(a.scheduler, "windows");
    let note = a.scheduler_note.as_deref().unwrap_or("");
    assert!(
        note.starts_with("the event scheduler gave up at t = ") && note.contains(why),
        "{note}"
    );
    // It tells how to skip the attempt (a pile can spend most of a run on it).
    assert!(note.contains("`scheduler = \"windows\"`"), "{note}");
    // And how to step it as a DEM code would.
    assert!(
        note.contains("`method = \"verlet\"` with `fixed_step_ns = "),
        "{note}"
    );
    assert!(a.events.is_empty() && w.events.is_empty());
    assert_eq!(a.impacts, w.impacts);
    assert_eq!(a.shots.len(), w.shots.len());
    for (x, y) in a.shots.iter().zip(&w.shots) {
        assert_eq!((x.pos, x.vel, x.omega), (y.pos, y.vel, y.omega));
    }
    assert!(w.scheduler_note.is_none());
}

#[test]
fn a_pile_the_event_scheduler_cannot_verify_is_run_on_windows() {
    // 900 shots of 0.55 mm at 7 % volume fraction thrown at 110 m/s, obliquely, onto the
    // specimen with friction 2 between shots: after the first impacts they pile up, and a
    // cluster's chunk keeps being reached by shots from outside it, redo after redo.
    // Until session 23 the event scheduler then accepted the chunk unverified, leaving
    // the contact to be found late (the same pack with 3,000 shots stopped 752 of them,
    // overlapping by 129 % of an effective radius). It now gives up, and the run is the
    // window scheduler's, record for record, with the reason in the run's tail. (Whether
    // a draw of this pack piles up so is chance, and which draws do changes with any
    // change to how contacts are integrated: before session 35's contacts unclamped up
    // to their kink, 250 alone of the seven seeds tried in 240-251; from then, 244, 252
    // and 253 of 240-262; since session 39's slow kinks left unlocated, 240 and 252;
    // since session 60's continuations on the lean path after the others, 253, 259 and
    // 261. Since session 62's bound on a change through a neighbour, none of 240-275
    // with 600 shots: they run on events to the end, in 3-5 s, with no contact met deep;
    // with 900, 243, 246, 250 and 252 of 240-255, the others giving up on the islands'
    // size.)
    let text = "seed = 250\nduration_ms = 0.15\ngravity_m_s2 = 0.0\n[shots]\ndiameter_mm = 0.549\n[shots.feed]\ntype = \"box\"\ncount = 900\nmin_mm = [0.0, 0.0, 0.3]\nmax_mm = [9.231, 9.231, 13.521]\nvelocity_m_s = [10.91, -18.36, -108.14]\n[restitution]\nshot_specimen = 0.605\nshot_shot = 0.7\n[friction]\nshot_specimen = 0.3\nshot_shot = 1.974\n[effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n";
    redone_on_windows(text, "kept being reached by shots from outside it");
}

#[test]
fn a_pile_integrated_as_one_island_is_run_on_windows() {
    // 600 shots of 0.57 mm falling at 25 m/s onto the specimen, lossy contacts with
    // friction: they come to rest in a pile that the event scheduler integrates as one
    // cluster, every member at the step of whichever is mid-impact (51 shots per step
    // on average by the end; the 3,000-shot version of this pile took 217 s on events
    // before it gave up on an unverified chunk, 21 s on windows). Once its steps carry more
    // shots than the window scheduler's islands hold, it gives up.
    let text = "seed = 392\nduration_ms = 0.5\ngravity_m_s2 = 9.81\n[shots]\ndiameter_mm = 0.574\n[shots.feed]\ntype = \"box\"\ncount = 600\nmin_mm = [0.0, 0.0, 1.180]\nmax_mm = [7.392, 7.392, 19.802]\nvelocity_m_s = [0.68, 0.16, -24.66]\n[restitution]\nshot_specimen = 0.3\nshot_shot = 0.3\n[friction]\nshot_specimen = 0.3\nshot_shot = 0.3\n[effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n";
    redone_on_windows(text, "shots per integrator step on average");
}

#[test]
fn the_give_up_suggests_a_fiftieth_of_the_fastest_contact_time_as_fixed_step() {
    // Hertz (Johnson, Contact Mechanics, 11.2): t_c = 2.943 (5 m* / (4 K))^(2/5) v^(-1/5),
    // K = 4/3 E* sqrt(R*), 1/E* = 2 (1 - nu^2) / E for steel on steel.
    let hertz_time = |m: f64, r: f64, v: f64| {
        let e_star = common::E_STEEL / (2.0 * (1.0 - common::NU_STEEL * common::NU_STEEL));
        let k = 4.0 / 3.0 * e_star * r.sqrt();
        2.943 * (1.25 * m / k).powf(0.4) * v.powf(-0.2)
    };
    let slow = shot(
        0,
        0.8e-3,
        Vec3::new(0.0, 0.0, 1e-3),
        Vec3::new(3.0, 0.0, 0.0),
    );
    let fast = shot(
        1,
        0.8e-3,
        Vec3::new(0.0, 0.0, 3e-3),
        Vec3::new(0.0, 0.0, -40.0),
    );
    let small = shot(
        2,
        0.3e-3,
        Vec3::new(0.0, 0.0, 5e-3),
        Vec3::new(0.0, 0.0, -1.0),
    );
    let shots = [slow, fast, small.clone()];
    let (m, r) = (small.body.mass, small.body.radius);
    // Two of the smallest shots head-on at twice the fastest speed: shorter than one on
    // the specimen at that speed (half the effective mass and radius).
    let both = peenflow::events::fixed_step_hint(&contact_physics(Some(0.7), Some(0.7)), &shots);
    assert!(
        rel(both, hertz_time(m / 2.0, r / 2.0, 80.0) / 50.0) < 1e-3,
        "{both}"
    );
    let specimen = peenflow::events::fixed_step_hint(&contact_physics(Some(0.7), None), &shots);
    assert!(
        rel(specimen, hertz_time(m, r, 40.0) / 50.0) < 1e-3,
        "{specimen}"
    );
    assert!(both < specimen);
}

/// A stream in vacuum (no air, no nozzle wall contact) runs on the event scheduler on
/// auto: a stream's shots wait at their entry points one after the other, which is not
/// a pile. Until session 29 `auto` took them as shots starting in contact and ran the
/// window scheduler, about ten times slower on a 10,000-shot stream
/// (docs/performance-history.md, "Streams in vacuum on the event scheduler, and the pile
/// check on the latest steps, session 29").
/// Fed through a nozzle tilted at 45 degrees, slowly enough that a rebound is gone
/// before the next shot lands, the shots never meet, and the event scheduler's
/// impacts are the window scheduler's, shot by shot, within the tolerance's reach.
/// The simulation of scene `text`, which `auto` must run on the event scheduler.
fn on_events(text: &str, name: &str) -> Simulation {
    let scene = Scene::from_toml(text, name).unwrap();
    let sim = Simulation::new(&scene, &scene.effects()).unwrap();
    assert_eq!(sim.scheduler_in_use(), "events");
    sim
}

#[test]
fn a_stream_in_vacuum_runs_on_the_event_scheduler() {
    let text = "duration_ms = 40.0\n[nozzle]\nangle_deg = 45.0\nstandoff_mm = 20.0\n[shots.feed]\ntype = \"stream\"\nrate_per_s = 1000.0\nentry_speed_m_s = 20.0\narrivals = \"regular\"\n[effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n";
    let a = on_events(text, "vacuum_stream.toml").run(&|_| {});
    assert_eq!(a.scheduler, "events");
    assert!(a.scheduler_note.is_none(), "{:?}", a.scheduler_note);
    let windows = Scene::from_toml(
        &format!("{text}[integrator]\nscheduler = \"windows\"\n"),
        "vacuum_stream.toml",
    )
    .unwrap();
    let w = simulate(&windows);
    assert_eq!(w.scheduler, "windows");
    assert!(
        a.shots.iter().chain(&w.shots).all(|s| s.collisions == 0),
        "the shots must not meet for this test"
    );
    assert!(a.impacts.len() >= 30, "{} impacts", a.impacts.len());
    assert_eq!(a.impacts.len(), w.impacts.len());
    for (x, y) in a.impacts.iter().zip(&w.impacts) {
        assert_eq!(x.shot, y.shot);
        assert!(rel(x.speed_m_s, y.speed_m_s) < 1e-6, "{x:?}\n{y:?}");
        assert!((x.time_s - y.time_s).abs() < 1e-9, "{x:?}\n{y:?}");
        assert!(
            (x.x_m - y.x_m).abs() + (x.y_m - y.y_m).abs() < 1e-8,
            "{x:?}\n{y:?}"
        );
    }
}

/// A shot thrown up under gravity rises through cell faces and falls back through them in
/// one free flight. Until session 29 the event scheduler looked for a shot's next face
/// crossing from its flight's start, found the crossing up again after the crossing back
/// down, and the run never ended (found by `bench/random_scenes.py --vacuum`: a stream of
/// slow rebounds under 100 m/s^2). The run must end, and each shot's first impact is the
/// closed-form fall: t = (v0 + sqrt(v0^2 + 2 g h)) / g at sqrt(v0^2 + 2 g h), h the centre's
/// drop to the specimen. The thread is a watchdog for the hang, not a speed measurement:
/// the run takes about a millisecond.
#[test]
fn a_shot_thrown_up_falls_back_through_the_cells_it_rose_through() {
    let text = "duration_ms = 500.0\ngravity_m_s2 = 9.81\n[shots]\ndiameter_mm = 0.8\n[shots.feed]\ntype = \"list\"\n[[shots.feed.shots]]\nposition_mm = [0.0, 0.0, 5.0]\nvelocity_m_s = [0.0, 0.0, 1.0]\n[[shots.feed.shots]]\nposition_mm = [20.0, 0.0, 30.0]\n[[shots.feed.shots]]\nposition_mm = [0.0, 20.0, 60.0]\nvelocity_m_s = [0.0, 0.0, 0.3]\n[effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n";
    on_events(text, "thrown_up.toml");
    // (A simulation does not cross threads: the watchdog's thread builds its own.)
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        tx.send(on_events(text, "thrown_up.toml").run(&|_| {}))
            .unwrap()
    });
    let out = rx
        .recv_timeout(std::time::Duration::from_secs(300))
        .expect("the event scheduler did not end the run");
    assert_eq!(out.scheduler, "events");
    let g = 9.81;
    for (shot, z0, v0) in [(0u32, 5e-3, 1.0f64), (1, 30e-3, 0.0), (2, 60e-3, 0.3)] {
        let first = out
            .impacts
            .iter()
            .find(|m| m.shot == shot)
            .expect("every shot lands");
        let h = z0 - 0.4e-3;
        let v = (v0 * v0 + 2.0 * g * h).sqrt();
        let t = (v0 + v) / g;
        assert!(
            rel(first.time_s, t) < 1e-12,
            "shot {shot}: {} s against {t} s",
            first.time_s
        );
        assert!(
            rel(first.speed_m_s, v) < 1e-12,
            "shot {shot}: {} m/s against {v} m/s",
            first.speed_m_s
        );
    }
    // The bounces go on (restitution 0.7) and every shot is accounted for.
    assert!(out.impacts.len() > 10, "{}", out.impacts.len());
    assert!(out.events.is_empty(), "{:?}", out.events);
}

/// On the fixed-step method (`method = "verlet"` with `scheduler = "events"`), a give-up
/// says the run was redone on windows, where that method steps every shot on one grid,
/// and suggests no step: the scene has one.
#[test]
fn a_give_up_on_the_fixed_step_method_suggests_no_step() {
    let gave_up = |on_fixed_step| {
        peenflow::events::GaveUp {
            time_s: 1e-4,
            members: 40,
            why: peenflow::events::GiveUpReason::Unverified,
            fixed_step: 2e-8,
            on_fixed_step,
        }
        .to_string()
    };
    let (fixed, adaptive) = (gave_up(true), gave_up(false));
    assert!(
        fixed.starts_with("the event scheduler gave up at t = 0.100000 ms: a cluster of 40 shots")
    );
    assert!(
        fixed.contains(
            "redone on windows, where the fixed-step method steps every shot on one grid"
        )
    );
    assert!(fixed.contains("`scheduler = \"windows\"`"), "{fixed}");
    assert!(!fixed.contains("fixed_step_ns"), "{fixed}");
    assert!(
        adaptive.contains("`method = \"verlet\"` with `fixed_step_ns = 20`"),
        "{adaptive}"
    );
}

/// LIGGGHTS' stream.in (`bench/scenes/pack_stream_10k.toml`: 10,000 shots at 70 m/s, a
/// 5 % volume fraction, rebounds meeting the incoming shots) at the default tolerance
/// and at LIGGGHTS' accuracy (1e-4), on the event scheduler: no contact is found
/// overlapping deeper than the rounding level (`late_contacts_deep`). Until session 59 a
/// shot whose earliest pending touch was a stale one already past (predicted with a shot
/// whose path had changed since) was taken as free for good, through the real touch
/// that stale one hid: its new path met a shot resolved ahead of it 2 um deep, in both
/// runs.
#[test]
fn a_stale_pending_touch_hides_no_real_one() {
    let text = std::fs::read_to_string(common::root().join("bench/scenes/pack_stream_10k.toml"))
        .expect("bench/scenes/pack_stream_10k.toml");
    for tol in ["1e-6", "1e-4"] {
        let scene = Scene::from_toml(
            &format!("{text}\n[integrator]\ntolerance = {tol}\n"),
            "pack_stream_10k",
        )
        .unwrap();
        meets_no_contact_deep(&format!("tolerance {tol}"), &scene, 40_000);
    }
}

/// Boxes of shots thrown onto the plate (`bench/random_scenes.py`): no contact is
/// found overlapping deeper than the rounding level. Until session 60 a cluster whose
/// groups ended at different times checked the shots of a group that had parted on their
/// free paths against the groups that ran on, although they changed path before those
/// ended:
/// * 2,602 shots at 107 m/s, restitution 1 and friction 0.8 between shots, on the
///   fixed-step method on the event scheduler (`--ballistic --verlet --events --seed
///   628`, scene 16): a shot touched its group's shots again as they parted, and its new
///   path met a shot resolved ahead of it 18 um deep (2 % of the contact distance);
/// * 3,000 shots of 0.49 mm at 120 m/s at tolerance 1e-4 (`--ballistic --seed 630`, scene
///   13): a shot that had parted touched a shot outside, which was sent into a group that
///   ran on, 12 um deep.
///
/// And a third (`--ballistic --seed 626`, scene 70: 3,000 shots of 0.35 mm at 95 m/s,
/// tolerance 1e-5): a chunk ended with two groups held, one a shot on the plate alone. It
/// continued on the lean path first and took a shot released by the same chunk as free;
/// the other group, resuming at the same moment, took that shot in, and its new path met
/// the shot on the plate 1.5 um deep. Continuations that may take the lean path now come
/// after the others at the same time.
#[test]
fn three_thrown_boxes_meet_no_contact_late() {
    // As `bench/random_scenes.py --ballistic` writes them: seed, gravity (m/s^2),
    // diameter (mm), count, the box's corners and the velocity, the restitutions with
    // the specimen and between shots, and the tables that differ.
    let thrown = |k: (u64, f64, f64, u32), [lo, hi, v]: [&str; 3], e: (&str, &str), rest| {
        let (seed, g, d, count) = k;
        let text = format!(
            "seed = {seed}\nduration_ms = 1.0\ngravity_m_s2 = {g}\n[shots]\ndiameter_mm = {d}\n\
             [shots.feed]\ntype = \"box\"\ncount = {count}\nmin_mm = {lo}\nmax_mm = {hi}\n\
             velocity_m_s = {v}\n[restitution]\nshot_specimen = {}\nshot_shot = {}\n{rest}\
             [effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n",
            e.0, e.1
        );
        Scene::from_toml(&text, "thrown_box").unwrap()
    };
    let fixed_step = thrown(
        (607, 100.0, 0.821, 2602),
        [
            "[0.0, 0.0, 0.487]",
            "[26.487, 26.487, 17.708]",
            "[1.92, 14.23, -106.58]",
        ],
        ("1.000", "1.000"),
        "[friction]\nshot_specimen = 0.100\nshot_shot = 0.800\n[integrator]\n\
         method = \"verlet\"\nscheduler = \"events\"\nfixed_step_ns = 8.419\n",
    );
    let adaptive = thrown(
        (468, 100.0, 0.490, 3000),
        [
            "[0.0, 0.0, 1.907]",
            "[38.686, 38.686, 9.458]",
            "[9.32, 7.26, -119.84]",
        ],
        ("0.900", "0.700"),
        "[integrator]\ntolerance = 0.0001\n",
    );
    let resuming = thrown(
        (177, 9.81, 0.351, 3000),
        [
            "[0.0, 0.0, 1.494]",
            "[14.577, 14.577, 16.217]",
            "[-17.67, 14.66, -91.89]",
        ],
        ("0.300", "1.000"),
        "[integrator]\ntolerance = 1e-05\n",
    );
    for (name, scene, onsets) in [
        ("628/16", fixed_step, 20_000),
        ("630/13", adaptive, 8_000),
        ("626/70", resuming, 20_000),
    ] {
        meets_no_contact_deep(name, &scene, onsets);
    }
}

/// Runs `scene` on the event scheduler and asks for more than `onsets` contact onsets
/// and no contact met deeper than the rounding level.
fn meets_no_contact_deep(name: &str, scene: &Scene, onsets: u64) {
    let out = simulate(scene);
    assert_eq!(out.scheduler, "events");
    eprintln!(
        "{name}: {} contact onsets, {} late, {} of them deep, {} clusters, {} cluster redos",
        out.work.contact_onsets,
        out.work.late_contacts,
        out.work.late_contacts_deep,
        out.work.clusters,
        out.work.cluster_redos
    );
    assert!(out.work.contact_onsets > onsets, "{name}");
    assert_eq!(out.work.late_contacts_deep, 0, "{name}");
}

/// The gap `three_thrown_boxes_meet_no_contact_late` left open (session 60), met in
/// `bench/random_scenes.py` boxes and closed in session 62: a free shot's path was relied
/// on until its next pending touch, but a shot near it changed its own path first (at its
/// touch, or as its cluster resumed) and then reached it. Seed 642 scene 12 (a lone
/// contact relied on a neighbour that a cluster then took in: 1.5 um deep) and seed 630
/// scene 11 (the same, 15 um) are the lone path's side; seed 644 scene 19 (a cluster
/// relied on a shot that another cluster, resuming 0.55 ns later, then took in: 18.7 um
/// deep, on the fixed-step method) is the gathering's.
#[test]
fn a_change_through_a_neighbour_meets_no_contact_late() {
    // As `bench/random_scenes.py --ballistic` writes them: seed and duration (ms),
    // gravity (m/s^2), diameter (mm), count, the box's corners and the velocity, and the
    // tables.
    let thrown = |(seed, ms): (u64, f64),
                  g: f64,
                  d: f64,
                  count: u32,
                  [lo, hi, v]: [&str; 3],
                  rest: &str| {
        let text = format!(
            "seed = {seed}\nduration_ms = {ms}\ngravity_m_s2 = {g}\n[shots]\ndiameter_mm = {d}\n\
             [shots.feed]\ntype = \"box\"\ncount = {count}\nmin_mm = {lo}\nmax_mm = {hi}\n\
             velocity_m_s = {v}\n{rest}[effects]\ndrag = false\nlateral_force = false\n\
             nozzle_wall_contact = false\n"
        );
        Scene::from_toml(&text, "thrown_box").unwrap()
    };
    let lone = thrown(
        (504, 0.5),
        0.0,
        1.488,
        104,
        [
            "[0.0, 0.0, 0.786]",
            "[8.389, 8.389, 19.280]",
            "[-15.05, 5.64, -12.13]",
        ],
        "[restitution]\nshot_specimen = 0.900\nshot_shot = 0.300\n[friction]\n\
         shot_specimen = 1.410\nshot_shot = 0.300\n[integrator]\ntolerance = 0.001\n",
    );
    let lone_long = thrown(
        (798, 1.0),
        100.0,
        0.595,
        2046,
        [
            "[0.0, 0.0, 1.728]",
            "[19.898, 19.898, 17.523]",
            "[11.14, 18.45, -109.40]",
        ],
        "[restitution]\nshot_specimen = 0.300\nshot_shot = 0.936\n[integrator]\n\
         tolerance = 0.0001\n",
    );
    let gathering = thrown(
        (881, 0.5),
        9.81,
        1.055,
        327,
        [
            "[0.0, 0.0, 0.588]",
            "[14.947, 14.947, 8.498]",
            "[16.05, -7.13, -76.05]",
        ],
        "[restitution]\nshot_specimen = 0.700\nshot_shot = 0.300\n[integrator]\n\
         method = \"verlet\"\nscheduler = \"events\"\nfixed_step_ns = 57.637\n",
    );
    for (name, scene, onsets) in [
        ("642/12", lone, 150),
        ("630/11", lone_long, 10_000),
        ("644/19", gathering, 1_000),
    ] {
        meets_no_contact_deep(name, &scene, onsets);
    }
}
