//! Stream and size-distribution feeds: shots enter at their arrival times inside the bore,
//! sizes follow the distribution, runs stay finite and every shot is accounted for.

mod common;
use peenflow::scene::Scene;
use peenflow::sim::Simulation;
use peenflow::state::ShotStatus;

#[test]
fn stream_feed_enters_over_time_and_reaches_the_specimen() {
    let text = r#"
duration_ms = 6.0
[shots.feed]
type = "stream"
rate_per_s = 20000.0
duration_ms = 2.0
"#;
    let scene = Scene::from_toml(text, "stream").unwrap();
    let shots = peenflow::feed::initial_shots(&scene).unwrap();
    // Poisson arrivals at 20,000/s over 2 ms: 40 expected, sd ~6.3.
    assert!((20..60).contains(&shots.len()), "{}", shots.len());
    assert!(shots.windows(2).all(|w| w[0].t_start <= w[1].t_start));
    assert!(shots.iter().all(|s| s.t_start < 2e-3));
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    assert!(out.events.is_empty(), "{:?}", out.events);
    assert!(out.shots.iter().all(|s| s.status != ShotStatus::Failed));
    for m in &out.impacts {
        let s = &out.shots[m.shot as usize];
        assert!(
            m.time_s > s.t_start + 2e-3,
            "shot {} hit {} s after entering",
            m.shot,
            m.time_s - s.t_start
        );
    }
    let hit = out.shots.iter().filter(|s| s.hits > 0).count();
    assert!(
        hit as f64 > 0.6 * out.shots.len() as f64,
        "{hit}/{}",
        out.shots.len()
    );
}

#[test]
fn discrete_sizes_follow_their_weights() {
    let text = r#"
[shots.size_distribution]
type = "discrete"
diameters_mm = [0.5, 0.8]
weights = [3.0, 1.0]
[shots.feed]
type = "batch"
count = 400
axial_spread_mm = 40.0
radial_offset_mm = [0.0, 2.6]
"#;
    let scene = Scene::from_toml(text, "sizes").unwrap();
    let shots = peenflow::feed::initial_shots(&scene).unwrap();
    let small = shots
        .iter()
        .filter(|s| (s.body.radius - 0.25e-3).abs() < 1e-12)
        .count();
    // Binomial(400, 0.75): mean 300, sd 8.7.
    assert!((270..330).contains(&small), "{small}");
    for (i, a) in shots.iter().enumerate() {
        for b in &shots[..i] {
            assert!((a.pos - b.pos).norm() >= a.body.radius + b.body.radius);
        }
    }
}

#[test]
fn dense_stream_with_windows_shrinking_around_entering_shots() {
    // 200,000 shots/s: islands grow, windows shrink, and shots keep entering meanwhile.
    let text = r#"
duration_ms = 3.0
[shots.feed]
type = "stream"
rate_per_s = 200000.0
"#;
    let scene = Scene::from_toml(text, "dense stream").unwrap();
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    assert!(out.events.is_empty(), "{:?}", out.events);
    // The inlet cannot take 200,000 shots/s entering at rest: the feed throttles and the
    // summary says so.
    assert!(
        out.shots.len() > 200 && out.shots.len() < 600,
        "{}",
        out.shots.len()
    );
    let summary = peenflow::summary::Summary::new(&scene, &scene.effects().decisions, &out, 0.0, 1);
    assert!(summary.text().contains("the inlet throttled the stream"));
    assert!(
        out.shots
            .iter()
            .all(|s| s.pos.iter().chain(s.vel.iter()).all(|v| v.is_finite()))
    );
    let collisions: u32 = out.shots.iter().map(|s| s.collisions).sum();
    assert!(collisions > 0);
}
