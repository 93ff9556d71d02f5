//! Same scene + seed => byte-identical impacts.csv and shots.csv (and the run's picture),
//! for 1 and 2 threads.

use crate::common;
use common::*;
use std::fs;

#[test]
fn outputs_are_identical_across_runs_and_thread_counts() {
    let tmp = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for (k, threads) in ["1", "2", "2"].iter().enumerate() {
        let out = format!("out{k}");
        let o = peenflow(&["run", "--out", &out, "-q", "-j", threads], tmp.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let dir = tmp.path().join(&out);
        outputs.push((
            fs::read(dir.join("impacts.csv")).unwrap(),
            fs::read(dir.join("shots.csv")).unwrap(),
            fs::read(dir.join("impacts.svg")).unwrap(),
        ));
    }
    assert!(outputs[0].0.len() > 500);
    assert!(outputs.iter().all(|o| *o == outputs[0]));
    // A different seed gives a different run.
    let o = peenflow(&["run", "--out", "other", "-q", "--seed", "2"], tmp.path());
    assert!(o.status.success());
    assert_ne!(
        fs::read(tmp.path().join("other/impacts.csv")).unwrap(),
        outputs[0].0
    );
}

#[test]
fn friction_and_sieve_sizes_are_deterministic_across_thread_counts() {
    let tmp = tempfile::tempdir().unwrap();
    for scene in ["friction_spin.toml", "s330_stream.toml"] {
        let path = root().join("examples").join(scene);
        let path = path.to_str().unwrap();
        let mut outputs = Vec::new();
        for threads in ["1", "2"] {
            let out = format!("{scene}-{threads}");
            let o = peenflow(
                &["run", path, "--out", &out, "-q", "-j", threads],
                tmp.path(),
            );
            assert!(
                o.status.code().unwrap() <= 1,
                "{}",
                String::from_utf8_lossy(&o.stderr)
            );
            outputs.push(fs::read(tmp.path().join(&out).join("impacts.csv")).unwrap());
        }
        assert!(outputs[0].len() > 500, "{scene}");
        assert!(outputs[0] == outputs[1], "{scene}: 1 and 2 threads differ");
        if scene == "friction_spin.toml" {
            // Spin reaches the outputs: final omega per shot in shots.csv.
            let shots = fs::read_to_string(tmp.path().join(format!("{scene}-1")).join("shots.csv"))
                .unwrap();
            let header: Vec<&str> = shots.lines().next().unwrap().split(',').collect();
            let k = header.iter().position(|h| *h == "omega_y_rad_s").unwrap();
            assert!(
                shots
                    .lines()
                    .skip(1)
                    .any(|l| l.split(',').nth(k).unwrap().parse::<f64>().unwrap() != 0.0)
            );
        }
    }
}

/// Windows hand their islands to the thread pool only when enough shots take steps; with
/// that threshold at zero every window runs in parallel, and the records must still be
/// identical to a one-thread run.
#[test]
fn windows_integrated_in_parallel_give_the_one_thread_records() {
    let scene = peenflow::scene::Scene::default_scene();
    let run = |threads: usize, min_shots: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            peenflow::sim::Simulation::new(&scene, &scene.effects())
                .unwrap()
                .with_parallel_min_shots(min_shots)
                .run(&|_| {})
        })
    };
    let one = run(1, 0);
    let two = run(2, 0);
    let default = run(2, peenflow::sim::PARALLEL_MIN_SHOTS);
    assert_eq!(one.scheduler, "windows");
    assert!(one.impacts.len() > 10);
    assert_eq!(one.impacts, two.impacts);
    assert_eq!(one.shots, two.shots);
    assert_eq!(one.impacts, default.impacts);
    assert_eq!(one.shots, default.shots);
}
