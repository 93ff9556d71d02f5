//! Turbulent dispersion (beyond the paper, `jet.turbulence_intensity`): off costs nothing
//! and changes nothing; on, it scatters lone shots isotropically about the mean-flow
//! impact point, with a spread that grows linearly with the intensity (drag responds
//! linearly to small fluctuations), reproducibly whatever the thread count.

use crate::common;
use common::*;
use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

/// `n` shots started one by one on the jet axis in the inlet plane (2 ms apart, no
/// shot-shot contact), 0.8 mm, 0.6 MPa.
fn lone_shots(intensity: f64, switch: &str, n: usize) -> RunOutput {
    let mut text = format!(
        "duration_ms = {}\ngravity_m_s2 = 0.0\n[jet]\nturbulence_intensity = {intensity}\n[shots.feed]\ntype = \"list\"\n",
        2.0 * n as f64 + 8.0
    );
    for k in 0..n {
        text.push_str(&format!(
            "[[shots.feed.shots]]\nposition_mm = [0.0, 0.0, 140.0]\nstart_ms = {}\n",
            2.0 * k as f64
        ));
    }
    text.push_str(&format!(
        "[effects]\nshot_shot_contact = false\nturbulent_dispersion = {switch}\n"
    ));
    let scene = Scene::from_toml(&text, "turbulence").unwrap();
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    assert!(out.events.is_empty(), "{:?}", out.events);
    out
}

fn first_hits(out: &RunOutput) -> Vec<(f64, f64)> {
    out.impacts
        .iter()
        .filter(|i| i.first_hit == 1)
        .map(|i| (i.x_m, i.y_m))
        .collect()
}

#[test]
fn off_changes_nothing_and_costs_nothing() {
    let reference = lone_shots(0.0, "\"auto\"", 5);
    let off = lone_shots(0.3, "false", 5);
    assert_eq!(reference.impacts, off.impacts);
    assert_eq!(off.work.eddies, 0);
    assert_eq!(reference.work.eddies, 0);
    // All five land on the axis without turbulence.
    assert!(first_hits(&reference).iter().all(|p| p.0.hypot(p.1) < 1e-9));
}

#[test]
fn lone_shots_scatter_isotropically_and_linearly_in_the_intensity() {
    let n = 60;
    let mut rms = Vec::new();
    for intensity in [0.05, 0.1, 0.2] {
        let out = lone_shots(intensity, "\"auto\"", n);
        assert!(
            out.work.eddies > 10 * n as u64,
            "{} eddies",
            out.work.eddies
        );
        let hits = first_hits(&out);
        assert_eq!(hits.len(), n);
        let (mx, my) = hits.iter().fold((0.0, 0.0), |a, p| {
            (a.0 + p.0 / n as f64, a.1 + p.1 / n as f64)
        });
        let r2 = hits.iter().map(|p| p.0 * p.0 + p.1 * p.1).sum::<f64>() / n as f64;
        let sigma = (r2 / 2.0).sqrt(); // per axis
        // Isotropic, centred on the axis: mean within 4 standard errors.
        let se = sigma / (n as f64).sqrt();
        assert!(
            mx.abs() < 4.0 * se && my.abs() < 4.0 * se,
            "mean ({mx}, {my}), se {se}"
        );
        println!(
            "I = {intensity}: lateral rms {:.4} mm per axis",
            sigma * 1e3
        );
        rms.push(sigma);
    }
    // Linear response: doubling the intensity doubles the spread (within sampling noise
    // of 60 shots, about 13 % per estimate).
    for k in 1..rms.len() {
        let ratio = rms[k] / rms[k - 1];
        assert!(
            (1.5..2.6).contains(&ratio),
            "spread ratio {ratio} for doubled intensity"
        );
    }
}

#[test]
fn turbulent_runs_are_identical_for_1_and_2_threads() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("t.toml"),
        "[jet]\nturbulence_intensity = 0.25\n",
    )
    .unwrap();
    let mut outs = Vec::new();
    for j in ["1", "2"] {
        let o = peenflow(&["run", "t.toml", "-q", "-j", j, "--out", j], tmp.path());
        assert!(
            o.status.code().unwrap() <= 1,
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        outs.push(std::fs::read(tmp.path().join(j).join("impacts.csv")).unwrap());
    }
    assert!(outs[0] == outs[1]);
    let d = std::fs::read_to_string(tmp.path().join("1/summary.json")).unwrap();
    assert!(d.contains("\"eddies\""));
}
