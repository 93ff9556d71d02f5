//! A large island's right-hand side split over the threads (`Physics::blocks_min`, session
//! 38): each block of members receives its terms in the order of one pass over every
//! member and pair (a pair across two blocks is evaluated in both), so a run gives the
//! records and work counts of the one-thread run byte for byte, whatever the thread
//! count. Here every island of four shots or more is split (blocks of two or more).

use crate::common;

use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

/// `scene` on a pool of `threads` threads, islands split from two members per block.
fn run(scene: &Scene, threads: usize) -> RunOutput {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let sim = Simulation::new(scene, &scene.effects())
            .unwrap()
            .with_blocks_min(2);
        let phys = sim.physics();
        // The split the runs below rely on: one pass on one thread, a block per thread.
        assert_eq!(peenflow::integrate::island::blocks(phys, 100), threads);
        assert_eq!(peenflow::integrate::island::blocks(phys, 3), 1);
        sim.run(&|_| {})
    })
}

fn same_runs(scene: &Scene) -> RunOutput {
    let one = run(scene, 1);
    for threads in [2, 3] {
        let many = run(scene, threads);
        assert_eq!(one.impacts.len(), many.impacts.len(), "{threads} threads");
        for (a, b) in one.impacts.iter().zip(&many.impacts) {
            assert_eq!(format!("{a:?}"), format!("{b:?}"), "{threads} threads");
        }
        assert_eq!(one.shots.len(), many.shots.len());
        for (a, b) in one.shots.iter().zip(&many.shots) {
            assert_eq!(format!("{a:?}"), format!("{b:?}"), "{threads} threads");
        }
        assert_eq!(one.work, many.work, "{threads} threads");
        assert_eq!(one.events, many.events, "{threads} threads");
    }
    one
}

/// A bed of 192 shots with friction settling on the specimen: one island, its (001)
/// layers in consecutive members, so the blocks meet at a layer; the shots spin.
#[test]
fn a_settling_bed_with_friction_is_the_same_on_one_two_and_three_threads() {
    let text = "title = \"bed\"\nduration_ms = 0.02\n[shots]\ndiameter_mm = 0.8\n\
        [shots.feed]\ntype = \"bed\"\nnx = 4\nny = 4\nlayers = 6\n\
        [restitution]\nshot_specimen = 0.7\nshot_shot = 0.9\n\
        [friction]\nshot_specimen = 0.3\nshot_shot = 0.3\n\
        [effects]\ndrag = false\nlateral_force = false\ngravity = true\n\
        specimen_contact = true\nshot_shot_contact = true\nnozzle_wall_contact = false\n";
    let scene = Scene::from_toml(text, "bed.toml").unwrap();
    let one = same_runs(&scene);
    assert_eq!(one.shots.len(), 192);
    assert!(one.work.pair_contact_checks > 100_000, "{:?}", one.work);
    assert!(one.work.friction_calls > 10_000, "{:?}", one.work);
    assert!(one.shots.iter().any(|s| s.omega.norm() > 0.0));
}

/// A colliding stream through the nozzle (400 shots over 10 ms): islands of shots met in
/// flight and above the specimen, their members in feed order, so a block's pairs reach
/// into the others anywhere.
#[test]
fn a_colliding_stream_is_the_same_on_one_two_and_three_threads() {
    let scene = common::nozzle_stream("blocks test", 40_000.0, (10.0, 4.0), 1);
    let one = same_runs(&scene);
    assert!(one.impacts.len() > 300, "{} impacts", one.impacts.len());
}

/// A column of 120 shots thrown onto the specimen on the fixed-step method, rebounds
/// meeting the shots still coming, friction on: contacts start and end at step ends,
/// and on more threads the forces, the overlap guard and the separations run in
/// blocks. (On one thread a step's end takes each member and each pair through the
/// onsets, the guard and the separations at once, `Ctx::fixed_step_end`, session 71:
/// the blocks' runs are the three passes it stands for.)
#[test]
fn a_fixed_step_pile_is_the_same_on_one_two_and_three_threads() {
    let text = "title = \"pile\"\nseed = 7\nduration_ms = 0.3\n[shots]\ndiameter_mm = 0.717\n\
        [shots.feed]\ntype = \"box\"\ncount = 120\nmin_mm = [0.0, 0.0, 0.4]\n\
        max_mm = [4.0, 4.0, 10.0]\nvelocity_m_s = [0.0, 0.0, -40.0]\n\
        [restitution]\nshot_specimen = 1.0\nshot_shot = 0.5\n\
        [friction]\nshot_specimen = 0.0\nshot_shot = 0.3\n\
        [integrator]\nmethod = \"verlet\"\nfixed_step_ns = 20\n\
        [effects]\ndrag = false\nlateral_force = false\ngravity = true\n\
        specimen_contact = true\nshot_shot_contact = true\nnozzle_wall_contact = false\n";
    let scene = Scene::from_toml(text, "pile.toml").unwrap();
    let one = same_runs(&scene);
    assert!(one.impacts.len() > 100, "{} impacts", one.impacts.len());
    assert!(one.work.contact_onsets > 200, "{:?}", one.work);
}

/// Shots too soft for Hertz contact on the fixed-step method: four converge on a point, a
/// fifth is thrown onto the specimen. Their overlaps pass what the guard allows and the
/// islands stop with the same events (the shots, the times, the messages naming the pair
/// and the specimen) whether a step's end takes one pass (one thread) or the three passes
/// in blocks (two and three threads). In steel, the four leave a small domain as one.
#[test]
fn a_fixed_step_island_stops_and_leaves_the_same_on_one_two_and_three_threads() {
    let mut text = "title = \"jelly\"\nduration_ms = 0.05\ngravity_m_s2 = 0.0\n\
        [materials.jelly]\nyoungs_modulus_gpa = 0.00001\npoisson_ratio = 0.45\n\
        density_kg_m3 = 7850.0\n[shots]\nmaterial = \"jelly\"\ndiameter_mm = 0.8\n\
        [specimen]\nmaterial = \"jelly\"\n\
        [integrator]\nmethod = \"verlet\"\nfixed_step_ns = 20\n\
        [effects]\ndrag = false\nlateral_force = false\nnozzle_wall_contact = false\n\
        [shots.feed]\ntype = \"list\"\n"
        .to_string();
    let shots = [
        ([-0.5, -0.5, 3.0], [40.0, 40.0, 0.0]),
        ([0.5, -0.5, 3.0], [-40.0, 40.0, 0.0]),
        ([-0.5, 0.5, 3.0], [40.0, -40.0, 0.0]),
        ([0.5, 0.5, 3.0], [-40.0, -40.0, 0.0]),
        ([5.0, 0.0, 0.5], [0.0, 0.0, -60.0]),
    ];
    for (p, v) in shots {
        text += &format!("[[shots.feed.shots]]\nposition_mm = {p:?}\nvelocity_m_s = {v:?}\n");
    }
    let scene = Scene::from_toml(&text, "jelly.toml").unwrap();
    let one = same_runs(&scene);
    let causes: Vec<_> = one
        .events
        .iter()
        .map(|e| (e.shot, e.cause.as_str()))
        .collect();
    assert_eq!(one.events.len(), 5, "{causes:?}");
    for e in &one.events {
        let named = if e.shot == 4 {
            "shot 4 overlaps the specimen by"
        } else {
            "overlap by"
        };
        assert!(e.cause.contains(named), "{causes:?}");
        assert!(e.cause.ends_with("Hertz contact does not hold there"));
        assert_eq!(e.suggestion, "use a smaller fixed step");
    }
    // Four steel shots flying side by side out of the smallest domain the nozzle allows
    // (3 mm across the axis), closing on each other: they touch as they leave it, one
    // island.
    let cut = text.find("[[shots.feed.shots]]").unwrap();
    let mut small = text[..cut]
        .replace("material = \"jelly\"\n", "")
        .replace("duration_ms = 0.05", "duration_ms = 0.1");
    for (y, z, vy, vz) in [
        (-0.448, 3.0, 1.0, 1.0),
        (0.448, 3.0, -1.0, 1.0),
        (-0.448, 3.896, 1.0, -1.0),
        (0.448, 3.896, -1.0, -1.0),
    ] {
        small += &format!(
            "[[shots.feed.shots]]\nposition_mm = [1.0, {y}, {z}]\nvelocity_m_s = [40.0, {vy}, {vz}]\n"
        );
    }
    small += "[domain]\nradius_mm = 3.0\n";
    let scene = Scene::from_toml(&small, "steel.toml").unwrap();
    let one = same_runs(&scene);
    assert!(one.events.is_empty(), "{:?}", one.events);
    let left =
        |s: &&peenflow::state::ShotState| s.status == peenflow::state::ShotStatus::LeftDomain;
    assert_eq!(one.shots.iter().filter(left).count(), 4);
}
