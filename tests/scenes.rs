//! Scene files: every tests/scenes/good/*.toml and examples/*.toml loads (sweep files:
//! every case); every case of
//! tests/scenes/bad/*.toml (cases separated by `+++` lines, the expected message part on
//! a `#^` line) makes `peenflow run` exit with code 2 and one line naming the problem,
//! without a panic and without creating the output directory.

use crate::common;
use common::*;
use peenflow::scene::Scene;
use std::fs;

#[test]
fn good_scenes_and_examples_load() {
    let mut n = 0;
    for dir in ["tests/scenes/good", "examples"] {
        for entry in fs::read_dir(root().join(dir)).unwrap() {
            let p = entry.unwrap().path();
            if p.to_string_lossy().ends_with("_sweep.toml") {
                // A sweep file: every case must resolve to a valid, placeable scene.
                let plan = peenflow::sweep::Plan::load(&p)
                    .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                for c in &plan.cases {
                    peenflow::feed::initial_shots(&c.scene).unwrap_or_else(|e| panic!("{e}"));
                }
                n += 1;
            } else if p.extension().is_some_and(|e| e == "toml") {
                let scene = Scene::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                // Placement must succeed too.
                peenflow::feed::initial_shots(&scene).unwrap_or_else(|e| panic!("{e}"));
                n += 1;
            }
        }
    }
    assert!(n >= 10, "only {n} good scenes");
}

#[test]
fn bad_scenes_get_one_clear_message() {
    let tmp = tempfile::tempdir().unwrap();
    let mut n = 0;
    let mut files: Vec<_> = fs::read_dir(root().join("tests/scenes/bad"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for file in files {
        let text = fs::read_to_string(&file).unwrap();
        for (k, case) in text.split("\n+++\n").enumerate() {
            let expected: Vec<&str> = case
                .lines()
                .filter_map(|l| l.strip_prefix("#^"))
                .map(str::trim)
                .collect();
            assert!(
                !expected.is_empty(),
                "{} case {k}: no #^ line",
                file.display()
            );
            let case_file = tmp.path().join(format!("case{n}.toml"));
            fs::write(&case_file, case).unwrap();
            let out_dir = tmp.path().join(format!("out{n}"));
            let o = peenflow(
                &[
                    "run",
                    case_file.to_str().unwrap(),
                    "--out",
                    out_dir.to_str().unwrap(),
                ],
                tmp.path(),
            );
            let stderr = String::from_utf8_lossy(&o.stderr);
            let label = format!("{} case {k}", file.display());
            assert_eq!(
                o.status.code(),
                Some(2),
                "{label}: exit {:?}, stderr {stderr}",
                o.status
            );
            assert!(!stderr.contains("panicked"), "{label}: panic: {stderr}");
            assert_eq!(
                stderr.trim().lines().count(),
                1,
                "{label}: not one line: {stderr}"
            );
            assert!(
                stderr.contains(case_file.to_str().unwrap()),
                "{label}: file not named: {stderr}"
            );
            for e in expected {
                assert!(stderr.contains(e), "{label}: expected `{e}` in: {stderr}");
            }
            assert!(!out_dir.exists(), "{label}: output directory created");
            n += 1;
        }
    }
    assert!(n >= 25, "only {n} bad cases");
}

#[test]
fn missing_scene_file_and_existing_output_dir_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let o = peenflow(&["run", "no-such-scene.toml"], tmp.path());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr.contains("no-such-scene.toml: cannot read the scene file"),
        "{stderr}"
    );
    // The cause once, not once per link of the error chain.
    assert_eq!(
        stderr.matches("No such file or directory").count(),
        1,
        "{stderr}"
    );

    let out = tmp.path().join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("keep.txt"), "x").unwrap();
    let scene = root().join("examples/single_shot.toml");
    let o = peenflow(
        &["run", scene.to_str().unwrap(), "--out", "out"],
        tmp.path(),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr.contains("output directory exists and is not empty; pass --force"),
        "{stderr}"
    );
    let o = peenflow(
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            "out",
            "--force",
            "-q",
        ],
        tmp.path(),
    );
    assert!(o.status.success());
    assert!(out.join("impacts.csv").exists() && out.join("keep.txt").exists());
}

#[test]
fn init_writes_the_default_scene_which_loads() {
    let tmp = tempfile::tempdir().unwrap();
    let o = peenflow(&["init", "my.toml"], tmp.path());
    assert!(o.status.success());
    let scene = Scene::load(&tmp.path().join("my.toml")).unwrap();
    assert_eq!(
        scene,
        Scene::from_toml(peenflow::scene::DEFAULT_SCENE, &scene.path).unwrap()
    );
    // Refuses to overwrite.
    let o = peenflow(&["init", "my.toml"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn init_writes_every_example_and_lists_them() {
    use peenflow::scene::examples::EXAMPLES;
    // The embedded examples are exactly the files of examples/.
    let mut files: Vec<String> = fs::read_dir(root().join("examples"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "toml").then(|| p.file_stem().unwrap().to_string_lossy().into())
        })
        .collect();
    files.sort();
    let mut names: Vec<String> = EXAMPLES.iter().map(|e| e.name.to_string()).collect();
    names.sort();
    assert_eq!(
        names, files,
        "examples/ and scene::examples::EXAMPLES differ"
    );
    let tmp = tempfile::tempdir().unwrap();
    let list = peenflow(&["init", "--list"], tmp.path());
    assert!(list.status.success());
    let list = String::from_utf8_lossy(&list.stdout);
    for e in EXAMPLES {
        assert!(
            list.contains(&format!("{:<18} {}", e.name, e.about)),
            "{list}"
        );
        // Written byte for byte, to NAME.toml by default; it says how to run it.
        let o = peenflow(&["init", "--example", e.name], tmp.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let path = tmp.path().join(format!("{}.toml", e.name));
        assert_eq!(
            fs::read(&path).unwrap(),
            fs::read(root().join("examples").join(format!("{}.toml", e.name))).unwrap()
        );
        let command = if e.sweep {
            "peenflow sweep"
        } else {
            "peenflow run"
        };
        assert!(String::from_utf8_lossy(&o.stderr).contains(command));
    }
    // To a path of one's choice, or to standard output.
    let o = peenflow(&["init", "--example", "single_shot", "s.toml"], tmp.path());
    assert!(o.status.success());
    Scene::load(&tmp.path().join("s.toml")).unwrap();
    let o = peenflow(&["init", "--example", "angle_45", "-"], tmp.path());
    assert_eq!(
        o.stdout,
        fs::read(root().join("examples/angle_45.toml")).unwrap()
    );
    // An unknown name: one line with the names allowed; nothing written.
    let o = peenflow(&["init", "--example", "gear"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--example gear: no such example; allowed: single_shot, angle_45"),
        "{err}"
    );
    assert!(!tmp.path().join("gear.toml").exists());
}

#[test]
fn errors_doc_quotes_every_expected_message() {
    let doc = fs::read_to_string(root().join("docs/errors.md")).unwrap();
    for entry in fs::read_dir(root().join("tests/scenes/bad")).unwrap() {
        let text = fs::read_to_string(entry.unwrap().path()).unwrap();
        for line in text.lines().filter_map(|l| l.strip_prefix("#^")) {
            assert!(
                doc.contains(line.trim()),
                "docs/errors.md does not quote: {}",
                line.trim()
            );
        }
    }
}

#[test]
fn unwritable_output_is_refused_before_running() {
    let tmp = tempfile::tempdir().unwrap();
    fs::write(tmp.path().join("out.txt"), "x").unwrap();
    let o = peenflow(&["run", "--out", "out.txt"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("out.txt: exists and is not a directory"));
    let o = peenflow(&["run", "--out", "out.txt/sub"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("out.txt/sub: cannot write:") && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
}
