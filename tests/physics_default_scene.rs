//! The paper's Table 2 scene (30 shots, 10 ms) over 5 seeds: every shot is accounted for,
//! no shot fails, every impact is finite and below 150 m/s. And with shot-shot contact
//! off, each of the 30 shots flies bit for bit as it would alone, with no neighbour search
//! and no work for any effect that is off.

use peenflow::scene::{Scene, Switch};
use peenflow::sim::Simulation;
use peenflow::state::ShotStatus;

#[test]
fn default_scene_over_five_seeds_accounts_for_every_shot() {
    for seed in 1..=5 {
        let mut scene = Scene::default_scene();
        scene.seed = seed;
        let effects = scene.effects();
        assert!(effects.shot_shot_contact && effects.nozzle_wall_contact && effects.drag);
        let out = Simulation::new(&scene, &effects).unwrap().run(&|_| {});
        assert_eq!(out.shots.len(), 30);
        for (i, s) in out.shots.iter().enumerate() {
            assert_eq!(s.id.0 as usize, i);
            assert_ne!(s.status, ShotStatus::Failed, "seed {seed}: shot {i} failed");
            assert!(s.pos.iter().chain(s.vel.iter()).all(|v| v.is_finite()));
            let recorded = out.impacts.iter().filter(|m| m.shot == s.id.0).count();
            assert_eq!(
                recorded as u32, s.hits,
                "seed {seed}: shot {i} hits vs records"
            );
        }
        assert!(out.events.is_empty(), "seed {seed}: {:?}", out.events);
        for m in &out.impacts {
            assert!(
                m.speed_m_s.is_finite() && m.speed_m_s < 150.0,
                "seed {seed}: {m:?}"
            );
            assert!(m.normal_speed_m_s > 0.0);
            assert!((m.center_z_m - 0.5 * m.diameter_m).abs() < 1e-9);
        }
        let hit = out.shots.iter().filter(|s| s.hits > 0).count();
        println!(
            "seed {seed}: {hit}/30 hit, {} impacts, {} shot-shot contacts",
            out.impacts.len(),
            out.shots.iter().map(|s| s.collisions).sum::<u32>() / 2
        );
        assert!(hit >= 15, "seed {seed}: only {hit} shots hit");
    }
}

#[test]
fn without_shot_shot_contact_each_shot_flies_as_if_alone() {
    let mut scene = Scene::default_scene();
    scene.effects.switches[4] = Switch::Off; // shot_shot_contact
    scene.effects.switches[1] = Switch::Off; // lateral_force
    let effects = scene.effects();
    assert!(!effects.shot_shot_contact && !effects.lateral_force);
    let sim = Simulation::new(&scene, &effects).unwrap();
    let physics = sim.physics().clone();
    let shots = peenflow::feed::initial_shots(&scene).unwrap();
    let all = sim.run(&|_| {});
    assert_eq!(all.work.neighbour_searches, 0);
    assert_eq!(all.work.pair_contact_checks, 0);
    assert_eq!(all.work.lateral_force_calls, 0);
    assert!(all.work.drag_calls > 0 && all.work.gravity_calls > 0);
    assert!(all.work.wall_contact_checks > 0);
    for shot in shots {
        let alone = Simulation::from_parts(physics.clone(), vec![shot.clone()], scene.duration)
            .run(&|_| {});
        let mine: Vec<_> = all
            .impacts
            .iter()
            .filter(|m| m.shot == shot.id.0)
            .cloned()
            .collect();
        assert_eq!(mine, alone.impacts, "shot {}", shot.id.0);
        assert_eq!(all.shots[shot.id.0 as usize], alone.shots[0]);
    }
}

#[test]
fn effects_that_are_off_do_no_work() {
    // Only gravity and the specimen: no flow sampling, no drag, no lateral force, no wall,
    // no neighbour search.
    let mut scene = Scene::default_scene();
    scene.duration = 2e-3;
    for (i, on) in [false, false, true, true, false, false].iter().enumerate() {
        scene.effects.switches[i] = if *on { Switch::On } else { Switch::Off };
    }
    let effects = scene.effects();
    let out = Simulation::new(&scene, &effects).unwrap().run(&|_| {});
    let w = out.work;
    assert_eq!(
        (
            w.flow_samples,
            w.drag_calls,
            w.lateral_force_calls,
            w.wall_contact_checks,
            w.neighbour_searches,
            w.pair_contact_checks,
            w.region_crossings
        ),
        (0, 0, 0, 0, 0, 0, 0)
    );
    assert!(w.gravity_calls > 0 && w.specimen_contact_checks > 0);
}
