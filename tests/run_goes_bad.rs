//! When a run goes bad anyway (here: shots so soft and fast that the Hertz overlap passes
//! half their radius), the run stops those shots with a message naming the shot, the time,
//! the cause and a fix, records the events in summary.json, writes only finite numbers,
//! and exits with status 1 ("ran, but").

use crate::common;
use common::*;
use std::fs;

#[test]
fn bad_runs_stop_the_shot_and_say_why() {
    let tmp = tempfile::tempdir().unwrap();
    fs::write(
        tmp.path().join("soft.toml"),
        r#"
duration_ms = 0.5
gravity_m_s2 = 0.0
[materials.jelly]
youngs_modulus_gpa = 0.00001
poisson_ratio = 0.45
density_kg_m3 = 7850.0
[shots]
material = "jelly"
[specimen]
material = "jelly"
[effects]
drag = false
lateral_force = false
[shots.feed]
type = "list"
[[shots.feed.shots]]
position_mm = [0.0, 0.0, 2.0]
velocity_m_s = [0.0, 0.0, -100.0]
[[shots.feed.shots]]
position_mm = [5.0, 0.0, 2.0]
velocity_m_s = [0.0, 0.0, -1.0]
"#,
    )
    .unwrap();
    let o = peenflow(&["run", "soft.toml", "--out", "out"], tmp.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stderr.contains("1 shot(s) had to be stopped"), "{stderr}");
    assert!(stdout.contains("event: shot 0 at t = "), "{stdout}");
    assert!(
        stdout.contains("overlaps the specimen by")
            && stdout.contains("Hertz contact does not hold there"),
        "{stdout}"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&fs::read(tmp.path().join("out/summary.json")).unwrap()).unwrap();
    let events = summary["events"].as_array().unwrap();
    assert_eq!(events.len(), 1);
    assert_eq!(events[0]["shot"], 0);
    assert!(events[0]["time_s"].as_f64().unwrap() > 0.0);
    assert!(
        events[0]["suggestion"]
            .as_str()
            .unwrap()
            .contains("youngs_modulus_gpa")
    );
    assert_eq!(summary["failed"], 1);
    // The other shot ran on; no NaN anywhere in the outputs.
    for f in ["impacts.csv", "shots.csv", "summary.json"] {
        let text = fs::read_to_string(tmp.path().join("out").join(f))
            .unwrap()
            .to_lowercase();
        assert!(!text.contains("nan") && !text.contains("inf"), "{f}");
    }
    let shots = fs::read_to_string(tmp.path().join("out/shots.csv")).unwrap();
    assert!(shots.lines().nth(1).unwrap().contains(",failed,"));
    assert!(shots.lines().nth(2).unwrap().contains(",active,"));
}
