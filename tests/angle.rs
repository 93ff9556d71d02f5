//! Peening angle: the nozzle tilted from the specimen normal. The jet field and the bore
//! are carried in the nozzle frame, so a shot on the axis flies the same path relative to
//! the nozzle whatever the tilt (gravity off). A tilted shot touches the specimen when its
//! centre is R above it, i.e. at the axial distance l - R/cos(tilt), so it must match a
//! vertical nozzle whose stand-off puts the touch at the same axial distance: same impact
//! speed (to 1e-7), contact point at x = -R/tan(angle), impact angle from the normal =
//! 90 deg - peening angle. Rotating the tilt's azimuth rotates the impacts (to 1e-9).

use crate::common;
use common::*;
use peenflow::scene::Scene;
use peenflow::sim::Simulation;

fn lone_shot(angle: f64, azimuth: f64) -> peenflow::record::Impact {
    lone_shot_at(angle, azimuth, 100.0)
}

fn lone_shot_at(angle: f64, azimuth: f64, standoff_mm: f64) -> peenflow::record::Impact {
    // The shot starts in the inlet plane on the axis: place it through the nozzle frame.
    let text = format!(
        "duration_ms = 8.0\ngravity_m_s2 = 0.0\n[integrator]\ntolerance = 1e-9\n[nozzle]\nangle_deg = {angle}\nazimuth_deg = {azimuth}\nstandoff_mm = {standoff_mm}\n[effects]\nshot_shot_contact = false\n[shots.feed]\ntype = \"batch\"\ncount = 1\nradial_offset_mm = [0.0, 0.0]\naxial_spread_mm = 0.0\n"
    );
    let scene = Scene::from_toml(&text, "angle").unwrap();
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    out.impacts[0].clone()
}

#[test]
fn tilt_keeps_the_on_axis_flight_and_sets_the_impact_angle() {
    assert!(lone_shot(90.0, 0.0).angle_deg.abs() < 1e-6);
    for angle in [30.0, 45.0, 60.0, 75.0] {
        let m = lone_shot(angle, 0.0);
        let r_mm = 0.5 * m.diameter_m * 1e3;
        let tilt = (90.0f64 - angle).to_radians();
        let normal = lone_shot_at(90.0, 0.0, 100.0 - r_mm / tilt.cos() + r_mm);
        println!(
            "angle {angle}: speed {:.9} m/s (vertical equivalent {:.9}) at ({:.3e}, {:.1e}), impact angle {:.4} deg",
            m.speed_m_s, normal.speed_m_s, m.x_m, m.y_m, m.angle_deg
        );
        assert!(
            rel(m.speed_m_s, normal.speed_m_s) < 1e-7,
            "speed {} vs {}",
            m.speed_m_s,
            normal.speed_m_s
        );
        // The centre touches R above the plane, upstream of the axis foot.
        let r = 0.5 * m.diameter_m;
        let expected_x = -r / angle.to_radians().tan();
        assert!(
            (m.x_m - expected_x).abs() < 1e-6 && m.y_m.abs() < 1e-9,
            "{} vs {expected_x}",
            m.x_m
        );
        assert!(
            (m.angle_deg - (90.0 - angle)).abs() < 1e-4,
            "{}",
            m.angle_deg
        );
        assert!(m.vx_m_s > 0.0, "shots travel towards +x for azimuth 0");
    }
}

#[test]
fn azimuth_rotates_the_impacts() {
    let a = lone_shot(60.0, 0.0);
    let b = lone_shot(60.0, 90.0);
    assert!(
        (b.x_m + a.y_m).abs() < 1e-9 && (b.y_m - a.x_m).abs() < 1e-9,
        "({}, {}) vs ({}, {})",
        b.x_m,
        b.y_m,
        a.x_m,
        a.y_m
    );
    assert!((b.vx_m_s + a.vy_m_s).abs() < 1e-6 && (b.vy_m_s - a.vx_m_s).abs() < 1e-6);
    assert!((a.speed_m_s - b.speed_m_s).abs() < 1e-9 * a.speed_m_s);
}

#[test]
fn angle_examples_run_and_hit_off_centre() {
    for a in [45, 60] {
        let scene = Scene::load(&root().join(format!("examples/angle_{a}.toml"))).unwrap();
        let out = Simulation::new(&scene, &scene.effects())
            .unwrap()
            .run(&|_| {});
        assert!(out.events.is_empty());
        let first: Vec<_> = out.impacts.iter().filter(|m| m.first_hit == 1).collect();
        assert!(first.len() > 10);
        let mean_angle = first.iter().map(|m| m.angle_deg).sum::<f64>() / first.len() as f64;
        println!(
            "{a} deg: {} first hits, mean impact angle {mean_angle:.1} deg from the normal",
            first.len()
        );
        assert!((mean_angle - (90.0 - a as f64)).abs() < 10.0);
    }
}
