//! Friction and spin against rigid-body impact theory (e.g. Brach, "Mechanical Impact
//! Dynamics", 1991; Goldsmith 1960). A sphere (mass m, radius R, I = 2/5 m R^2) hits a
//! fixed plane with normal speed v_n and tangential speed v_t, no initial spin,
//! restitution e, Coulomb coefficient mu:
//! - sliding throughout when v_t > 7/2 mu (1 + e) v_n:
//!   v_t' = v_t - mu (1 + e) v_n,  omega' R = 5/2 mu (1 + e) v_n;
//! - otherwise the contact point stops slipping (rolling):
//!   v_t' = 5/7 v_t,  omega' R = v_t'.
//!
//! The normal rebound does not depend on friction. Two equal spheres: the same with the
//! pair's tangential mass m/7 (slip stops) or mu J_n (sliding).

use peenflow::Vec3;
use peenflow::scene::Scene;
use peenflow::sim::{RunOutput, Simulation};

const R: f64 = 0.4e-3;

fn run(text: &str) -> RunOutput {
    let scene = Scene::from_toml(text, "friction test").unwrap();
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    assert!(out.events.is_empty(), "{:?}", out.events);
    out
}

/// One 0.8 mm steel shot 0.1 mm above the specimen moving at (vt, 0, -vn); no jet, no
/// gravity; the run ends long after the rebound. `friction` goes before the
/// `[effects]` table, `switches` into it.
fn plane(vt: f64, vn: f64, friction: &str) -> RunOutput {
    plane_with(vt, vn, friction, "")
}

fn plane_with(vt: f64, vn: f64, friction: &str, switches: &str) -> RunOutput {
    run(&format!(
        r#"duration_ms = 0.1
gravity_m_s2 = 0.0
[shots]
diameter_mm = 0.8
[shots.feed]
type = "list"
[[shots.feed.shots]]
position_mm = [0.0, 0.0, 0.5]
velocity_m_s = [{vt}, 0.0, {}]
{friction}
[effects]
drag = false
lateral_force = false
nozzle_wall_contact = false
{switches}
"#,
        -vn
    ))
}

/// Rigid-body prediction (v_t', omega' R) for a sphere on a plane.
fn theory_plane(vt: f64, vn: f64, e: f64, mu: f64) -> (f64, f64) {
    if vt > 3.5 * mu * (1.0 + e) * vn {
        (vt - mu * (1.0 + e) * vn, 2.5 * mu * (1.0 + e) * vn)
    } else {
        (5.0 / 7.0 * vt, 5.0 / 7.0 * vt)
    }
}

#[test]
fn sphere_on_plane_matches_rigid_body_theory_in_both_regimes() {
    let (vn, mu) = (10.0, 0.3);
    // Threshold v_t = 3.5 * 0.3 * 1.7 * 10 = 17.85 m/s.
    let mut worst: f64 = 0.0;
    for vt in [1.0, 5.0, 10.0, 15.0, 17.0, 19.0, 25.0, 40.0, 80.0] {
        let out = plane(vt, vn, "[friction]\nshot_specimen = 0.3");
        let s = &out.shots[0];
        assert_eq!(s.hits, 1);
        let e = s.vel.z / vn; // measured normal restitution
        assert!((e - 0.7).abs() < 1e-3, "normal restitution {e}");
        let (vt_th, wr_th) = theory_plane(vt, vn, e, mu);
        // omega about +y rolls a shot moving along +x: contact-point speed v_x - omega_y R.
        let (vt_got, wr_got) = (s.vel.x, s.omega.y * R);
        let err = ((vt_got - vt_th).abs()).max((wr_got - wr_th).abs()) / vt;
        println!(
            "v_t {vt:5.1}: v_t' {vt_got:.6} (theory {vt_th:.6}), omega R {wr_got:.6} (theory {wr_th:.6}), error {err:.1e}"
        );
        // Near the regime threshold the slip stops late in the contact, where the stick
        // damping (which scales with overlap^(1/4)) is weak: the regularisation leaves a
        // residual slip there. Measured: 2.6e-3 at 0.95 of the threshold, 8e-4 at 0.84,
        // <= 1.2e-4 below 0.6, 1e-15 when sliding.
        let threshold = 3.5 * mu * (1.0 + e) * vn;
        let allowed = if (vt / threshold - 1.0).abs() < 0.2 {
            5e-3
        } else {
            2e-4
        };
        assert!(
            err < allowed,
            "v_t {vt}: deviation {err:.2e} of v_t > {allowed:.0e}"
        );
        worst = worst.max(err);
        // No spin about other axes, no sideways motion.
        assert!(s.omega.x.abs() < 1e-9 && s.omega.z.abs() < 1e-9 && s.vel.y.abs() < 1e-12);
        // Friction only takes energy: translational + rotational after <= before.
        let m = s.body.mass;
        let ke_after =
            0.5 * m * s.vel.norm_squared() + 0.5 * 0.4 * m * R * R * s.omega.norm_squared();
        let ke_normal_after = 0.5 * m * s.vel.z * s.vel.z;
        let ke_before = 0.5 * m * (vt * vt + vn * vn);
        assert!(ke_after <= ke_before - (0.5 * m * vn * vn - ke_normal_after) + 1e-12 * ke_before);
    }
    assert!(
        worst < 5e-3,
        "worst deviation from rigid-body theory {worst:.2e} of v_t"
    );
}

#[test]
fn sliding_regime_is_exact_coulomb() {
    let (vt, vn, mu) = (40.0, 10.0, 0.3);
    let s = plane(vt, vn, "[friction]\nshot_specimen = 0.3").shots[0].clone();
    let e = s.vel.z / vn;
    let (vt_th, wr_th) = theory_plane(vt, vn, e, mu);
    assert!(
        (s.vel.x - vt_th).abs() < 1e-6 * vt,
        "{} vs {vt_th}",
        s.vel.x
    );
    assert!(
        (s.omega.y * R - wr_th).abs() < 1e-6 * vt,
        "{} vs {wr_th}",
        s.omega.y * R
    );
}

#[test]
fn friction_off_gives_the_frictionless_results_exactly() {
    let reference = plane(25.0, 10.0, "");
    // Coefficients given but the effect switched off: nothing changes, no work done.
    let off = plane_with(
        25.0,
        10.0,
        "[friction]\nshot_specimen = 0.3",
        "friction = false",
    );
    assert_eq!(reference.impacts, off.impacts);
    assert_eq!(reference.shots, off.shots);
    assert_eq!(off.work.friction_calls, 0);
    assert_eq!(reference.work.friction_calls, 0);
    assert_eq!(off.shots[0].omega, Vec3::zeros());
    // Friction on with mu = 0: spin is integrated but nothing torques it; the states
    // equal the frictionless run bit for bit.
    let zero = plane_with(25.0, 10.0, "", "friction = true");
    assert!(zero.work.friction_calls > 0);
    assert_eq!(zero.shots[0].pos, reference.shots[0].pos);
    assert_eq!(zero.shots[0].vel, reference.shots[0].vel);
    assert_eq!(zero.shots[0].omega, Vec3::zeros());
}

/// Shot A 0.1 mm above shot B (both 0.8 mm), A moving at (vt, 0, -vn), B at rest; no
/// specimen, no jet, no gravity.
fn pair(vt: f64, vn: f64, mu: f64) -> RunOutput {
    pair_with(vt, vn, mu, "")
}

/// [`pair`] with `integrator` (TOML) before the `[effects]` table.
fn pair_with(vt: f64, vn: f64, mu: f64, integrator: &str) -> RunOutput {
    let x0 = x0_of(vt, vn);
    run(&format!(
        r#"duration_ms = 1.0
gravity_m_s2 = 0.0
[shots]
diameter_mm = 0.8
[shots.feed]
type = "list"
[[shots.feed.shots]]
position_mm = [{x0}, 0.0, 20.81]
velocity_m_s = [{vt}, 0.0, {}]
[[shots.feed.shots]]
position_mm = [0.0, 0.0, 20.0]
[friction]
shot_shot = {mu}
[restitution]
shot_shot = 0.9
{integrator}
[effects]
drag = false
lateral_force = false
nozzle_wall_contact = false
specimen_contact = false
"#,
        -vn
    ))
}

/// Start of A along x, mm: offset so that the line of centres is vertical at the middle
/// of the contact (the normal then turns symmetrically about z).
fn x0_of(vt: f64, vn: f64) -> f64 {
    let m = 7850.0 * std::f64::consts::PI / 6.0 * (2.0 * R).powi(3);
    let law = peenflow::contact::HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.9);
    let tc = peenflow::contact::hertz::contact_time(m / 2.0, law.stiffness(R / 2.0), vn);
    -vt * (0.01e-3 / vn + 0.5 * tc) * 1e3
}

/// Total angular momentum about the origin: orbital plus spin.
fn angular_momentum(out: &RunOutput) -> Vec3 {
    out.shots
        .iter()
        .map(|s| {
            let m = s.body.mass;
            s.pos.cross(&(s.vel * m)) + s.omega * (0.4 * m * s.body.radius * s.body.radius)
        })
        .sum()
}

#[test]
fn two_spheres_match_rigid_body_theory_and_conserve_momenta() {
    // Rigid-body theory holds the contact normal fixed; two spheres sliding past each
    // other turn their line of centres by about v_t t_c / (2R) during the contact. At
    // v_n = 0.5 m/s that turn is ~1e-3 rad, small against mu: compare there.
    let (vn, mu) = (0.5, 0.2);
    let threshold = 3.5 * mu * 1.9 / 2.0 * vn * 2.0; // 7 mu J_n / m, J_n = m (1+e) v_n / 2
    for vt in [0.2, 0.5, 1.5, 3.0] {
        let out = pair(vt, vn, mu);
        let (a, b) = (&out.shots[0], &out.shots[1]);
        assert_eq!((a.collisions, b.collisions), (1, 1));
        let m = a.body.mass;
        let jn = m * (1.9 / 2.0) * vn;
        let sliding = vt > threshold;
        let jt = if sliding { mu * jn } else { m * vt / 7.0 };
        let i = 0.4 * m * R * R;
        let (va, vb, w) = (vt - jt / m, jt / m, jt * R / i);
        let dev = [
            a.vel.x - va,
            b.vel.x - vb,
            (a.omega.y - w) * R,
            (b.omega.y - w) * R,
        ]
        .iter()
        .fold(0.0f64, |x, d| x.max(d.abs()))
            / (jt / m);
        println!(
            "v_t {vt}: {} regime, A v_t' {:.6} (theory {va:.6}), B {:.6} ({vb:.6}), omega R {:.6} / {:.6} ({:.6}), deviation {dev:.1e} of the change",
            if sliding { "sliding" } else { "rolling" },
            a.vel.x,
            b.vel.x,
            a.omega.y * R,
            b.omega.y * R,
            w * R
        );
        // Measured: 1.2e-3 to 3.2e-3 of the change (the normal's turn and the
        // regularisation's residual slip).
        assert!(
            dev < 1e-2,
            "v_t {vt}: deviation {dev:.2e} of the tangential change"
        );
        // Linear and angular momentum are conserved (the tangential force acts at one
        // point for both shots); energy only decreases.
        let p = a.vel * m + b.vel * m;
        assert!((p - Vec3::new(vt * m, 0.0, -vn * m)).norm() < 1e-12 * m * vt.max(vn));
        let l0 =
            Vec3::new(x0_of(vt, vn) * 1e-3, 0.0, 20.81e-3).cross(&(Vec3::new(vt, 0.0, -vn) * m));
        let l1 = angular_momentum(&out);
        assert!(
            (l1 - l0).norm() < 1e-9 * l0.norm().max(m * R * vt),
            "L {l0} -> {l1}"
        );
        let ke = |s: &peenflow::state::ShotState| {
            0.5 * m * s.vel.norm_squared() + 0.5 * i * s.omega.norm_squared()
        };
        assert!(ke(a) + ke(b) < 0.5 * m * (vt * vt + vn * vn));
    }
}

#[test]
fn the_fixed_step_method_spins_shots_as_rigid_body_theory_says() {
    // Velocity Verlet at 20 ns (LIGGGHTS' step for these shots): spin is kicked with the
    // torque as velocities are with the force, so both regimes come out to the step's
    // accuracy. A shot on the plane (v_n 10 m/s, contact about 75 steps long):
    let verlet = "[integrator]\nmethod = \"verlet\"\nfixed_step_ns = 20\n";
    let (vn, mu) = (10.0, 0.3);
    for vt in [5.0, 10.0, 40.0] {
        let out = plane(
            vt,
            vn,
            &format!("[friction]\nshot_specimen = 0.3\n{verlet}"),
        );
        let s = &out.shots[0];
        assert_eq!(s.hits, 1);
        assert_eq!(out.work.shot_steps, 5000, "0.1 ms of whole 20 ns steps");
        let e = s.vel.z / vn;
        // The step's error on the rebound (measured 0.70059).
        assert!((e - 0.7).abs() < 2e-3, "normal restitution {e}");
        let (vt_th, wr_th) = theory_plane(vt, vn, e, mu);
        let err = ((s.vel.x - vt_th).abs()).max((s.omega.y * R - wr_th).abs()) / vt;
        println!(
            "plane, v_t {vt}: v_t' {:.6} ({vt_th:.6}), omega R {:.6} ({wr_th:.6}), error {err:.1e}",
            s.vel.x,
            s.omega.y * R
        );
        // Measured: 9e-6 (v_t 5), 6e-5 (10, the regularisation's residual slip near the
        // threshold, as for the adaptive method), 4e-16 (sliding: exact Coulomb).
        let allowed = if vt > 3.5 * mu * (1.0 + e) * vn {
            1e-12
        } else {
            3e-4
        };
        assert!(err < allowed, "v_t {vt}: deviation {err:.2e} of v_t");
    }
    // Two shots (v_n 0.5 m/s, mu 0.2), on the window scheduler: the rigid-body tangential
    // exchange, and exact linear momentum.
    let (vn, mu) = (0.5, 0.2);
    for vt in [0.5, 3.0] {
        let out = pair_with(vt, vn, mu, verlet);
        assert_eq!(out.scheduler, "windows");
        let (a, b) = (&out.shots[0], &out.shots[1]);
        assert_eq!((a.collisions, b.collisions), (1, 1));
        let m = a.body.mass;
        let e = (a.vel.z - b.vel.z) / vn;
        let jn = m * (1.0 + e) / 2.0 * vn;
        let sliding = vt > 7.0 * mu * jn / m;
        let jt = if sliding { mu * jn } else { m * vt / 7.0 };
        let w = jt * R / (0.4 * m * R * R);
        let dev = [
            a.vel.x - (vt - jt / m),
            b.vel.x - jt / m,
            (a.omega.y - w) * R,
            (b.omega.y - w) * R,
        ]
        .iter()
        .fold(0.0f64, |x, d| x.max(d.abs()))
            / (jt / m);
        println!("pair, v_t {vt}: restitution {e:.5}, deviation {dev:.1e} of the change");
        // As for the adaptive method (the normal's turn during the contact; measured
        // 1.2e-3 to 3.2e-3 there).
        assert!(dev < 1e-2, "v_t {vt}: deviation {dev:.2e}");
        let p = a.vel * m + b.vel * m;
        assert!((p - Vec3::new(vt * m, 0.0, -vn * m)).norm() < 1e-12 * m * vt.max(vn));
    }
}
