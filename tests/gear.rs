//! A spur gear (`[specimen] shape = "gear"`, beyond the paper), against theory. The
//! test computes the gear's surface from textbook gear geometry, not from the library's
//! pieces:
//! * the flank at the pitch circle: a standard gear's tooth space is half the circular
//!   pitch wide there (`tau / 4` either side of its middle), and the involute's normal
//!   makes the pressure angle with the pitch circle's tangent;
//! * the root fillet where the rack's rounded tooth corner cuts it with its contact
//!   normal at 45 degrees: by the law of gearing that normal runs through the pitch
//!   point, which fixes the rolling angle;
//! * the root and the tip circles, and the tip edge's circle, `rho_e` from both the
//!   tip circle and the flank.
//!
//! Shots thrown along the normal at each of them, on both sides of a tooth space and
//! in the next one, on the gear as cut and turned, rebound straight back with the
//! restitution and are recorded at the point aimed at; a nozzle stream hits every zone,
//! the same on one and two threads, and leaves no shot inside the gear; a gear that
//! cannot be cut, or keys of other shapes, are refused with the key named; a turning
//! gear's coverage takes runs on the gear (its teeth checked, a rack's run refused
//! among them, the zones tiling the gear's own period).

use crate::common;
use common::*;
use peenflow::Vec3;
use peenflow::scene::Scene;
use std::f64::consts::PI;

/// Shot radius, mm.
const R: f64 = 0.4;
/// The test gear, mm, degrees: teeth, module, pressure angle, root fillet radius (the
/// rack's corner), tip edge radius; standard addendum (1 m) and dedendum (1.25 m).
const TEETH: f64 = 24.0;
const MODULE: f64 = 2.0;
const ALPHA: f64 = 20.0;
const FILLET: f64 = 0.76;
const EDGE: f64 = 0.4;

fn gear_lines(offset: f64) -> String {
    format!(
        "[specimen]\nshape = \"gear\"\nteeth = {TEETH}\nmodule_mm = {MODULE:?}\n\
         pressure_angle_deg = {ALPHA:?}\nradius_mm = {FILLET:?}\nedge_radius_mm = {EDGE:?}\n\
         offset_mm = {offset:?}\n"
    )
}

/// A scene without air or gravity onto `specimen`, restitution 0.7, with `shots`
/// (position mm, velocity m/s).
fn scene(specimen: &str, shots: &[(Vec3, Vec3)], duration_ms: f64) -> Scene {
    airless_scene(specimen, shots, duration_ms, 2.0 * R, "", "gear.toml")
}

/// Surface points and normals of the test gear ([`gear_zone_points`]).
fn zone_points() -> Vec<(&'static str, Point, Point)> {
    gear_zone_points(TEETH, MODULE, ALPHA, FILLET, EDGE)
}

/// Each zone's point on the right and the left of the tooth space under the jet and
/// on the right of the next one, with the gear turned by `offset` mm of pitch-circle
/// arc, 4 mm apart along the axis: (zone, point mm, normal) in the world (axis along
/// y, `across` = +x, the root circle's top at the origin before turning).
fn aimed_points(offset: f64) -> Vec<(&'static str, Vec3, Vec3)> {
    let tau = 2.0 * PI / TEETH;
    let r_p = TEETH * MODULE / 2.0;
    let r_f = r_p - 1.25 * MODULE;
    let mut out = Vec::new();
    for (name, (x, y), (nx, ny)) in zone_points() {
        for (side, k) in [(1.0, 0.0), (-1.0, 0.0), (1.0, 1.0)] {
            let r = offset / r_p + k * tau;
            let world = |v: Point| {
                let vx = side * v.0;
                (vx * r.cos() + v.1 * r.sin(), -vx * r.sin() + v.1 * r.cos())
            };
            let (ps, pz) = world((x, y));
            let (ns, nz) = world((nx, ny));
            let along = 4.0 * out.len() as f64;
            out.push((name, Vec3::new(ps, along, pz - r_f), Vec3::new(ns, 0.0, nz)));
        }
    }
    out
}

#[test]
fn shots_thrown_along_the_normal_rebound_straight_back_in_every_zone_of_a_gear() {
    for offset in [0.0, 1.3] {
        for speed in [10.0, 60.0] {
            let aimed = aimed_points(offset);
            let shots: Vec<(Vec3, Vec3)> = aimed
                .iter()
                .map(|(_, p, n)| (p + n * (R + 0.3), n * -speed))
                .collect();
            let out = run_scene(&scene(&gear_lines(offset), &shots, 0.05));
            assert!(out.events.is_empty(), "{:?}", out.events);
            assert_eq!(out.impacts.len(), shots.len(), "offset {offset}");
            let mut worst: f64 = 0.0;
            for (s, (zone, _, n)) in out.shots.iter().zip(&aimed) {
                assert_eq!(s.hits, 1, "{zone}");
                let back = s.vel.dot(n);
                let err = (back / (0.7 * speed) - 1.0).abs();
                println!("offset {offset} {speed} m/s {zone}: {err:.2e}");
                worst = worst.max(err);
                let sideways = (s.vel - n * back).norm();
                assert!(sideways < 1e-8 * speed, "{zone}: sideways {sideways:e}");
            }
            assert!(worst < 2e-5, "offset {offset} at {speed} m/s: {worst:e}");
            for imp in &out.impacts {
                let (zone, p, n) = &aimed[imp.shot as usize];
                let point = Vec3::new(imp.x_m, imp.y_m, imp.z_m) * 1e3;
                assert!((point - p).norm() < 1e-8, "{zone}: {point:?} vs {p:?}");
                let centre = Vec3::new(imp.center_x_m, imp.center_y_m, imp.center_z_m) * 1e3;
                assert!(((centre - point) - n * R).norm() < 1e-8, "{zone}");
                assert!((imp.normal_speed_m_s / speed - 1.0).abs() < 1e-9, "{imp:?}");
            }
        }
    }
}

#[test]
fn a_stream_onto_a_gear_hits_every_zone_and_is_the_same_on_one_and_two_threads() {
    // (Turned by a quarter pitch: a tooth's tip under the jet's edge.)
    let text = format!(
        "duration_ms = 8.0\n{}[shots.feed]\ntype = \"stream\"\nrate_per_s = 20000.0\n",
        gear_lines(1.5)
    );
    let scene = Scene::from_toml(&text, "gear_stream.toml").unwrap();
    let said = &scene.effects().decisions[3];
    assert!(
        said.reason.ends_with(
            "; a spur gear of 24 teeth, module 2 mm, pressure angle 20 degrees, root, pitch \
             and tip circles 43 / 48 / 52 mm in diameter, root fillets cut by a 0.76 mm tool \
             radius, tip edges of 0.4 mm, its axis at 90 degrees from +x, turned 1.5 mm along \
             its pitch circle from a tooth space's middle under the jet axis' foot"
        ),
        "{}",
        said.reason
    );
    let one = run_scene_on(1, &scene);
    let two = run_scene_on(2, &scene);
    assert_eq!(one.impacts, two.impacts);
    assert_eq!(one.shots, two.shots);
    assert!(one.events.is_empty(), "{:?}", one.events);
    let shape = scene.specimen_shape;
    let peenflow::contact::specimen::SpecimenShape::Groove(g) = &shape else {
        panic!("not a gear")
    };
    assert_eq!(g.gear().map(|g| g.teeth()), Some(24));
    check_every_zone_hit(&one, &shape);
}

#[test]
fn gears_that_cannot_be_cut_and_keys_of_other_shapes_are_refused() {
    let err = |specimen: &str| {
        Scene::from_toml(
            &format!("[shots]\ndiameter_mm = 0.8\n{specimen}"),
            "bad.toml",
        )
        .unwrap_err()
        .to_string()
    };
    let cases = [
        (
            "[specimen]\nshape = \"gear\"\nmodule_mm = 2.0\n",
            "specimen.teeth",
            "needs teeth",
        ),
        (
            "[specimen]\nshape = \"gear\"\nteeth = 12\nmodule_mm = 2.0\n",
            "specimen.teeth",
            "undercut the flanks (not modelled); use teeth >= 18",
        ),
        (
            "[specimen]\nshape = \"gear\"\nteeth = 24\nmodule_mm = 2.0\naddendum_mm = 3.9\n",
            "specimen.teeth",
            "come to a point",
        ),
        (
            "[specimen]\nshape = \"gear\"\nteeth = 24\nmodule_mm = 2.0\ndepth_mm = 4.5\n",
            "specimen.depth_mm",
            "leave this key out",
        ),
        (
            "[specimen]\nshape = \"groove\"\nradius_mm = 1.0\ndepth_mm = 4.0\nteeth = 24\n",
            "specimen.teeth",
            "only a gear has this dimension",
        ),
        (
            "[specimen]\nshape = \"gear\"\nteeth = 24\nmodule_mm = 2.0\nradius_mm = 1.2\n",
            "specimen.radius_mm",
            "use radius_mm <=",
        ),
        (
            "[specimen]\nshape = \"gear\"\nteeth = 24\nmodule_mm = 1.0\n",
            "specimen.radius_mm",
            "from 1.5 times the largest shot's radius",
        ),
    ];
    for (text, key, what) in cases {
        let e = err(text);
        assert!(e.contains(key) && e.contains(what), "{text}: {e}");
        assert!(e.contains("bad.toml"), "{e}");
    }
}

/// A turning gear's coverage from runs on the gear itself (`peenflow coverage
/// --gear-teeth`): its teeth must be the gear's, and a rack's run does not mix with the
/// gear's; with the right teeth the profile's period is the gear's own.
#[test]
fn a_turning_gears_coverage_takes_runs_on_the_gear() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let stream = "duration_ms = 4.0\n[shots.feed]\ntype = \"stream\"\nrate_per_s = 20000.0\n";
    let rack = "[specimen]\nshape = \"groove\"\nradius_mm = 0.76\nbottom_mm = 0.5\n\
                flank_deg = 20.0\ndepth_mm = 4.5\nedge_radius_mm = 0.4\npitch_mm = 6.283\n";
    for (name, text) in [
        ("a", format!("{stream}{}", gear_lines(0.0))),
        ("b", format!("{stream}{}", gear_lines(2.5))),
        ("r", format!("{stream}{rack}")),
    ] {
        std::fs::write(dir.join(format!("{name}.toml")), text).unwrap();
        let o = peenflow(&["run", &format!("{name}.toml"), "--out", name, "-q"], dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let cov = |files: &[&str], teeth: &str, out: &str| {
        let mut args = vec!["coverage"];
        args.extend(files);
        args.extend(["--gear-teeth", teeth, "--traverse-mm-s", "1", "--out", out]);
        peenflow(&args, dir)
    };
    let o = cov(&["a/impacts.h5", "b/impacts.h5"], "23", "wrong");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(
            "--gear-teeth 23: the runs' gear has 24 teeth ([specimen] teeth); give --gear-teeth 24"
        ),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let written = |out: &str| {
        std::fs::read_dir(dir.join(out))
            .map(|d| d.count())
            .unwrap_or(0)
    };
    assert_eq!(written("wrong"), 0);
    let o = cov(&["a/impacts.h5", "r/impacts.h5"], "24", "mixed");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("differs from") && err.contains("in more than offset_mm"),
        "{err}"
    );
    assert_eq!(written("mixed"), 0);
    let o = cov(&["a/impacts.h5", "b/impacts.h5"], "24", "cov");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("cov/gear.json")).unwrap()).unwrap();
    println!("{}", serde_json::to_string_pretty(&json["zones"]).unwrap());
    // The zones tile the gear's period, the arc over one tooth space and one tooth.
    let (_, scene) = peenflow::export::read_impact_file(&dir.join("a/impacts.h5")).unwrap();
    let peenflow::contact::specimen::SpecimenShape::Groove(g) = &scene.specimen_shape else {
        panic!("not a gear")
    };
    let period = g.period_arc().unwrap();
    let total: f64 = json["zones"]
        .as_array()
        .unwrap()
        .iter()
        .map(|z| z["arc_m"].as_f64().unwrap())
        .sum();
    assert!((total - period).abs() < 1e-9, "{total} against {period}");
}
