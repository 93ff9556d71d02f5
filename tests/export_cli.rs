//! `peenflow export` and `peenflow run --export/--snapshots` from the command line:
//! VTK outputs read back, snapshot positions against direct runs, and bad input (missing
//! or corrupt impacts.h5, a template with an undefined variable, an empty selection, a
//! run without impacts, an unknown format) getting one clear line, a non-zero exit and no partial output.

use crate::common;
use common::*;
use std::fs;
use std::path::Path;

fn run_single(tmp: &Path) {
    let scene = root().join("examples/single_shot.toml");
    let o = peenflow(&["run", scene.to_str().unwrap(), "--out", "run", "-q"], tmp);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn fails_cleanly(tmp: &Path, args: &[&str], expected: &str) {
    let o = peenflow(args, tmp);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
    assert!(
        stderr.contains(expected),
        "{args:?}: expected `{expected}` in {stderr}"
    );
    assert!(!tmp.join("bad").exists(), "{args:?}: output created");
}

#[test]
fn export_bad_input_gets_one_line_and_no_output() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    run_single(t);
    fails_cleanly(
        t,
        &["export", "nope.h5", "-f", "calculix", "-o", "bad"],
        "nope.h5: cannot read impacts: no such file",
    );
    fs::write(
        t.join("corrupt.h5"),
        b"\x89HDF\r\n\x1a\ngarbage garbage garbage",
    )
    .unwrap();
    fails_cleanly(
        t,
        &["export", "corrupt.h5", "-f", "vtk", "-o", "bad"],
        "corrupt.h5: cannot read impacts: not a readable HDF5 file",
    );
    // A run's directory, or its CSV, for its impact file: the message names the file.
    let h5 = Path::new("run").join("impacts.h5").display().to_string();
    fails_cleanly(
        t,
        &["export", "run", "-f", "vtk", "-o", "bad"],
        &format!("run: cannot read impacts: is a directory; pass the run's impact file, {h5}"),
    );
    let csv = Path::new("run").join("impacts.csv").display().to_string();
    let o = peenflow(&["coverage", &csv, "--out", "bad"], t);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{csv}: cannot read impacts: not a readable HDF5 file"
        )) && stderr
            .trim_end()
            .ends_with(&format!("; the run's impact file is {h5}")),
        "{stderr}"
    );
    assert!(!t.join("bad").exists());
    fails_cleanly(
        t,
        &["export", ".", "-f", "vtk", "-o", "bad"],
        ".: cannot read impacts: is a directory, not an impact file (a run's impacts.h5)",
    );
    for (flag, value, expected) in [
        (
            "--window",
            "1,2,3",
            "--window 1,2,3: give x0,y0,x1,y1 in mm with x1 > x0 and y1 > y0",
        ),
        (
            "--window",
            "5,5,1,1",
            "--window 5,5,1,1: give x0,y0,x1,y1 in mm with x1 > x0 and y1 > y0",
        ),
        (
            "--time-window",
            "2,1",
            "--time-window 2,1: give t0,t1 in ms with t1 > t0",
        ),
        // A negative number is a value to check, not an unknown flag.
        (
            "--element-size-mm",
            "-1",
            "--element-size-mm -1: allowed 0.001 mm or more",
        ),
    ] {
        fails_cleanly(
            t,
            &[
                "export",
                "run/impacts.h5",
                "-f",
                "vtk",
                flag,
                value,
                "-o",
                "bad",
            ],
            expected,
        );
    }
    // A run that recorded no impact (1 ms: no shot reaches the specimen) has nothing to
    // export.
    fs::write(t.join("short.toml"), "duration_ms = 1.0\n").unwrap();
    let o = peenflow(&["run", "short.toml", "--out", "short", "-q"], t);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    fails_cleanly(
        t,
        &["export", "short/impacts.h5", "-f", "vtk", "-o", "bad"],
        "the file holds no impacts: the run recorded none (no shot reached the specimen in its duration); nothing to export",
    );
    fails_cleanly(
        t,
        &["export", "run/impacts.h5", "-f", "nastran", "-o", "bad"],
        "--format nastran: unknown format; allowed: abaqus, lsdyna, calculix, vtk, csv",
    );
    fails_cleanly(
        t,
        &[
            "export",
            "run/impacts.h5",
            "-f",
            "vtk",
            "--time-window",
            "0,1",
            "-o",
            "bad",
        ],
        "the selection is empty: 1 impacts in the file, none with time 0..1 ms",
    );
    fails_cleanly(
        t,
        &[
            "export",
            "run/impacts.h5",
            "-f",
            "calculix",
            "--target-material",
            "A5052",
            "--element-size-mm",
            "0.002",
            "-o",
            "bad",
        ],
        "allowed at most 2000000: select fewer or closer impacts (--window, --time-window, --first, --sample) or pass a larger --element-size-mm",
    );
    fs::write(
        t.join("my.j2"),
        "*HEADING\n{{ title }}\n{{ no_such_variable }}\n",
    )
    .unwrap();
    fails_cleanly(
        t,
        &[
            "export",
            "run/impacts.h5",
            "-f",
            "calculix",
            "--template",
            "my.j2",
            "--target-material",
            "A5052",
            "-o",
            "bad",
        ],
        "my.j2: line 3: undefined value",
    );
    fails_cleanly(
        t,
        &["export", "run/impacts.h5", "-f", "calculix", "-o", "bad"],
        "target material \"table2-steel\" has no yield strength: pass --target-material A5052",
    );
    // `run --export` refuses a deck it cannot build before running, not after: no output
    // directory is created.
    fails_cleanly(
        t,
        &["run", "--export", "abaqus", "-o", "bad"],
        "target material \"table2-steel\" has no yield strength: pass --target-material A5052",
    );
    fails_cleanly(
        t,
        &[
            "run",
            "--export",
            "calculix",
            "--target-material",
            "cheese",
            "-o",
            "bad",
        ],
        "--target-material cheese: unknown material; known: table2-steel",
    );
    // An existing output file is not overwritten without --force.
    let o = peenflow(&["export", "run/impacts.h5", "-f", "vtk", "-o", "good"], t);
    assert!(o.status.success());
    let o = peenflow(&["export", "run/impacts.h5", "-f", "vtk", "-o", "good"], t);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("exists; pass --force"));
}

#[test]
fn user_template_renders_with_the_model() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    run_single(t);
    fs::write(
        t.join("mine.j2"),
        "{{ shots|length }} shot(s), {{ nodes|length }} nodes, v_z = {{ shots[0].velocity[2]|g }} {{ units.length }}/s\n",
    )
    .unwrap();
    let o = peenflow(
        &[
            "export",
            "run/impacts.h5",
            "-f",
            "abaqus",
            "--template",
            "mine.j2",
            "--target-material",
            "A5052",
            "--units",
            "si",
            "-o",
            "out",
        ],
        t,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = fs::read_to_string(t.join("out/abaqus.inp")).unwrap();
    assert!(
        text.starts_with("1 shot(s), ") && text.contains("v_z = -60.14"),
        "{text}"
    );
}

#[test]
fn vtk_outputs_are_well_formed() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let o = peenflow(
        &[
            "run",
            "--out",
            "run",
            "-q",
            "--snapshots",
            "0.5",
            "--export",
            "vtk,calculix",
            "--target-material",
            "A5052",
        ],
        t,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let impacts = peenflow::export::hdf5::read(&t.join("run/impacts.h5"))
        .unwrap()
        .impacts;
    let vtp = fs::read_to_string(t.join("run/impacts.vtp")).unwrap();
    assert!(vtp.contains(&format!("NumberOfPoints=\"{}\"", impacts.len())));
    assert!(vtp.contains("Name=\"velocity_m_s\" NumberOfComponents=\"3\""));
    let pvd = fs::read_to_string(t.join("run/snapshots/shots.pvd")).unwrap();
    assert_eq!(
        pvd.matches("<DataSet").count(),
        21,
        "10 ms every 0.5 ms, from 0"
    );
    for k in 0..21 {
        assert!(t.join(format!("run/snapshots/shots_{k:05}.vtp")).exists());
    }
    // Every VTK file is well-formed XML with consistent counts (python's XML parser), and
    // meshio reads the FE model's unstructured grid.
    let check = r#"
import sys, glob, xml.etree.ElementTree as ET
d = sys.argv[1]
for f in glob.glob(d + "/*.vtp") + glob.glob(d + "/snapshots/*.vtp"):
    piece = ET.parse(f).getroot().find("PolyData/Piece")
    n = int(piece.get("NumberOfPoints"))
    for a in piece.iter("DataArray"):
        comps = int(a.get("NumberOfComponents", "1"))
        vals = a.text.split() if a.text else []
        if a.get("Name") in ("connectivity", "offsets"):
            assert len(vals) == n, (f, a.get("Name"))
        else:
            assert len(vals) == n * comps, (f, a.get("Name"), len(vals), n, comps)
try:
    import meshio
    m = meshio.read(d + "/fe_model.vtu")
    assert len(m.points) > 100 and m.cells[0].type == "hexahedron"
except ImportError:
    pass
print("ok")
"#;
    let o = std::process::Command::new("python3")
        .args(["-c", check])
        .arg(t.join("run"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn snapshot_positions_match_runs_that_stop_there() {
    // The lone shot recorded every 0.5 ms (Hermite interpolation between steps) against
    // runs of the same scene that end at those times: within 1 um.
    let text = fs::read_to_string(root().join("examples/single_shot.toml")).unwrap();
    let scene = peenflow::scene::Scene::from_toml(&text, "single").unwrap();
    let mut sim = peenflow::sim::Simulation::new(&scene, &scene.effects()).unwrap();
    sim.record_snapshots(0.5e-3);
    let out = sim.run(&|_| {});
    assert_eq!(out.snapshots.len(), 11);
    for (t, pts) in out.snapshots.iter().skip(1).step_by(2) {
        let mut s2 = scene.clone();
        s2.duration = *t;
        let direct = peenflow::sim::Simulation::new(&s2, &s2.effects())
            .unwrap()
            .run(&|_| {});
        let p = direct.shots[0].pos;
        let q = pts[0].position;
        let d = ((p.x - q[0]).powi(2) + (p.y - q[1]).powi(2) + (p.z - q[2]).powi(2)).sqrt();
        println!("t = {t}: snapshot vs direct {d:.3e} m");
        assert!(d < 1e-6, "t = {t}: {d}");
    }
}
