//! Sweeps: sharded + merged equals a single run; a killed sweep resumes without
//! re-running finished cases and ends equal to an uninterrupted one; per-case numbers
//! equal separate `run`s; bad sweep files get one-line errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant, SystemTime};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_peenflow"))
}

fn ok(o: Output) -> String {
    assert!(
        o.status.success(),
        "peenflow failed: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// 2 pressures x 2 shot counts x 2 seeds on the Table 2 scene.
const SMALL: &str = r#"title = "test sweep"
seeds = [1, 2]
[vary]
"air.gauge_pressure_mpa" = [0.4, 0.6]
"shots.feed.count" = { from = 10, to = 20, steps = 2 }
"#;

fn write_sweep(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn sweep(file: &Path, out: &Path, extra: &[&str]) -> String {
    ok(bin()
        .arg("sweep")
        .arg(file)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap())
}

#[test]
fn two_shards_merged_equal_one_run() {
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(t.path(), "s.toml", SMALL);
    let one = t.path().join("one");
    sweep(&f, &one, &["-j", "2"]);
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    let sa = sweep(&f, &a, &["--shard", "1/2", "-j", "1"]);
    let sb = sweep(&f, &b, &["--shard", "2/2"]);
    assert!(sa.contains("shard 1/2: ran 2 case(s)"), "{sa}");
    assert!(sb.contains("shard 2/2: ran 2 case(s)"), "{sb}");
    assert!(!a.join("sweep.h5").exists(), "a shard must not assemble");
    let merged = t.path().join("merged");
    let m = ok(bin()
        .arg("merge")
        .arg(&a)
        .arg(&b)
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap());
    assert!(m.contains("merged 4 case(s)"), "{m}");
    // The same file, byte for byte (every dataset and attribute equal).
    let x = std::fs::read(one.join("sweep.h5")).unwrap();
    let y = std::fs::read(merged.join("sweep.h5")).unwrap();
    assert!(x == y, "merged sweep.h5 differs from the single run's");
    assert_eq!(
        std::fs::read(one.join("cases.csv")).unwrap(),
        std::fs::read(merged.join("cases.csv")).unwrap()
    );
    // Merging into the first shard's directory works too.
    ok(bin().arg("merge").arg(&a).arg(&b).output().unwrap());
    assert!(std::fs::read(a.join("sweep.h5")).unwrap() == x);
    // Every case directory is there and its impacts export like a run's.
    let case = std::fs::read_dir(&merged)
        .unwrap()
        .filter_map(|e| e.ok())
        .find(|e| e.file_name().to_string_lossy().starts_with("case-000"))
        .unwrap()
        .path();
    ok(bin()
        .arg("export")
        .arg(case.join("impacts.h5"))
        .args(["-f", "csv", "--out"])
        .arg(t.path().join("exp"))
        .output()
        .unwrap());
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

fn finished_cases(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.filter_map(|e| e.ok())
                .filter(|e| e.path().join("case.json").is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| !n.starts_with('.'))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn killed_sweep_resumes_and_ends_equal() {
    let t = tempfile::tempdir().unwrap();
    // 8 cases x 2 seeds, one thread: long enough to be killed part-way.
    let text = r#"seeds = 2
[vary]
"air.gauge_pressure_mpa" = [0.3, 0.4, 0.5, 0.6]
"shots.diameter_mm" = [0.6, 0.8]
"#;
    let f = write_sweep(t.path(), "k.toml", text);
    let full = t.path().join("full");
    sweep(&f, &full, &["-j", "1"]);
    let dir = t.path().join("killed");
    let mut child = bin()
        .arg("sweep")
        .arg(&f)
        .arg("--out")
        .arg(&dir)
        .args(["-j", "1", "-q"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while finished_cases(&dir).is_empty() {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no case finished"
        );
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().ok();
    child.wait().unwrap();
    let done = finished_cases(&dir);
    assert!(
        !done.is_empty() && done.len() < 8,
        "the kill should land part-way: {} cases finished",
        done.len()
    );
    assert!(!dir.join("sweep.h5").exists());
    // Every case directory present is complete (the rest are hidden temporaries).
    for d in std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()) {
        let n = d.file_name().to_string_lossy().into_owned();
        if d.path().is_dir() && !n.starts_with('.') {
            for f in [
                "case.json",
                "impacts.h5",
                "scene.toml",
                "speed.png",
                "radius.svg",
            ] {
                assert!(d.path().join(f).is_file(), "{n} lacks {f}");
            }
        }
    }
    let stamps: Vec<SystemTime> = done
        .iter()
        .map(|c| mtime(&dir.join(c).join("case.json")))
        .collect();
    let out = sweep(&f, &dir, &["-j", "2"]);
    assert!(
        out.contains(&format!(
            "ran {} case(s), skipped {} finished",
            8 - done.len(),
            done.len()
        )),
        "{out}"
    );
    for (c, s) in done.iter().zip(&stamps) {
        assert_eq!(mtime(&dir.join(c).join("case.json")), *s, "{c} was re-run");
    }
    let leftovers: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporaries left: {leftovers:?}");
    assert!(
        std::fs::read(dir.join("sweep.h5")).unwrap()
            == std::fs::read(full.join("sweep.h5")).unwrap(),
        "resumed sweep.h5 differs from the uninterrupted one"
    );
}

#[test]
fn per_case_numbers_equal_separate_runs() {
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(t.path(), "s.toml", SMALL);
    let out = t.path().join("sw");
    sweep(&f, &out, &[]);
    let case = out.join("case-003_gauge_pressure_mpa-0.6_count-20");
    let cj: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(case.join("case.json")).unwrap()).unwrap();
    let mut speed_means = Vec::new();
    for (k, seed) in [1u64, 2].iter().enumerate() {
        let rdir = t.path().join(format!("run{seed}"));
        ok(bin()
            .arg("run")
            .arg(case.join("scene.toml"))
            .args(["--seed", &seed.to_string(), "-q", "--out"])
            .arg(&rdir)
            .output()
            .unwrap());
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(rdir.join("summary.json")).unwrap())
                .unwrap();
        let r = &cj["runs"][k];
        assert_eq!(r["seed"], *seed);
        assert_eq!(r["shots"], s["shots"]);
        assert_eq!(r["shots_hit"], s["shots_hit"]);
        assert_eq!(r["impacts"], s["impacts"]);
        assert_eq!(r["stats"]["hit_fraction"], s["hit_fraction"]);
        assert_eq!(r["stats"]["speed_mean_m_s"], s["normal_speed_m_s"]["mean"]);
        assert_eq!(r["stats"]["speed_p90_m_s"], s["normal_speed_m_s"]["p90"]);
        let p90_mm = s["radius_m"]["p90"].as_f64().unwrap() * 1e3;
        assert_eq!(r["stats"]["radius_p90_mm"].as_f64().unwrap(), p90_mm);
        speed_means.push(s["normal_speed_m_s"]["mean"].as_f64().unwrap());
    }
    // The case statistic is the mean over seeds, with a t-interval around it.
    let st = &cj["stats"]["speed_mean_m_s"];
    let mean = (speed_means[0] + speed_means[1]) / 2.0;
    assert!((st["mean"].as_f64().unwrap() - mean).abs() < 1e-12 * mean);
    let sd = (speed_means[0] - speed_means[1]).abs() / 2f64.sqrt();
    let half = 12.706204736 * sd / 2f64.sqrt(); // t_{0.975, 1}
    assert!((st["ci_high"].as_f64().unwrap() - mean - half).abs() < 1e-6 * mean);
    // The impacts in the case file are the two runs' impacts, seed by seed.
    let csv1 = std::fs::read_to_string(t.path().join("run1/impacts.csv")).unwrap();
    let csv2 = std::fs::read_to_string(t.path().join("run2/impacts.csv")).unwrap();
    let n = csv1.lines().count() + csv2.lines().count() - 2;
    assert_eq!(
        cj["runs"][0]["impacts"].as_u64().unwrap() as usize
            + cj["runs"][1]["impacts"].as_u64().unwrap() as usize,
        n
    );
}

fn sweep_err(text: &str, extra: &[&str]) -> String {
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(t.path(), "bad.toml", text);
    let o = bin()
        .arg("sweep")
        .arg(&f)
        .arg("--out")
        .arg(t.path().join("out"))
        .args(extra)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "expected exit 2 for:\n{text}");
    assert!(
        !t.path().join("out").exists(),
        "a rejected sweep must not create its output directory"
    );
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(e.trim().lines().count(), 1, "one line expected: {e}");
    e
}

#[test]
fn bad_sweep_files_get_one_line_errors() {
    let e = sweep_err("[vary]\n\"air.gauge_presure_mpa\" = [0.3]\n", &[]);
    assert!(
        e.contains("bad.toml")
            && e.contains("air.gauge_presure_mpa")
            && e.contains("did you mean `gauge_pressure_mpa`"),
        "{e}"
    );
    let e = sweep_err("[vary]\n\"nozzle.bore\" = [6.0]\n", &[]);
    assert!(
        e.contains("unknown key `bore`") && e.contains("bore_mm"),
        "{e}"
    );
    let e = sweep_err(
        "seed = 3\n[vary]\n\"air.gauge_pressure_mpa\" = [0.3]\n",
        &[],
    );
    assert!(
        e.contains("unknown key `seed`; did you mean `seeds`?"),
        "{e}"
    );
    let e = sweep_err("[vary]\n\"title.x\" = [1]\n", &[]);
    assert!(e.contains("names nothing"), "{e}");
    let e = sweep_err("[vary]\n\"air.gauge_pressure_mpa\" = []\n", &[]);
    assert!(
        e.contains("\"air.gauge_pressure_mpa\" = []") && e.contains("empty"),
        "{e}"
    );
    let e = sweep_err(
        "combine = \"zip\"\n[vary]\n\"air.gauge_pressure_mpa\" = [0.3, 0.6]\n\"shots.diameter_mm\" = [0.5]\n",
        &[],
    );
    assert!(
        e.contains("same length") && e.contains("has 1 values"),
        "{e}"
    );
    let e = sweep_err(
        "[vary]\n\"air.gauge_pressure_mpa\" = [0.3]\n",
        &["--shard", "3/2"],
    );
    assert!(e.contains("--shard 3/2") && e.contains("1..=2"), "{e}");
    let e = sweep_err("[vary]\n\"air.gauge_pressure_mpa\" = [0.3, 50.0]\n", &[]);
    assert!(
        e.contains("= 50") && e.contains("allowed (0, 5] MPa"),
        "{e}"
    );
    let e = sweep_err(
        "[vary]\n\"air.gauge_pressure_mpa\" = { from = 0.2, to = 0.6, step = 3 }\n",
        &[],
    );
    assert!(e.contains("did you mean `steps`"), "{e}");
    let e = sweep_err(
        "seeds = 0\n[vary]\n\"air.gauge_pressure_mpa\" = [0.3]\n",
        &[],
    );
    assert!(e.contains("seeds = 0"), "{e}");
    let e = sweep_err("[vary]\n", &[]);
    assert!(e.contains("[vary] is empty"), "{e}");
    let e = sweep_err(
        "names = [\"a\"]\n[vary]\n\"air.gauge_pressure_mpa\" = [0.3, 0.4]\n",
        &[],
    );
    assert!(
        e.contains("names has 1 entries but the sweep has 2 cases"),
        "{e}"
    );
    let e = sweep_err("[vary]\n\"seed\" = [1, 2]\n", &[]);
    assert!(e.contains("`seeds`"), "{e}");
}

#[test]
fn ranges_expand_and_merge_rejects_foreign_shards() {
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(
        t.path(),
        "r.toml",
        "[vary]\n\"air.gauge_pressure_mpa\" = { from = 0.1, to = 0.4, steps = 4 }\n\"nozzle.standoff_mm\" = { from = 50, to = 200, steps = 3, scale = \"log\" }\n",
    );
    let list = ok(bin().arg("sweep").arg(&f).arg("--list").output().unwrap());
    assert!(list.contains("12 case(s)"), "{list}");
    for v in [
        "= 0.1,",
        "= 0.2,",
        "= 0.3,",
        "= 0.4,",
        "standoff_mm = 50",
        "standoff_mm = 100",
        "standoff_mm = 200",
    ] {
        assert!(list.contains(v), "{v} missing from\n{list}");
    }
    // Shards of different sweeps do not merge.
    let g = write_sweep(
        t.path(),
        "g.toml",
        "[vary]\n\"air.gauge_pressure_mpa\" = [0.5]\n",
    );
    let h = write_sweep(
        t.path(),
        "h.toml",
        "[vary]\n\"air.gauge_pressure_mpa\" = [0.6]\n",
    );
    sweep(&g, &t.path().join("g"), &["--shard", "1/1"]);
    sweep(&h, &t.path().join("h"), &["--shard", "1/1"]);
    let o = bin()
        .arg("merge")
        .arg(t.path().join("g"))
        .arg(t.path().join("h"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("not the sweep of"), "{e}");
    // A directory holding another sweep is refused.
    let o = bin()
        .arg("sweep")
        .arg(&h)
        .arg("--out")
        .arg(t.path().join("g"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds another sweep"));
}

#[test]
fn sweep_h5_reads_in_h5py() {
    let py = Command::new("python3").args(["-c", "import h5py"]).output();
    if !py.map(|o| o.status.success()).unwrap_or(false) {
        assert!(std::env::var_os("CI").is_none(), "h5py missing in CI");
        eprintln!("SKIPPED: h5py not installed");
        return;
    }
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(t.path(), "s.toml", SMALL);
    let out = t.path().join("sw");
    sweep(&f, &out, &[]);
    let script = r#"
import sys, h5py, csv
f = h5py.File(sys.argv[1], "r")
assert f.attrs["format"] == "peenflow-sweep-h5/1"
names = [n.decode() for n in f["cases/name"][:]]
assert len(names) == 4, names
p = f["cases/parameters/air.gauge_pressure_mpa"][:]
assert list(p) == [0.4, 0.4, 0.6, 0.6], p
n = f["cases/parameters/shots.feed.count"][:]
assert list(n) == [10, 20, 10, 20], n
case = f["impacts/case"][:]
seed = f["impacts/seed"][:]
assert set(case) <= {0, 1, 2, 3} and set(seed) <= {1, 2}
runs = f["runs/case"][:]
assert list(runs) == [0, 0, 1, 1, 2, 2, 3, 3]
hf = f["cases/stats/hit_fraction/mean"][:]
rows = list(csv.DictReader(open(sys.argv[2])))
for k, r in enumerate(rows):
    assert abs(float(r["hit_fraction_mean"]) - hf[k]) < 1e-12
    assert r["name"] == names[k]
counts = f["cases/radius_histogram/counts"]
assert counts.shape[0] == 4
print("ok", len(case))
"#;
    let o = Command::new("python3")
        .args(["-c", script])
        .arg(out.join("sweep.h5"))
        .arg(out.join("cases.csv"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn slurm_template_runs_shards_that_merge_to_a_single_run() {
    let t = tempfile::tempdir().unwrap();
    let f = write_sweep(t.path(), "s.toml", SMALL);
    let one = t.path().join("one");
    sweep(&f, &one, &[]);
    let out = t.path().join("cluster");
    let bin_path = env!("CARGO_BIN_EXE_peenflow");
    for k in 1..=2 {
        let o = Command::new("bash")
            .arg(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/templates/slurm_array.sh"
            ))
            .arg(&f)
            .arg(&out)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env("SLURM_CPUS_PER_TASK", "1")
            .env("PEENFLOW", bin_path)
            .output()
            .unwrap();
        ok(o);
    }
    ok(bin()
        .arg("merge")
        .arg(out.join("shard-1"))
        .arg(out.join("shard-2"))
        .arg("--out")
        .arg(out.join("all"))
        .output()
        .unwrap());
    assert!(
        std::fs::read(out.join("all/sweep.h5")).unwrap()
            == std::fs::read(one.join("sweep.h5")).unwrap()
    );
}
