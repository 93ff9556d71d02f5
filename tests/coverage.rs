//! Coverage against analytic expectations: dents of area `a` dropped at uniformly random
//! places of an area `A` cover `1 - exp(-N a / A)` of it (a Poisson field); arriving at a
//! steady rate, the Avrami fit has `n = 1` and `k = N a / (A T)`, and 98 % coverage takes
//! `T ln 50 / (N a / A)`. Plus the command end to end.

use crate::common;
use common::peenflow;
use peenflow::coverage::{Dent, compute};
use rand::{Rng, SeedableRng};
use std::process::Command;

/// `n` dents of radius `r` at uniform places over the window grown by `r` on each side
/// (so the window sees no edge effect) and uniform times in `[0, t]`.
fn uniform(n: usize, r: f64, w: f64, t: f64, seed: u64) -> Vec<Dent> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            Dent::disc(
                rng.random_range(-r..w + r),
                rng.random_range(-r..w + r),
                r,
                rng.random_range(0.0..t),
            )
        })
        .collect()
}

#[test]
fn uniform_random_dents_cover_one_minus_exp_minus_a() {
    let (w, r, t_end): (f64, f64, f64) = (10e-3, 0.25e-3, 1.0);
    let area = (w + 2.0 * r).powi(2);
    for (n, seed) in [(1000, 1u64), (4000, 2), (10000, 3)] {
        let mut dents = uniform(n, r, w, t_end, seed);
        // Exposure starts at the first impact: shift it to t = 0 exactly.
        let t_min = dents.iter().map(|d| d.t).fold(f64::INFINITY, f64::min);
        for d in &mut dents {
            d.t -= t_min;
        }
        let cov = compute(&dents, [0.0, 0.0, w, w], r / 10.0, t_end - t_min);
        let a = n as f64 * std::f64::consts::PI * r * r / area;
        let expected = 1.0 - (-a).exp();
        println!(
            "N = {n}: coverage {:.4}, expected 1 - exp(-{a:.3}) = {expected:.4}",
            cov.final_coverage
        );
        // Sampling noise of a Poisson field over ~(w / 2r)^2 = 400 dent areas: ~1 %.
        assert!(
            (cov.final_coverage - expected).abs() < 0.015,
            "coverage {} vs {expected}",
            cov.final_coverage
        );
        // Along the exposure: C(t) = 1 - exp(-a t / T).
        for &(tt, c) in cov.curve.iter().step_by(20) {
            let e = 1.0 - (-a * tt / t_end).exp();
            assert!((c - e).abs() < 0.02, "t {tt}: {c} vs {e}");
        }
        if let Some(fit) = cov.fit {
            println!(
                "  Avrami n = {:.3} (1), k = {:.3} ({a:.3}), t98 fit {:.3} (theory {:.3})",
                fit.n,
                fit.k,
                fit.time_to(0.98),
                t_end * 50f64.ln() / a
            );
            assert!((fit.n - 1.0).abs() < 0.05, "Avrami exponent {}", fit.n);
            assert!(
                (fit.k / a - 1.0).abs() < 0.06,
                "Avrami rate {} vs {a}",
                fit.k
            );
            let t98 = t_end * 50f64.ln() / a;
            assert!((fit.time_to(0.98) / t98 - 1.0).abs() < 0.08);
        } else {
            panic!("no fit");
        }
        if let Some(t98) = cov.t98_measured {
            assert!(expected > 0.97, "98 % reached below the expected coverage");
            let theory = t_end * 50f64.ln() / a;
            assert!((t98 / theory - 1.0).abs() < 0.1, "t98 {t98} vs {theory}");
        }
    }
}

/// An elliptic dent (a bar's or a groove's) covers its ellipse: the cells whose centre
/// lies inside, `pi a_x a_y` of the window to the grid's resolution.
#[test]
fn one_elliptic_dent_covers_its_ellipse() {
    let (rx, ry) = (1.5e-3, 0.6e-3);
    let dents = [Dent {
        x: 5e-3,
        y: 5e-3,
        rx,
        ry,
        t: 0.0,
    }];
    let cov = compute(&dents, [0.0, 0.0, 10e-3, 10e-3], 10e-6, 1.0);
    let expected = std::f64::consts::PI * rx * ry / 1e-4;
    assert!(
        (cov.final_coverage / expected - 1.0).abs() < 2e-3,
        "{} vs {expected}",
        cov.final_coverage
    );
    // Covered 1.45 mm across, not 0.65 mm along.
    let at = |x: f64, y: f64| cov.counts[(y / 10e-6) as usize * cov.nx + (x / 10e-6) as usize];
    assert_eq!(at(6.445e-3, 5.005e-3), 1);
    assert_eq!(at(5.005e-3, 5.655e-3), 0);
    assert_eq!(at(5.005e-3, 5.555e-3), 1);
}

#[test]
fn one_dent_covers_its_disc() {
    let r = 1e-3;
    let dents = [Dent::disc(5e-3, 5e-3, r, 0.0)];
    let cov = compute(&dents, [0.0, 0.0, 10e-3, 10e-3], 10e-6, 1.0);
    let expected = std::f64::consts::PI * r * r / 1e-4;
    assert!(
        (cov.final_coverage / expected - 1.0).abs() < 2e-3,
        "{} vs {expected}",
        cov.final_coverage
    );
    assert_eq!(cov.dents_in_window, 1);
    assert_eq!(*cov.counts.iter().max().unwrap(), 1);
    // A dent outside the window covers nothing.
    let far = [Dent::disc(50e-3, 5e-3, r, 0.0)];
    let cov = compute(&far, [0.0, 0.0, 10e-3, 10e-3], 10e-6, 1.0);
    assert_eq!((cov.final_coverage, cov.dents_in_window), (0.0, 0));
}

#[test]
fn coverage_command_end_to_end() {
    let t = tempfile::tempdir().unwrap();
    common::coverage_run(t.path());
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--window",
            "-2,-2,2,2",
            "--out",
            "c",
        ],
        t.path(),
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        text.contains("plastic dent") && text.contains("coverage "),
        "{text}"
    );
    for f in [
        "coverage.csv",
        "coverage.json",
        "coverage_map.png",
        "coverage_map.svg",
        "coverage_curve.png",
        "coverage_curve.svg",
    ] {
        assert!(t.path().join("c").join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path().join("c/coverage.json")).unwrap())
            .unwrap();
    let c = json["final_coverage"].as_f64().unwrap();
    assert!(c > 0.0 && c <= 1.0);
    // The curve is non-decreasing and ends at the final coverage.
    let csv = std::fs::read_to_string(t.path().join("c/coverage.csv")).unwrap();
    let vals: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(vals.windows(2).all(|w| w[1] >= w[0]));
    assert_eq!(*vals.last().unwrap(), c);
    // Again, into the same file: /coverage is replaced, the impacts stay readable.
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--out",
            "c2",
            "--target-material",
            "hardened-steel",
        ],
        t.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = peenflow(
        &["export", "run/impacts.h5", "-f", "csv", "--out", "e"],
        t.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // h5py reads the map.
    let py = Command::new("python3").args(["-c", "import h5py"]).output();
    if py.map(|o| o.status.success()).unwrap_or(false) {
        let o = Command::new("python3")
            .args([
                "-c",
                "import h5py,sys; g=h5py.File(sys.argv[1])['coverage']; m=g['dent_count'][:]; \
                 assert m.ndim == 2 and m.sum() > 0; assert 'hardened' not in g.attrs['target'] or True; \
                 print(g.attrs['target'], g['curve_coverage'][-1])",
                "run/impacts.h5",
            ])
            .current_dir(t.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stdout).starts_with("hardened-steel"));
    } else {
        assert!(std::env::var_os("CI").is_none(), "h5py missing in CI");
    }
    // Bad input: one line, exit 2.
    for (args, needle) in [
        (
            vec![
                "coverage",
                "run/impacts.h5",
                "--window",
                "2,2,1,1",
                "--out",
                "x",
            ],
            "--window",
        ),
        (vec!["coverage", "nope.h5", "--out", "y"], "nope.h5"),
        (
            vec!["coverage", "run/impacts.h5", "--cell-um", "0", "--out", "z"],
            "--cell-um",
        ),
        (
            vec![
                "coverage",
                "run/impacts.h5",
                "--target-material",
                "cheese",
                "--out",
                "w",
            ],
            "cheese",
        ),
    ] {
        let o = peenflow(&args, t.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(needle) && e.trim().lines().count() == 1, "{e}");
    }
    // A cell too fine for the window is enlarged to 2000 cells along it, and the run
    // says so.
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--cell-um",
            "0.001",
            "--no-h5",
            "--out",
            "fine",
        ],
        t.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("note: --cell-um 0.001 would need more than 2000 cells along the window; cells enlarged to"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(t.path().join("fine/coverage.json")).unwrap(),
    )
    .unwrap();
    let cells = &json["cells"];
    assert_eq!(
        cells[0].as_u64().unwrap().max(cells[1].as_u64().unwrap()),
        2000,
        "{cells}"
    );
}

#[test]
fn a_sweep_case_gives_the_coverage_of_one_seed() {
    let t = tempfile::tempdir().unwrap();
    let case = common::two_seed_sweep(t.path());
    let mut dents = Vec::new();
    for seed in ["1", "2"] {
        let out = format!("c{seed}");
        let o = peenflow(
            &["coverage", case, "--seed", seed, "--no-h5", "--out", &out],
            t.path(),
        );
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(text.contains(&format!("coverage of seed {seed}")), "{text}");
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(t.path().join(&out).join("coverage.json")).unwrap(),
        )
        .unwrap();
        dents.push(json["dents"].as_u64().unwrap());
        // The same seed run alone has as many impacts (all dent: normal speed > 0).
        let o = peenflow(
            &[
                "run",
                "sw/case-000_gauge_pressure_mpa-0.6/scene.toml",
                "--seed",
                seed,
                "-q",
                "--out",
                &format!("r{seed}"),
            ],
            t.path(),
        );
        assert!(o.status.code().unwrap() <= 1);
        let rows = std::fs::read_to_string(t.path().join(format!("r{seed}/impacts.csv")))
            .unwrap()
            .lines()
            .count()
            - 1;
        assert_eq!(rows as u64, *dents.last().unwrap());
    }
    let o = peenflow(&["coverage", case, "--seed", "7", "--out", "c7"], t.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds seeds 1, 2"));
}

/// `--dent-curve`: a one-point curve through Johnson's law (`a/R = (8 rho / (3 p_d))^(1/4)
/// v^(1/2)`, here at 1 m/s) gives the material model's coverage to the last digit; twice
/// the ratio gives twice the median dent diameter; bad curves get one line and exit 2.
#[test]
fn a_measured_dent_curve_replaces_the_material_model() {
    let t = tempfile::tempdir().unwrap();
    common::coverage_run(t.path());
    let run = |extra: &[&str], out: &str| {
        let mut args = vec!["coverage", "run/impacts.h5", "--no-h5", "--out", out];
        args.extend_from_slice(extra);
        let o = peenflow(&args, t.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(t.path().join(out).join("coverage.json")).unwrap(),
        )
        .unwrap();
        let csv = std::fs::read_to_string(t.path().join(out).join("coverage.csv")).unwrap();
        (json, csv, String::from_utf8_lossy(&o.stdout).to_string())
    };
    // Table 2 steel shots (7850 kg/m^3) on A5052 (p_d = 3 x 195 MPa).
    let f1 = (8.0f64 * 7850.0 / (3.0 * 3.0 * 195e6)).powf(0.25);
    let (model, model_csv, _) = run(&["--window", "-2,-2,2,2"], "m");
    let one = format!("1:{f1}");
    let (curve, curve_csv, said) = run(&["--window", "-2,-2,2,2", "--dent-curve", &one], "c");
    assert!(said.contains("measured dents (--dent-curve)"), "{said}");
    assert_eq!(model_csv, curve_csv);
    assert_eq!(model["final_coverage"], curve["final_coverage"]);
    let twice = format!("1:{}", 2.0 * f1);
    let (double, _, _) = run(&["--window", "-2,-2,2,2", "--dent-curve", &twice], "d");
    let d = |j: &serde_json::Value| j["median_dent_diameter_m"].as_f64().unwrap();
    assert!(
        (d(&double) / d(&model) - 2.0).abs() < 1e-9,
        "{double} {model}"
    );
    for (bad, says) in [
        ("20:0.4,10:0.5", "speeds must increase"),
        ("20-0.4", "give SPEED:RATIO pairs"),
        ("20:9", "allowed (0, 5]"),
    ] {
        let o = peenflow(
            &[
                "coverage",
                "run/impacts.h5",
                "--out",
                "bad",
                "--dent-curve",
                bad,
            ],
            t.path(),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains(says) && err.contains("--dent-curve"),
            "{bad}: {err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!t.path().join("bad").exists());
    }
}

/// On a cylindrical specimen the dents sit on its unrolled surface: an impact 40 degrees
/// around a 5 mm bar, 3 mm along it, dents at 5 mm x 40 degrees of arc and 3 mm, sized
/// by its speed normal to the surface; the map and `--window` take those coordinates
/// (the command end to end on a run onto a bar).
#[test]
fn dents_on_a_bar_sit_on_its_unrolled_surface() {
    use peenflow::Vec3;
    use peenflow::contact::specimen::SpecimenShape;
    use peenflow::coverage::{dent::DentModel, dents, dents_on};
    use peenflow::record::Impact;
    let bar = SpecimenShape::cylinder(5e-3, 90f64.to_radians());
    let th = 40f64.to_radians();
    let n = Vec3::new(th.sin(), 0.0, th.cos());
    let centre = Vec3::new(0.0, 3e-3, -5e-3) + n * 5.4e-3;
    let v = n * -50.0 + Vec3::new(0.0, 10.0, 0.0);
    let imp = Impact::on(
        &bar,
        0,
        1e-3,
        &centre,
        &v,
        &Vec3::zeros(),
        4e-4,
        2e-6,
        0,
        true,
    );
    assert!((imp.normal_speed_m_s - 50.0).abs() < 1e-12);
    let model = DentModel::for_pair(
        &peenflow::scene::material::builtin("SUJ-2").unwrap(),
        &peenflow::scene::material::builtin("A5052").unwrap(),
    );
    let d = dents_on(std::slice::from_ref(&imp), &model, &bar)[0];
    assert!(
        (d.x - 5e-3 * th).abs() < 1e-15 && (d.y - 3e-3).abs() < 1e-15,
        "{d:?}"
    );
    // The same normal speed head-on on the plate: the flat dent's radius `a`; on the
    // bar an ellipse, `a q^(3/8)` around and `a q^(-1/8)` along it, `q = 1/(1 + r/R_c)`
    // (docs/coverage.md).
    let flat = Impact::new(
        0,
        1e-3,
        &Vec3::new(0.0, 0.0, 4e-4),
        &Vec3::new(0.0, 0.0, -50.0),
        &Vec3::zeros(),
        4e-4,
        2e-6,
        0,
        true,
    );
    let a = dents(&[flat], &model)[0].rx;
    let q: f64 = 1.0 / (1.0 + 4e-4 / 5e-3);
    assert!((d.rx / (a * q.powf(0.375)) - 1.0).abs() < 1e-12, "{d:?}");
    assert!((d.ry / (a * q.powf(-0.125)) - 1.0).abs() < 1e-12, "{d:?}");

    // End to end: the spring wire's coverage names the bar's axes.
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::root().join("examples/spring_wire.toml");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("duration_ms = 30.0", "duration_ms = 8.0");
    std::fs::write(tmp.path().join("wire.toml"), text).unwrap();
    let o = peenflow(&["run", "wire.toml", "--out", "run", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--out",
            "cov",
            "--window",
            "-1,-1,1,1",
        ],
        tmp.path(),
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains("window around the bar -1.00..1.00 mm, along its axis -1.00..1.00 mm"),
        "{out}"
    );
}

/// In a groove the coverage is split by zone across the window: the zones' spans tile
/// it where the groove's profile puts them (the bottom's half width, the fillet's arc
/// `R (90 - flank)` beyond it), their cells add up to the window's and their coverages,
/// weighted by cells, to the window's (the command end to end on the gear root example,
/// whose run's summary counts every impact in one zone).
#[test]
fn coverage_in_a_groove_is_given_per_zone() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::root().join("examples/gear_root.toml");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("duration_ms = 30.0", "duration_ms = 8.0");
    std::fs::write(tmp.path().join("gear.toml"), text).unwrap();
    let o = peenflow(&["run", "gear.toml", "--out", "run", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The run's summary counts every impact in one zone.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("run/summary.json")).unwrap())
            .unwrap();
    let zones = summary["zones"].as_array().expect("zones");
    let names: Vec<&str> = zones.iter().map(|z| z["zone"].as_str().unwrap()).collect();
    assert_eq!(names, ["bottom", "fillet", "flank", "edge", "land"]);
    let sum = |k: &str| zones.iter().map(|z| z[k].as_u64().unwrap()).sum::<u64>();
    assert_eq!(sum("first_hits"), summary["first_hits"].as_u64().unwrap());
    assert_eq!(sum("impacts"), summary["impacts"].as_u64().unwrap());
    assert!(summary["across_m"].is_object() && summary.get("around_m").is_none());
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--out",
            "cov",
            "--window",
            "-3,-1,3,1",
        ],
        tmp.path(),
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains("window across the groove -3.00..3.00 mm"),
        "{out}"
    );
    assert!(out.contains("coverage per zone of the groove"), "{out}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("cov/coverage.json")).unwrap())
            .unwrap();
    let zones = json["zones"].as_array().expect("zones");
    let names: Vec<&str> = zones.iter().map(|z| z["zone"].as_str().unwrap()).collect();
    assert_eq!(names, ["flank", "fillet", "bottom", "fillet", "flank"]);
    // Fillet radius 1.52 mm, bottom 0.52 mm, flanks 20 degrees.
    let (hb, fillet_end) = (0.26e-3, 0.26e-3 + 1.52e-3 * 70f64.to_radians());
    let bounds = [-3e-3, -fillet_end, -hb, hb, fillet_end, 3e-3];
    let (mut cells, mut covered) = (0.0, 0.0);
    for (k, z) in zones.iter().enumerate() {
        let span = z["across_m"].as_array().unwrap();
        let (a, b) = (span[0].as_f64().unwrap(), span[1].as_f64().unwrap());
        assert!((a - bounds[k]).abs() < 1e-12 && (b - bounds[k + 1]).abs() < 1e-12);
        let n = z["cells"].as_f64().unwrap();
        cells += n;
        covered += n * z["coverage"].as_f64().unwrap();
    }
    let grid = json["cells"].as_array().unwrap();
    assert_eq!(
        cells,
        grid[0].as_f64().unwrap() * grid[1].as_f64().unwrap(),
        "the zones' cells are the window's"
    );
    let total = json["final_coverage"].as_f64().unwrap();
    assert!((covered / cells - total).abs() < 1e-12, "{covered} {total}");
    // The jet aims at the root: the fillets are dented.
    assert!(zones[1]["coverage"].as_f64().unwrap() > 0.0);
    // The dents are ellipses: longer across in the fillets, shorter on the edges; the
    // impact file's /coverage says the same as coverage.json.
    let aspect: Vec<f64> = json["dent_aspect_across_along"]
        .as_array()
        .expect("dent_aspect_across_along")
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(aspect[0] < 1.0 && aspect[2] > 1.0, "{aspect:?}");
    let py = Command::new("python3").args(["-c", "import h5py"]).output();
    if py.map(|o| o.status.success()).unwrap_or(false) {
        let o = Command::new("python3")
            .args([
                "-c",
                "import h5py,sys,json; a=list(h5py.File(sys.argv[1])['coverage'].attrs['dent_aspect_across_along']); \
                 j=json.load(open(sys.argv[2]))['dent_aspect_across_along']; assert a == j, (a, j); print('ok')",
            ])
            .arg(tmp.path().join("run/impacts.h5"))
            .arg(tmp.path().join("cov/coverage.json"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    } else {
        assert!(std::env::var_os("CI").is_none(), "h5py missing in CI");
    }
    // A nozzle moving along the groove keeps its pattern; one moving across does not,
    // and is refused before anything is written.
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--out",
            "along",
            "--no-h5",
            "--traverse-mm-s",
            "100",
            "--traverse-deg",
            "90",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(tmp.path().join("along/traverse.csv").exists());
    let o = peenflow(
        &[
            "coverage",
            "run/impacts.h5",
            "--out",
            "across",
            "--no-h5",
            "--traverse-mm-s",
            "100",
            "--traverse-deg",
            "30",
        ],
        tmp.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--traverse-deg 30: in a groove the nozzle can only move along it"),
        "{err}"
    );
    let left = std::fs::read_dir(tmp.path().join("across"))
        .map(|d| d.count())
        .unwrap_or(0);
    assert_eq!(left, 0, "nothing written");
}

/// A turning gear simulated dent by dent: the nozzle moves along the gear's axis while
/// the gear turns; each dent is drawn from the still-nozzle run whose offset is nearest
/// to the rack's offset at that moment and lands on the tooth space that sits where
/// that run's groove does. Turning fast (0.01 mm of feed per revolution), the mean
/// dents per point and the covered share over every tooth space and many lines along
/// the axis match `n(u) = (1/Z) sum_k w_k sum_j n_k(u + jP)` and `1 - exp(-n)` within 4
/// standard errors (about 4,000 samples per point). Turning slowly (8 mm per
/// revolution, the pattern's spread along the axis 3 mm), the dents vary along the axis
/// in helical bands whose amplitude matches [`GearProfile::new`]'s first harmonic.
#[test]
fn a_turning_gear_is_covered_as_a_simulation_of_it_finds() {
    use peenflow::coverage::gear::{GearProfile, OffsetRuns, Turning};
    use rand_distr::{Distribution, Exp, Normal};
    let (pitch, period, teeth, v) = (10e-3, 14e-3, 40usize, 1e-3);
    // Three offsets unevenly spread (shares 0.3, 0.25, 0.45), each with its own
    // pattern: round and elliptic dents scattered round its own centre, some in the
    // neighbouring grooves. Times i T / N: each run's exposure is T = 0.5 s.
    let offsets = [0.0, 1e-3, 5e-3];
    let centres = [-3e-3, 2e-3, 6e-3];
    let counts = [300usize, 200, 400];
    let t_run = 0.5;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let runs: Vec<Vec<Dent>> = (0..3)
        .map(|k| {
            let across = Normal::new(centres[k], 2.5e-3).unwrap();
            let along = Normal::new(0.0, 3e-3).unwrap();
            (0..counts[k])
                .map(|i| {
                    let (rx, ry) = if i % 2 == 0 {
                        (0.5e-3, 0.5e-3)
                    } else {
                        (0.6e-3, 0.4e-3)
                    };
                    Dent {
                        x: across.sample(&mut rng),
                        y: along.sample(&mut rng),
                        rx,
                        ry,
                        t: t_run * i as f64 / counts[k] as f64,
                    }
                })
                .collect()
        })
        .collect();
    let given: Vec<OffsetRuns> = (0..3)
        .map(|k| OffsetRuns {
            offset: offsets[k],
            runs: vec![&runs[k]],
        })
        .collect();
    let turning = Turning {
        teeth: teeth as u32,
        speed: v,
    };
    let feed = 8e-3;
    let g = GearProfile::new(&given, pitch, period, turning, 0.1e-3, 0.0, Some(feed)).unwrap();
    let m = g.points.len();
    assert_eq!(m, 140);
    let (step, u0) = (g.spacing, g.points[0].offset);
    let rates: Vec<f64> = counts.iter().map(|&n| n as f64 / t_run).collect();
    let r_max = rates.iter().cloned().fold(0.0, f64::max);
    let circle = |a: f64| a.rem_euclid(pitch);
    // The process: the nozzle moves from y = -100 mm to +100 mm at v while the rack's
    // offset runs at `big_v`; dents counted on lines across the gear `dy` apart.
    let mut simulate = |big_v: f64, dy: f64| -> (Vec<f64>, Vec<u32>) {
        let half_travel = 0.1;
        // 96 mm: 12 periods of the slow gear's bands.
        let lines: Vec<f64> = (0..(0.096 / dy).round() as usize)
            .map(|i| -0.048 + i as f64 * dy)
            .collect();
        let mut hits = vec![0u32; teeth * m * lines.len()];
        let gap = Exp::new(r_max).unwrap();
        let mut t = 0.0;
        loop {
            t += gap.sample(&mut rng);
            if t > 2.0 * half_travel / v {
                break;
            }
            let o = big_v * t;
            // The rack's offset is -O; the run nearest to it on the circle of one pitch.
            let phase = circle(-o);
            let dist = |k: usize| {
                let x = (phase - circle(offsets[k])).abs();
                x.min(pitch - x)
            };
            let k = (0..3).min_by(|&a, &b| dist(a).total_cmp(&dist(b))).unwrap();
            if rng.random::<f64>() >= rates[k] / r_max {
                continue;
            }
            let d = runs[k][rng.random_range(0..counts[k])];
            let n0 = ((o + offsets[k]) / pitch).round() as i64;
            let j = (d.x / period).round() as i64;
            let u = d.x - j as f64 * period;
            let space = (j + n0).rem_euclid(teeth as i64);
            let centre = space as f64 * period + u;
            let y = -half_travel + v * t + d.y;
            for (l, &line) in lines.iter().enumerate() {
                let dy = (line - y) / d.ry;
                if dy.abs() > 1.0 {
                    continue;
                }
                let dx = d.rx * (1.0 - dy * dy).sqrt();
                let lo = ((centre - dx - u0) / step).ceil() as i64;
                let hi = ((centre + dx - u0) / step).floor() as i64;
                for q in lo..=hi {
                    let q = q.rem_euclid((teeth * m) as i64) as usize;
                    hits[l * teeth * m + q] += 1;
                }
            }
        }
        (lines, hits)
    };

    // Turning fast: 40 m/s, 0.01 mm of feed per revolution.
    let (lines, hits) = simulate(40.0, 1e-3);
    let samples = (teeth * lines.len()) as f64;
    for (i, p) in g.points.iter().enumerate() {
        let (mut sum, mut covered) = (0.0, 0.0);
        for l in 0..lines.len() {
            for s in 0..teeth {
                let h = hits[l * teeth * m + s * m + i];
                sum += f64::from(h);
                covered += f64::from(u8::from(h > 0));
            }
        }
        let (mean, share) = (sum / samples, covered / samples);
        let se_n = (p.dents / samples).sqrt();
        let c = peenflow::coverage::traverse::coverage(p.dents);
        let se_c = (c * (1.0 - c) / samples).sqrt();
        assert!(
            (mean - p.dents).abs() < 4.0 * se_n,
            "u = {:.2} mm: simulated {mean:.4} dents per point, the law {:.4} (se {se_n:.4})",
            p.offset * 1e3,
            p.dents
        );
        assert!(
            (share - c).abs() < 4.0 * se_c,
            "u = {:.2} mm: simulated coverage {share:.4}, the law {c:.4} (se {se_c:.4})",
            p.offset * 1e3
        );
    }
    // The pattern reaches the whole period, unevenly.
    let most = g.points.iter().map(|p| p.dents).fold(0.0, f64::max);
    assert!(g.least().dents > 0.1 && most > 2.0 * g.least().dents);

    // Turning slowly: 8 mm of feed per revolution (V = v Z p / f). Tooth space `s`
    // passes `s f / Z` later along the axis. At each point, the first harmonic of its
    // counts over the lines and spaces; the Poisson noise adds its count to the squared
    // sum on average, taken off. In bins of 14 points, the rms amplitude against the
    // law's.
    let (lines, hits) = simulate(v * teeth as f64 * pitch / feed, 0.25e-3);
    let ripple = &g.banding.as_ref().unwrap().sample;
    let k = std::f64::consts::TAU / feed;
    let (mut least, mut most) = (f64::INFINITY, 0.0f64);
    for b in 0..m / 14 {
        let (mut law, mut measured, mut counted) = (0.0, 0.0, 0.0);
        for i in b * 14..(b + 1) * 14 {
            let (mut n, mut re, mut im) = (0.0, 0.0, 0.0);
            for (l, &y) in lines.iter().enumerate() {
                for s in 0..teeth {
                    let h = f64::from(hits[l * teeth * m + s * m + i]);
                    let phase = k * (y - s as f64 * feed / teeth as f64);
                    n += h;
                    re += h * phase.cos();
                    im += h * phase.sin();
                }
            }
            measured += 4.0 * (re * re + im * im - n) / (n * n);
            law += ripple[i] * ripple[i];
            counted += n;
        }
        let (measured, law) = ((measured / 14.0).max(0.0).sqrt(), (law / 14.0).sqrt());
        // An amplitude from N counts is off by about 2 / sqrt(N).
        let tol = 3.0 * 2.0 / (counted / 14.0).sqrt();
        assert!(
            (measured - law).abs() < tol,
            "bin {b}: simulated banding {measured:.4}, the law {law:.4} (tolerance {tol:.4})"
        );
        least = least.min(law);
        most = most.max(law);
    }
    // Bands at 8 mm per revolution (the pattern spreads 3 mm along the axis; each point
    // sees a few dozen of the runs' dents, so its amplitude is that of their sample);
    // none at 0.01 mm, where the dents are far longer than the feed.
    assert!(least > 0.05 && most < 0.6, "{least} {most}");
    let fast = GearProfile::new(&given, pitch, period, turning, 0.1e-3, 0.0, Some(1e-5)).unwrap();
    let flat = fast.banding.unwrap().sample.into_iter().fold(0.0, f64::max);
    assert!(flat < 0.01, "{flat}");
}

/// `peenflow coverage --gear-teeth` end to end: three runs of the gear root example
/// at uneven offsets; the profile's mean is the teeth-weighted mean of each run's own
/// raster along the rack folded over the profile's period (`--traverse-deg -90
/// --pitch-mm P`), whatever the bands; refusals name what to fix and write nothing.
#[test]
fn a_turning_gear_end_to_end() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let base = std::fs::read_to_string(common::root().join("examples/gear_root.toml"))
        .unwrap()
        .replace("duration_ms = 30.0", "duration_ms = 8.0");
    let offsets = [-4.0, 0.0, 2.5];
    for (k, o) in offsets.iter().enumerate() {
        let text = base.replace("# offset_mm = -1.2", &format!("offset_mm = {o}"));
        assert_ne!(text, base);
        std::fs::write(dir.join(format!("g{k}.toml")), text).unwrap();
        let o = peenflow(
            &[
                "run",
                &format!("g{k}.toml"),
                "--out",
                &format!("g{k}"),
                "-q",
            ],
            dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let files = ["g0/impacts.h5", "g1/impacts.h5", "g2/impacts.h5"];
    let mut args = vec!["coverage"];
    args.extend(files);
    args.extend([
        "--gear-teeth",
        "30",
        "--traverse-mm-s",
        "1",
        "--gear-rpm",
        "60",
        "--out",
        "gear",
    ]);
    let o = peenflow(&args, dir);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains("turning gear, 30 teeth (rack pitch 12.566 mm"),
        "{out}"
    );
    assert!(
        out.contains("at 60 rev/min the nozzle moves 1.000 mm per revolution"),
        "{out}"
    );
    for f in ["gear.csv", "gear.json", "gear.png", "gear.svg"] {
        assert!(dir.join("gear").join(f).is_file(), "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("gear/gear.json")).unwrap()).unwrap();
    // Shares: half the gaps on the circle of one pitch (phases 8.566, 0, 2.5 mm).
    let p = 12.566;
    let want = [
        (4.0 + 6.066) / 2.0 / p,
        (2.5 + 4.0) / 2.0 / p,
        (2.5 + 6.066) / 2.0 / p,
    ];
    let shares = json["offsets"].as_array().unwrap();
    for (s, w) in shares.iter().zip(want) {
        assert!((s["weight"].as_f64().unwrap() - w).abs() < 1e-9, "{s}");
    }
    let period = json["period_arc_m"].as_f64().unwrap();
    // Each run alone along the rack, folded over the period.
    let mut mean = 0.0;
    for (k, f) in files.iter().enumerate() {
        let out_k = format!("r{k}");
        let pitch_mm = format!("{:.12}", period * 1e3);
        let o = peenflow(
            &[
                "coverage",
                f,
                "--traverse-mm-s",
                "1",
                "--traverse-deg",
                "-90",
                "--pitch-mm",
                &pitch_mm,
                "--no-h5",
                "--out",
                &out_k,
            ],
            dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let csv = std::fs::read_to_string(dir.join(&out_k).join("raster.csv")).unwrap();
        let values: Vec<f64> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        mean += want[k] * values.iter().sum::<f64>() / values.len() as f64 / 30.0;
    }
    // Either's banded chords sum to the dents' areas up to a Riemann sum's error over
    // its own grid (2e-7 here).
    let got = json["mean_dents_per_point"].as_f64().unwrap();
    assert!((got - mean).abs() < 1e-5 * mean, "{got} vs {mean}");
    // The zones run across the tooth space side by side, the tooth top over the
    // period's ends; their arcs sum to the period; the least covered point is in one.
    let zones = json["zones"].as_array().unwrap();
    let named: Vec<String> = zones
        .iter()
        .map(|z| {
            format!(
                "{}{}",
                z["zone"].as_str().unwrap(),
                z["side"].as_str().unwrap()
            )
        })
        .collect();
    assert_eq!(
        named,
        [
            "edge-", "flank-", "fillet-", "bottom", "fillet+", "flank+", "edge+", "land"
        ]
    );
    let span = |z: &serde_json::Value, k: usize| z["across_m"][k].as_f64().unwrap();
    for w in zones.windows(2) {
        assert!((span(&w[0], 1) - span(&w[1], 0)).abs() < 1e-12);
    }
    let ends = span(&zones[7], 1) - span(&zones[0], 0);
    assert!((ends - period).abs() < 1e-12, "{ends} vs {period}");
    let arcs: f64 = zones.iter().map(|z| z["arc_m"].as_f64().unwrap()).sum();
    assert!((arcs - period).abs() < 1e-9, "{arcs} vs {period}");
    let least = json["least"]["dents_per_point"].as_f64().unwrap();
    let zone_least = zones
        .iter()
        .map(|z| z["least_dents"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(least, zone_least);

    // Refusals: one line, exit 2, nothing written.
    let plane = peenflow(&["run", "--out", "plane", "-q"], dir);
    assert!(plane.status.success());
    let wider = base.replace("radius_mm = 1.52", "radius_mm = 1.6");
    std::fs::write(dir.join("wide.toml"), wider).unwrap();
    assert!(
        peenflow(&["run", "wide.toml", "--out", "wide", "-q"], dir)
            .status
            .success()
    );
    let cases: [(&[&str], &str); 8] = [
        (
            &[
                "g0/impacts.h5",
                "--gear-teeth",
                "30",
                "--traverse-mm-s",
                "1",
            ],
            "a turning gear needs runs at 2 or more offsets across one pitch",
        ),
        (
            &[
                "g0/impacts.h5",
                "g0/impacts.h5",
                "--gear-teeth",
                "30",
                "--traverse-mm-s",
                "1",
            ],
            "offsets -4 mm and -4 mm are the same place on the rack (the pitch is 12.566 mm)",
        ),
        (
            &[
                "g0/impacts.h5",
                "plane/impacts.h5",
                "--gear-teeth",
                "30",
                "--traverse-mm-s",
                "1",
            ],
            "plane/impacts.h5: --gear-teeth: the specimen is a plane",
        ),
        (
            &[
                "g0/impacts.h5",
                "wide/impacts.h5",
                "--gear-teeth",
                "30",
                "--traverse-mm-s",
                "1",
            ],
            "its groove differs from g0/impacts.h5's in more than offset_mm",
        ),
        (
            &["g0/impacts.h5", "g1/impacts.h5", "--gear-teeth", "30"],
            "--gear-teeth 30: give the nozzle's speed along the gear's axis too",
        ),
        (
            &[
                "g0/impacts.h5",
                "g1/impacts.h5",
                "--gear-teeth",
                "30",
                "--traverse-mm-s",
                "1",
                "--traverse-deg",
                "90",
            ],
            "--traverse-deg does not apply with --gear-teeth",
        ),
        (
            &["g0/impacts.h5", "g1/impacts.h5", "--traverse-mm-s", "1"],
            "2 impact files given: several only with --gear-teeth",
        ),
        (
            &["g0/impacts.h5", "--gear-rpm", "60"],
            "--gear-rpm 60: give the gear's teeth too (--gear-teeth)",
        ),
    ];
    for (k, (extra, message)) in cases.iter().enumerate() {
        let out_k = format!("bad{k}");
        let mut args = vec!["coverage"];
        args.extend(extra.iter());
        args.extend(["--out", &out_k]);
        let o = peenflow(&args, dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        let written = std::fs::read_dir(dir.join(&out_k))
            .map(|d| d.count())
            .unwrap_or(0);
        assert_eq!(written, 0, "{args:?} wrote files");
    }
}
