//! Coverage under a moving nozzle (src/coverage/traverse.rs) against an independent
//! computation. A still nozzle's dents are drawn from a known footprint (Gaussian,
//! standard deviation 3 mm, dents of 0.25 mm radius at 5,000 per second); the profile
//! `peenflow coverage --traverse-mm-s` derives from them is compared with
//! - the footprint's own expected dents per point, integrated numerically;
//! - a moving nozzle simulated dent by dent: fresh dents, each placed where the nozzle
//!   was when it arrived, and the coverage measured by testing random points of the
//!   part against every dent near them (no cells, no formula).

use crate::common;
use common::peenflow;
use peenflow::coverage::Dent;
use peenflow::coverage::traverse::{Track, Traverse, coverage};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const SIGMA: f64 = 3e-3;
const RADIUS: f64 = 0.25e-3;
const RATE: f64 = 5000.0;
const SPEED: f64 = 0.1;

/// One dent of the footprint, relative to the jet axis.
fn draw(rng: &mut ChaCha8Rng) -> (f64, f64) {
    let g = Normal::new(0.0, SIGMA).unwrap();
    (g.sample(rng), g.sample(rng))
}

/// A still nozzle's dents over `t` seconds.
fn still(t: f64, seed: u64) -> Vec<Dent> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..(RATE * t) as usize)
        .map(|_| {
            let (x, y) = draw(&mut rng);
            Dent::disc(x, y, RADIUS, rng.random_range(0.0..t))
        })
        .collect()
}

/// Expected dents per point at lateral offset `w` for one pass, from the footprint:
/// `RATE / SPEED` times the Gaussian density averaged with the dent's chord.
fn expected(w: f64) -> f64 {
    let n = 4000;
    let h = 2.0 * RADIUS / n as f64;
    let density =
        |y: f64| (-0.5 * (y / SIGMA).powi(2)).exp() / (SIGMA * (2.0 * std::f64::consts::PI).sqrt());
    let integral: f64 = (0..n)
        .map(|k| {
            let u = -RADIUS + (k as f64 + 0.5) * h;
            density(w - u) * 2.0 * (RADIUS * RADIUS - u * u).sqrt() * h
        })
        .sum();
    RATE / SPEED * integral
}

/// Dents of a nozzle travelling along +x at `SPEED` over `length` metres centred on
/// x = 0, once along each line `y = line`: arrivals at uniform times (a Poisson stream),
/// each dent placed at the footprint's draw plus where the nozzle then was.
fn moving(lines: &[f64], length: f64, seed: u64) -> Vec<Dent> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let duration = length / SPEED;
    let mut dents = Vec::new();
    for &line in lines {
        for _ in 0..(RATE * duration) as usize {
            let t = rng.random_range(0.0..duration);
            let (x, y) = draw(&mut rng);
            dents.push(Dent::disc(
                x - 0.5 * length + SPEED * t,
                y + line,
                RADIUS,
                t,
            ));
        }
    }
    dents
}

/// Share of `samples` random points of the part (x in `[-span, span]`, y in `[y0, y1]`)
/// inside at least one dent, by direct test against the dents near each point.
fn measured(dents: &[Dent], span: f64, (y0, y1): (f64, f64), samples: usize, seed: u64) -> f64 {
    // Dents bucketed by x in bins one dent diameter wide.
    let bin = 2.0 * RADIUS;
    let key = |x: f64| (x / bin).floor() as i64;
    let mut buckets: std::collections::HashMap<i64, Vec<(f64, f64)>> = Default::default();
    for d in dents {
        buckets.entry(key(d.x)).or_default().push((d.x, d.y));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let covered = (0..samples)
        .filter(|_| {
            let (x, y) = (rng.random_range(-span..span), rng.random_range(y0..y1));
            (key(x) - 1..=key(x) + 1).any(|k| {
                buckets.get(&k).is_some_and(|ds| {
                    ds.iter()
                        .any(|(dx, dy)| (dx - x).powi(2) + (dy - y).powi(2) <= RADIUS * RADIUS)
                })
            })
        })
        .count();
    covered as f64 / samples as f64
}

/// The profile's mean coverage over offsets in `[y0, y1)`.
fn predicted(points: &[(f64, f64)], (y0, y1): (f64, f64)) -> f64 {
    let inside: Vec<f64> = points
        .iter()
        .filter(|p| p.0 >= y0 && p.0 < y1)
        .map(|p| coverage(p.1))
        .collect();
    inside.iter().sum::<f64>() / inside.len() as f64
}

#[test]
fn one_pass_matches_the_footprint_and_a_nozzle_moved_dent_by_dent() {
    // Ten seconds of the still nozzle: 50,000 dents.
    let traverse = Traverse {
        speed: SPEED,
        direction: 0.0,
        pitch: None,
    };
    let band = 4.0 * RADIUS;
    let track = Track::new(&still(10.0, 1), traverse, RADIUS / 5.0, band).unwrap();
    assert!(
        (track.rate / RATE - 1.0).abs() < 1e-3,
        "rate {}",
        track.rate
    );
    // Against the footprint: within three standard errors and the band's bias (its
    // width squared over 24 times the curvature, 0.5 % at the centre).
    for w in [0.0, 0.5 * SIGMA, SIGMA, 2.0 * SIGMA] {
        let p = track
            .pass
            .iter()
            .min_by(|a, b| (a.offset - w).abs().total_cmp(&(b.offset - w).abs()))
            .unwrap();
        let e = expected(p.offset);
        println!(
            "w {:.2} mm: {:.4} +- {:.4} against {e:.4}",
            w * 1e3,
            p.dents,
            p.se
        );
        assert!(
            (p.dents - e).abs() <= 3.0 * p.se + 0.01 * e,
            "w {w}: {} +- {} against {e}",
            p.dents,
            p.se
        );
    }
    // Against a nozzle moved over 2 m (20 s, 100,000 fresh dents), measured on its
    // middle 1.8 m in 1 mm strips (over five seeds of the moved nozzle, the strips
    // scatter by 0.005 about the footprint, at most 0.011): the footprint's
    // `1 - exp(-n)` within 0.02 (what the model claims), and the profile from the
    // still nozzle's dents within 0.03 (that, plus the estimate's own noise).
    let dents = moving(&[0.0], 2.0, 2);
    let points: Vec<(f64, f64)> = track.pass.iter().map(|p| (p.offset, p.dents)).collect();
    let exact: Vec<(f64, f64)> = points.iter().map(|p| (p.0, expected(p.0))).collect();
    for k in -6..6 {
        let strip = (k as f64 * 1e-3, (k + 1) as f64 * 1e-3);
        let m = measured(&dents, 0.9, strip, 40_000, 100 + k as u64);
        let (c, e) = (predicted(&points, strip), predicted(&exact, strip));
        println!("strip {k:+} mm: measured {m:.4}, footprint {e:.4}, profile {c:.4}");
        assert!(
            (m - e).abs() < 0.02,
            "strip {strip:?}: measured {m}, footprint {e}"
        );
        assert!(
            (m - c).abs() < 0.03,
            "strip {strip:?}: measured {m}, profile {c}"
        );
    }
    // The full-coverage speed of the best line: its expected dents over ln 50.
    let (v98, passes) = track.full_coverage().unwrap();
    let peak = track.peak();
    assert!((v98 - SPEED * peak.dents / 50f64.ln()).abs() < 1e-12);
    assert_eq!(passes, (50f64.ln() / peak.dents).ceil() as u64);
}

#[test]
fn a_raster_matches_passes_moved_dent_by_dent() {
    // Passes 4 mm apart: about 2.5 dents per point, 91 % coverage, varying over the
    // pitch. Measured as above; the raster's profile is an average of many passes, so
    // it is held to 0.02.
    let pitch = 4e-3;
    let traverse = Traverse {
        speed: SPEED,
        direction: 0.0,
        pitch: Some(pitch),
    };
    let track = Track::new(&still(10.0, 3), traverse, RADIUS / 5.0, 4.0 * RADIUS).unwrap();
    let raster = track.raster.clone().unwrap();
    let (least, mean) = track.raster_range().unwrap();
    // The mean over a pitch is every dent's area over the pitch and the speed.
    let area = RATE * std::f64::consts::PI * RADIUS * RADIUS / (SPEED * pitch);
    assert!((mean / area - 1.0).abs() < 1e-2, "{mean} against {area}");
    assert!(least.dents < mean);
    // Eleven passes over 2 m, measured between the middle two, in four 1 mm strips.
    let lines: Vec<f64> = (-5..=5).map(|k| k as f64 * pitch).collect();
    let dents = moving(&lines, 2.0, 4);
    let points: Vec<(f64, f64)> = raster.iter().map(|p| (p.offset, p.dents)).collect();
    for k in 0..4 {
        let strip = (k as f64 * 1e-3, (k + 1) as f64 * 1e-3);
        let m = measured(&dents, 0.9, strip, 40_000, 200 + k as u64);
        let c = predicted(&points, strip);
        println!("strip {k} mm: measured {m:.4}, predicted {c:.4}");
        assert!(
            (m - c).abs() < 0.02,
            "strip {strip:?}: measured {m}, predicted {c}"
        );
    }
}

#[test]
fn the_coverage_command_prints_and_writes_the_moving_nozzle() {
    let t = tempfile::tempdir().unwrap();
    common::coverage_run(t.path());
    let args = [
        "coverage",
        "run/impacts.h5",
        "--no-h5",
        "--traverse-mm-s",
        "100",
        "--traverse-deg",
        "30",
        "--pitch-mm",
        "2",
        "--out",
        "c",
    ];
    let o = peenflow(&args, t.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("nozzle moving at 100 mm/s towards 30 deg")
            && text.contains("raster, passes 2 mm apart")
            && text.contains("full coverage (98 %")
            && !text.contains("not a steady stream"),
        "{text}"
    );
    for f in ["traverse.csv", "raster.csv", "traverse.png", "traverse.svg"] {
        assert!(t.path().join("c").join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path().join("c/coverage.json")).unwrap())
            .unwrap();
    let tr = &json["traverse"];
    let num = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(num(&tr["speed_m_s"]), 0.1);
    assert!((num(&tr["direction_deg"]) - 30.0).abs() < 1e-9);
    // Full coverage where the raster is least covered: its dents over ln 50.
    let least = num(&tr["raster"]["least_dents_per_point"]);
    let v98 = num(&tr["full_coverage_speed_m_s"]);
    assert!((v98 - 0.1 * least / 50f64.ln()).abs() < 1e-12, "{tr}");
    assert_eq!(
        tr["passes_for_full_coverage"].as_u64().unwrap(),
        (50f64.ln() / least).ceil() as u64
    );
    // The pass's profile holds every dent's area once (its sum across the track): over
    // the pitch, that is the raster's mean (both sums of points, each on its grid).
    let column = |f: &str, k: usize| -> Vec<f64> {
        std::fs::read_to_string(t.path().join("c").join(f))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
            .collect()
    };
    let (w, n) = (column("traverse.csv", 0), column("traverse.csv", 1));
    let total: f64 = n.iter().sum::<f64>() * (w[1] - w[0]);
    let mean = num(&tr["raster"]["mean_dents_per_point"]);
    assert!((total / 2e-3 / mean - 1.0).abs() < 1e-3, "{total} {mean}");
    // Coverage is 1 - exp(-n) row by row.
    let c = column("traverse.csv", 3);
    assert!(
        n.iter()
            .zip(&c)
            .all(|(n, c)| (c - (1.0 - (-n).exp())).abs() < 1e-12)
    );
    // Into the impact file too (/coverage/traverse), as h5py reads it.
    let mut with_h5: Vec<&str> = args.iter().copied().filter(|a| *a != "--no-h5").collect();
    *with_h5.last_mut().unwrap() = "c5";
    let o = peenflow(&with_h5, t.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    if common::have("python3", &["-c", "import h5py"]) {
        let o = std::process::Command::new("python3")
            .args([
                "-c",
                "import h5py,sys; g=h5py.File(sys.argv[1])['coverage/traverse']; \
                 n=g['pass_dents'][:]; r=g['raster_dents'][:]; \
                 print(g.attrs['speed_m_s'], g.attrs['pitch_m'], len(n), n.sum(), len(r), \
                 g.attrs['passes_for_full_coverage'])",
                "run/impacts.h5",
            ])
            .current_dir(t.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout);
        let f: Vec<f64> = out.split_whitespace().map(|x| x.parse().unwrap()).collect();
        assert_eq!((f[0], f[1], f[2] as usize), (0.1, 0.002, n.len()), "{out}");
        assert!((f[3] / n.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{out}");
        assert_eq!(
            f[5] as u64,
            tr["passes_for_full_coverage"].as_u64().unwrap()
        );
    }
    // Bad input: one line naming the option, exit 2.
    for (args, needle) in [
        (
            vec!["--pitch-mm", "2"],
            "--pitch-mm 2: give the traverse speed too",
        ),
        (
            vec!["--traverse-deg", "10"],
            "--traverse-deg 10: give the traverse speed",
        ),
        (
            vec!["--traverse-mm-s", "0"],
            "--traverse-mm-s 0: allowed (0, 100000]",
        ),
        (
            vec!["--traverse-mm-s", "5", "--traverse-deg", "400"],
            "--traverse-deg 400: allowed [-360, 360]",
        ),
        (
            vec!["--traverse-mm-s", "5", "--pitch-mm", "-1"],
            "--pitch-mm -1: allowed (0, 10000]",
        ),
    ] {
        let mut all = vec!["coverage", "run/impacts.h5", "--no-h5", "--out", "bad"];
        all.extend(args);
        let o = peenflow(&all, t.path());
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(needle) && e.trim().lines().count() == 1, "{e}");
        assert!(!t.path().join("bad").exists(), "bad input wrote files");
    }
    // The paper's batch of 30 shots is no steady stream: the figures come with a note.
    let o = peenflow(&["run", "-q", "--out", "batch"], t.path());
    assert!(o.status.code().unwrap() <= 1);
    let o = peenflow(
        &[
            "coverage",
            "batch/impacts.h5",
            "--no-h5",
            "--traverse-mm-s",
            "50",
            "--out",
            "cb",
        ],
        t.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("not a steady stream"));
}

#[test]
fn a_sweep_case_pools_its_seeds_unless_one_is_chosen() {
    let t = tempfile::tempdir().unwrap();
    let case = common::two_seed_sweep(t.path());
    let traverse = |extra: &[&str], out: &str| -> (serde_json::Value, String) {
        let mut args = vec![
            "coverage",
            case,
            "--no-h5",
            "--traverse-mm-s",
            "50",
            "--out",
            out,
        ];
        args.extend(extra);
        let o = peenflow(&args, t.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(t.path().join(out).join("coverage.json")).unwrap(),
        )
        .unwrap();
        (
            json["traverse"].clone(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    let (both, text) = traverse(&[], "both");
    assert!(text.contains("over the file's 2 seeds"), "{text}");
    let (one, _) = traverse(&["--seed", "1"], "one");
    let (two, _) = traverse(&["--seed", "2"], "two");
    assert_eq!(both["runs"].as_u64(), Some(2));
    assert_eq!(one["runs"].as_u64(), Some(1));
    let n = |v: &serde_json::Value| v["dents"].as_u64().unwrap();
    assert_eq!(n(&both), n(&one) + n(&two));
}
