//! The lone shot of examples/single_shot.toml against an independent integration of the
//! same ODE: classical fixed-step RK4 (written here, with the paper's formulas computed
//! here from Eqs 2, 3, 7, 8, 11) that lands its steps exactly on the region borders and on
//! the contact. Tolerance: the 0.1 % on the impact speed; the reference itself
//! must agree with its half-step rerun to 1e-7.
//! Also: free flight is not paid at contact resolution (at most 2,000 steps from the
//! inlet to first contact, at least 15 steps in the specimen contact), and the README's
//! worked example quotes this run's counts.

use crate::common;
use common::*;
use peenflow::scene::Scene;
use peenflow::sim::Simulation;

struct Air {
    ui: f64,
    rho_star: f64,
    rho_ab: f64,
}

const D_BORE: f64 = 6e-3;
const L: f64 = 100e-3;
const LN: f64 = 40e-3;
const DIA: f64 = 0.8e-3;
const CD: f64 = 0.47;

/// Region on the axis: 0 bore, 1 potential core, 2 developed jet, 3 the developed jet
/// within the stagnation layer `layer` (m) above the plate, if there is one.
fn region(z: f64, layer: Option<f64>) -> u8 {
    let s = L - z;
    if s < 0.0 {
        0
    } else if s <= 5.0 * D_BORE {
        1
    } else if layer.is_some_and(|delta| z < delta) {
        3
    } else {
        2
    }
}

fn accel(air: &Air, reg: u8, z: f64, w: f64, layer: Option<f64>) -> f64 {
    let s = L - z;
    let (mut u, rho) = match reg {
        0 | 1 => (air.ui, air.rho_star),
        _ => (
            6.0 * D_BORE * air.ui / s,
            air.rho_star * (s - 5.0 * D_BORE) / s + air.rho_ab * 5.0 * D_BORE / s,
        ),
    };
    if let (3, Some(delta)) = (reg, layer) {
        // The layer's profile as docs/model.md states it: 2x - x^2 of the free speed.
        let x = z / delta;
        u *= 2.0 * x - x * x;
    }
    let m = RHO_SHOT * std::f64::consts::PI / 6.0 * DIA.powi(3);
    let area = std::f64::consts::PI * DIA * DIA / 4.0;
    0.5 * rho * CD * area * (u - w) * (u - w).abs() / m
}

/// One RK4 step of (z, w = downward speed) with the region frozen.
fn rk4(air: &Air, (reg, layer): (u8, Option<f64>), z: f64, w: f64, h: f64) -> (f64, f64) {
    let f = |z: f64, w: f64| (-w, accel(air, reg, z, w, layer));
    let k1 = f(z, w);
    let k2 = f(z + 0.5 * h * k1.0, w + 0.5 * h * k1.1);
    let k3 = f(z + 0.5 * h * k2.0, w + 0.5 * h * k2.1);
    let k4 = f(z + h * k3.0, w + h * k3.1);
    (
        z + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
        w + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
    )
}

/// Speed at first contact (z = R) by fixed-step RK4 with located borders.
fn reference_speed(air: &Air, h: f64) -> (f64, f64) {
    layered_reference_speed(air, h, None)
}

/// The same through a stagnation layer `layer` (m) thick above the plate.
fn layered_reference_speed(air: &Air, h: f64, layer: Option<f64>) -> (f64, f64) {
    let r = 0.5 * DIA;
    let (mut z, mut w, mut t) = (L + LN, 0.0, 0.0);
    let mut reg = region(z, layer);
    loop {
        let (z1, w1) = rk4(air, (reg, layer), z, w, h);
        let crossed_region = region(z1, layer) != reg;
        let hit = z1 <= r;
        if !crossed_region && !hit {
            z = z1;
            w = w1;
            t += h;
            continue;
        }
        // Bisect the step length to land on the border (z decreases monotonically).
        let border = if hit && !crossed_region {
            r
        } else {
            match (reg, layer) {
                (0, _) => L,
                (1, _) => L - 5.0 * D_BORE,
                (_, Some(delta)) => delta,
                _ => unreachable!("no border below the developed jet without a layer"),
            }
        };
        let border = border.max(r);
        let (mut lo, mut hi) = (0.0, h);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if rk4(air, (reg, layer), z, w, mid).0 > border {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (z2, w2) = rk4(air, (reg, layer), z, w, hi);
        z = z2;
        w = w2;
        t += hi;
        if border == r {
            return (w, t);
        }
        reg += 1;
    }
}

fn paper_air() -> Air {
    let (p, pb, temp, kappa, gas, rho_ab): (f64, f64, f64, f64, f64, f64) =
        (0.6e6, 0.1e6, 293.0, 1.4, 287.05, 1.205);
    let rho0 = rho_ab * (p + pb) / pb; // Eq 2
    let rho_star = rho0 * (2.0 / (kappa + 1.0)).powf(1.0 / (kappa - 1.0)); // Eq 3 (0.634)
    let ui = (kappa * gas * temp).sqrt() * (2.0 / (kappa + 1.0)).sqrt(); // choked Eq 8
    Air {
        ui,
        rho_star,
        rho_ab,
    }
}

#[test]
fn lone_shot_impact_speed_matches_independent_rk4_within_0_1_percent() {
    let air = paper_air();
    let (w_ref, t_ref) = reference_speed(&air, 1e-7);
    let (w_half, _) = reference_speed(&air, 5e-8);
    assert!(
        rel(w_half, w_ref) < 1e-7,
        "reference not converged: {w_ref} vs {w_half}"
    );

    let scene = Scene::load(&root().join("examples/single_shot.toml")).unwrap();
    let effects = scene.effects();
    let out = Simulation::new(&scene, &effects).unwrap().run(&|_| {});
    let first = &out.impacts[0];
    let err = rel(first.normal_speed_m_s, w_ref);
    println!(
        "impact speed {:.9} m/s, reference {:.9} m/s, relative error {:.2e}; time {:.9e} vs {:.9e} s",
        first.normal_speed_m_s, w_ref, err, first.time_s, t_ref
    );
    assert!(err < 1e-3, "impact speed error {err:.3e} >= 0.1 %");
    // Measured 8.5e-9 at the default tolerance 1e-6 (the specimen onset is located and
    // the contact force starts at the end of the locating step): allow 1e-6.
    assert!(err < 1e-6, "impact speed error {err:.3e} above 1e-6");
    assert!(rel(first.time_s, t_ref) < 1e-6);
    // model-notes: with rho* an on-axis 0.8 mm shot at 0.6 MPa lands at about 60 m/s.
    assert!((55.0..65.0).contains(&first.normal_speed_m_s));
}

#[test]
fn free_flight_is_cheap_and_the_contact_is_resolved() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("examples/single_shot.toml");
    let out = dir.path().join("out");
    let o = peenflow(
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let flight = s["steps"]["flight_to_first_contact"]["max"]
        .as_u64()
        .unwrap();
    let contact = s["steps"]["first_contact"]["min"].as_u64().unwrap();
    println!("steps inlet -> first contact: {flight}; steps in the contact: {contact}");
    assert!(flight <= 2000, "{flight} steps in free flight");
    // The error controller sets the steps of a contact (onset and end of force located):
    // about 25 at the default tolerance; a handful would mean the contact was skipped.
    assert!(contact >= 15, "only {contact} steps resolve the contact");
    // The README's worked example is this run: its console line and its sentence on the
    // steps must quote what the run prints and counts.
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let stdout = peenflow(
        &["run", scene.to_str().unwrap(), "--out", "printed"],
        dir.path(),
    )
    .stdout;
    let printed = String::from_utf8_lossy(&stdout);
    let work = printed.lines().find(|l| l.starts_with("work: ")).unwrap();
    let upto = work.find("; wall time").unwrap();
    assert!(
        readme.contains(&work[..upto]),
        "README's worked example does not quote `{}`",
        &work[..upto]
    );
    let sentence = format!(
        "It took {flight} steps from the inlet to the specimen\nand {contact} steps through"
    );
    assert!(
        readme.contains(&sentence),
        "README's worked example does not say `{sentence}`"
    );
}

#[test]
fn core_density_choice_gives_model_notes_speeds() {
    // model-notes: with rho* an on-axis 0.8 mm shot at 0.6 MPa lands at about 60 m/s,
    // with rho_0 at about 71 m/s (paper: 65-70 m/s).
    let text = std::fs::read_to_string(root().join("examples/single_shot.toml")).unwrap();
    let text = text.replace("core_density = \"rho_star\"", "core_density = \"rho_0\"");
    let scene = Scene::from_toml(&text, "rho_0").unwrap();
    let out = Simulation::new(&scene, &scene.effects())
        .unwrap()
        .run(&|_| {});
    let v = out.impacts[0].normal_speed_m_s;
    println!("rho_0 core: {v} m/s");
    assert!((70.0..72.5).contains(&v), "{v}");
}

/// The stagnation layer (beyond the paper, `jet.stagnation_layer_mm`) against the same
/// independent RK4 with the layer's profile written here (`2x - x^2` of the free jet's
/// axial speed below the layer's top, `x = z / delta`; its top is a located border, in
/// the reference and, since session 58, in peenflow). Layers of one bore diameter to a
/// fifth of the stand-off (docs/model.md). Tolerance 1e-5 of the impact speed (measured:
/// 1.5e-6, 9.0e-7 and 5.4e-7; peenflow's default tolerance is per step); and the layer brakes the shot by 0.05-0.5 % (measured 0.07 %
/// at 6 mm to 0.31 % at 20 mm), more the thicker it is.
#[test]
fn the_stagnation_layer_matches_independent_rk4() {
    let air = paper_air();
    let text = std::fs::read_to_string(root().join("examples/single_shot.toml")).unwrap();
    let (free, _) = reference_speed(&air, 1e-7);
    let mut last = free;
    for delta_mm in [6.0, 14.0, 20.0] {
        let delta = delta_mm * 1e-3;
        let (w_ref, t_ref) = layered_reference_speed(&air, 1e-7, Some(delta));
        let (w_half, _) = layered_reference_speed(&air, 5e-8, Some(delta));
        assert!(rel(w_half, w_ref) < 1e-7, "reference: {w_ref} vs {w_half}");
        let layered = text.replace(
            "[jet]\n",
            &format!("[jet]\nstagnation_layer_mm = {delta_mm}\n"),
        );
        assert_ne!(layered, text);
        let scene = Scene::from_toml(&layered, "layer.toml").unwrap();
        let effects = scene.effects();
        let said = format!("a stagnation layer {delta_mm} mm above the plate");
        assert!(effects.decisions[0].reason.ends_with(&said), "{effects:?}");
        let out = Simulation::new(&scene, &effects).unwrap().run(&|_| {});
        let first = &out.impacts[0];
        let err = rel(first.normal_speed_m_s, w_ref);
        println!(
            "layer {delta_mm} mm: impact speed {:.9} m/s, reference {w_ref:.9} m/s \
             ({:+.3} % on the free jet), relative error {err:.2e}",
            first.normal_speed_m_s,
            100.0 * (w_ref / free - 1.0)
        );
        assert!(err < 1e-5, "layer {delta_mm} mm: error {err:.3e}");
        assert!(rel(first.time_s, t_ref) < 1e-5);
        let braked = 1.0 - w_ref / free;
        assert!((5e-4..5e-3).contains(&braked), "braked by {braked}");
        assert!(w_ref < last);
        last = w_ref;
    }
}

/// The surface under a shot in the plane `y = 0`: the plate `z = 0`, or a bar of radius
/// `R` (m) whose axis runs along `y` through `(0, 0, -R)`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Under {
    Plate,
    Bar(f64),
}

impl Under {
    /// Height of `(x, z)` above the surface.
    fn height(self, x: f64, z: f64) -> f64 {
        match self {
            Under::Plate => z,
            Under::Bar(r) => x.hypot(z + r) - r,
        }
    }

    /// The outward unit normal `(n_x, n_z)` of the surface under `(x, z)`.
    fn normal(self, x: f64, z: f64) -> (f64, f64) {
        match self {
            Under::Plate => (0.0, 1.0),
            Under::Bar(r) => {
                let d = x.hypot(z + r);
                (x / d, (z + r) / d)
            }
        }
    }
}

/// The air of the developed jet at `(x, z)` in the plane `y = 0` (the jet on `x = 0`),
/// with the stagnation layer `delta` over the surface `under` and, if `wall` (over the
/// plate), its wall jet, written here from docs/model.md: within the layer the air's
/// component along the surface's normal is the free jet's times `f = 2x - x^2` (`x` the
/// height over `delta`; over the plate the axial speed of Eq 11), and the wall jet a
/// radial speed `(f'(x) / delta) (1/r) int_0^r u(r') r' dr'`, its integral by composite
/// Simpson (not the closed form peenflow uses). Returns the air's `(u_x, u_z)` and density.
fn developed_air(
    air: &Air,
    x: f64,
    z: f64,
    layer: Option<(f64, bool)>,
    under: Under,
) -> (f64, f64, f64) {
    let s = L - z;
    let u = |r: f64| 6.0 * D_BORE * air.ui / s * (-94.0 * (r / s).powi(2)).exp();
    assert!(
        s > 5.0 * D_BORE && x.abs() <= s / 5.0,
        "the test stays in the developed jet"
    );
    let rho = air.rho_star * (s - 5.0 * D_BORE) / s + air.rho_ab * 5.0 * D_BORE / s;
    let (mut ux, mut uz) = (0.0, -u(x.abs()));
    let height = under.height(x, z);
    if let (Some((delta, _)), Under::Bar(_)) = (layer, under)
        && height < delta
    {
        let xi = height / delta;
        let (nx, nz) = under.normal(x, z);
        let slowed = (ux * nx + uz * nz) * (1.0 - (2.0 * xi - xi * xi));
        (ux, uz) = (ux - nx * slowed, uz - nz * slowed);
    } else if let (Some((delta, wall)), Under::Plate) = (layer, under)
        && z < delta
    {
        let xi = z / delta;
        uz *= 2.0 * xi - xi * xi;
        if wall && x != 0.0 {
            let (r, n) = (x.abs(), 400);
            let h = r / n as f64;
            let integral = (0..=n)
                .map(|i| {
                    let ri = i as f64 * h;
                    let w = if i == 0 || i == n {
                        1.0
                    } else {
                        [2.0, 4.0][i % 2]
                    };
                    w * ri * u(ri)
                })
                .sum::<f64>()
                * h
                / 3.0;
            ux = 2.0 * (1.0 - xi) / delta * integral / r * x.signum();
        }
    }
    (ux, uz, rho)
}

/// A shot of the single-shot scene's kind from `(x0, z0)` at `(0, vz0)` in the developed
/// jet to its first touch (its centre its radius above the surface `under`), by
/// fixed-step RK4 with the layer's top and the touch located: the centre's `(x, z)`, and
/// `(vx, vz, t)` there.
fn off_axis_reference(
    air: &Air,
    (x0, z0, vz0): (f64, f64, f64),
    (layer, under): (Option<(f64, bool)>, Under),
    h: f64,
) -> ([f64; 2], f64, f64, f64) {
    let rad = 0.5 * DIA;
    let m = RHO_SHOT * std::f64::consts::PI / 6.0 * DIA.powi(3);
    let area = std::f64::consts::PI * DIA * DIA / 4.0;
    // The layer's side of the top is frozen for a step, as peenflow freezes nothing there
    // but its steps are short: both sides' formulas agree at the top.
    let f = |y: [f64; 4], inside: bool| {
        let lay = layer.map(|(d, w)| if inside { (d, w) } else { (-1.0, w) });
        let (ux, uz, rho) = developed_air(air, y[0], y[1], lay, under);
        let (rx, rz) = (ux - y[2], uz - y[3]);
        let k = 0.5 * rho * CD * area * rx.hypot(rz) / m;
        [y[2], y[3], k * rx, k * rz]
    };
    let step = |y: [f64; 4], inside: bool, h: f64| {
        let add = |a: [f64; 4], b: [f64; 4], c: f64| std::array::from_fn(|i| a[i] + c * b[i]);
        let k1 = f(y, inside);
        let k2 = f(add(y, k1, 0.5 * h), inside);
        let k3 = f(add(y, k2, 0.5 * h), inside);
        let k4 = f(add(y, k3, h), inside);
        std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    let top = layer.map_or(f64::NEG_INFINITY, |(d, _)| d);
    let height = |y: &[f64; 4]| under.height(y[0], y[1]);
    let (mut y, mut t) = ([x0, z0, 0.0, vz0], 0.0);
    let mut inside = height(&y) < top;
    loop {
        let border = if inside { rad } else { top.max(rad) };
        let y1 = step(y, inside, h);
        if height(&y1) > border {
            y = y1;
            t += h;
            continue;
        }
        let (mut lo, mut hi) = (0.0, h);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if height(&step(y, inside, mid)) > border {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        y = step(y, inside, hi);
        t += hi;
        if border == rad {
            return ([y[0], y[1]], y[2], y[3], t);
        }
        inside = true;
    }
}

/// examples/single_shot.toml with its shot replaced by shots at `(x, 0, z)` (m) moving
/// at `(0, 0, v)` (m/s).
fn dropped_shots(starts: &[(f64, f64, f64)]) -> String {
    let text = std::fs::read_to_string(root().join("examples/single_shot.toml")).unwrap();
    let feed: String = starts
        .iter()
        .map(|(x, z, v)| {
            format!(
                "[[shots.feed.shots]]\nposition_mm = [{}, 0.0, {}]\nvelocity_m_s = [0.0, 0.0, {v}]\n",
                x * 1e3,
                z * 1e3
            )
        })
        .collect();
    let at = text.find("[[shots.feed.shots]]").unwrap();
    let end = text[at..].find("\n\n").unwrap() + at + 1;
    format!("{}{feed}{}", &text[..at], &text[end..])
}

/// Runs the scene `toml` (at `tolerance`, if given) after checking that the drag's line
/// in the run's effects ends with `said` exactly when `saying`.
fn run_saying(
    mut toml: String,
    tolerance: Option<f64>,
    (said, saying): (&str, bool),
) -> peenflow::sim::RunOutput {
    if let Some(tol) = tolerance {
        toml += &format!("\n[integrator]\ntolerance = {tol:e}\n");
    }
    let scene = Scene::from_toml(&toml, "layer.toml").unwrap();
    let effects = scene.effects();
    assert_eq!(
        effects.decisions[0].reason.ends_with(said),
        saying,
        "{effects:?}"
    );
    Simulation::new(&scene, &effects).unwrap().run(&|_| {})
}

/// The wall jet (beyond the paper, `jet.wall_jet`) against an independent RK4 of the
/// same equations, written here (`developed_air`, its radial flow integrated by Simpson):
/// three shots dropped off the axis in the developed jet (3 and 10 mm at 60 m/s, 10 mm at
/// 15 m/s) through a 14 mm layer. The wall jet pushes them outwards (1.5, 4.0 and 49 um
/// across the plate; 0.020, 0.068 and 0.19 m/s along it at the touch). At the default
/// tolerance the impact's position is within 1e-5 of the shot's diameter of the
/// reference's, its velocity within 1e-5 of `|v| + 1 m/s` and its time within 1e-5 (the
/// integrator's own error scales; measured at most 4.8e-7, 1.1e-6 and 1.1e-7); at
/// tolerance 1e-10 the push and the tangential velocity are within 1e-3 of the
/// reference's (measured at most 2.2e-9). Without the wall jet the shots land where they were
/// dropped.
#[test]
fn the_wall_jet_matches_independent_rk4_off_the_axis() {
    let air = paper_air();
    let delta = 0.014;
    let starts = [
        (3e-3, 0.04, -60.0),
        (10e-3, 0.04, -60.0),
        (10e-3, 0.03, -15.0),
    ];
    let base = dropped_shots(&starts);
    for (wall, tolerance) in [(true, None), (true, Some(1e-10)), (false, None)] {
        let keys = format!("[jet]\nstagnation_layer_mm = 14.0\nwall_jet = {wall}\n");
        let said = "a stagnation layer 14 mm above the plate and flows out along it (wall jet)";
        let out = run_saying(base.replace("[jet]\n", &keys), tolerance, (said, wall));
        for (k, &(x0, z0, v0)) in starts.iter().enumerate() {
            let first = out.impacts.iter().find(|i| i.shot as usize == k).unwrap();
            let layer = (Some((delta, wall)), Under::Plate);
            let ([x, _], vx, vz, t) = off_axis_reference(&air, (x0, z0, v0), layer, 1e-7);
            let ([xh, _], vxh, vzh, _) = off_axis_reference(&air, (x0, z0, v0), layer, 5e-8);
            let (push, kick) = (x - x0, vx);
            let scale = first.speed_m_s + 1.0;
            let errors = [
                (first.x_m - x).abs() / DIA,
                (first.vx_m_s - vx).abs() / scale,
                (first.vz_m_s - vz).abs() / scale,
                rel(first.time_s, t),
            ];
            println!(
                "wall jet {wall}, tolerance {tolerance:?}, shot {k}: moved {:.5e} m (reference \
                 {push:.5e}), tangential {:.5e} m/s (reference {kick:.5e}), normal {:.7} m/s \
                 (reference {:.7}); errors {:.2e} {:.2e} {:.2e} {:.2e}",
                first.x_m - x0,
                first.vx_m_s,
                -first.vz_m_s,
                -vz,
                errors[0],
                errors[1],
                errors[2],
                errors[3],
            );
            let converged = |a: f64, b: f64, of: f64| (a - b).abs() <= 1e-4 * of.abs();
            assert!(converged(xh, x, push) && converged(vxh, vx, kick));
            assert!(rel(vzh, vz) < 1e-9);
            assert!(errors.iter().all(|e| *e < 1e-5), "errors {errors:?}");
            if !wall {
                assert_eq!((push, kick), (0.0, 0.0));
                assert_eq!((first.x_m, first.vx_m_s), (x0, 0.0));
            } else if tolerance.is_some() {
                assert!(
                    push > 1e-6 && kick > 1e-2,
                    "the wall jet pushes out: {push}, {kick}"
                );
                assert!(
                    (first.x_m - x).abs() < 1e-3 * push,
                    "pushed to {}",
                    first.x_m
                );
                assert!(
                    (first.vx_m_s - vx).abs() < 1e-3 * kick,
                    "along {}",
                    first.vx_m_s
                );
            }
        }
    }
}

/// The stagnation layer over a bar (beyond the paper: `[specimen] shape = "cylinder"`
/// with `jet.stagnation_layer_mm`) against the same independent RK4 (`developed_air`
/// with the bar's normal written here): three shots dropped beside the crest line of a
/// bar of 8 mm radius (2 and 5 mm off at 60 m/s, 4 mm at 15 m/s) through a 6 mm layer,
/// and without it. Over the bar's sides the layer slows only the air's part along the
/// bar's normal, so the air turns outwards round the bar and carries the shots out. At
/// the default tolerance the contact point is within 1e-5 of the shot's diameter of the
/// reference's, the velocity within 1e-5 of `|v| + 1 m/s` and the time within 1e-5; at
/// tolerance 1e-10 the contact point's move and the tangential speed within 1e-3 of the
/// reference's.
#[test]
fn the_layer_over_a_bar_matches_independent_rk4() {
    let air = paper_air();
    let (radius, delta) = (8e-3, 6e-3);
    let starts = [
        (2e-3, 0.04, -60.0),
        (5e-3, 0.04, -60.0),
        (4e-3, 0.03, -15.0),
    ];
    let base = dropped_shots(&starts).replace(
        "[specimen]\n",
        "[specimen]\nshape = \"cylinder\"\nradius_mm = 8.0\naxis_deg = 90.0\n",
    );
    for (layer, tolerance) in [
        (Some(delta), None),
        (Some(delta), Some(1e-10)),
        (None, None),
    ] {
        let toml = match layer {
            Some(_) => base.replace("[jet]\n", "[jet]\nstagnation_layer_mm = 6.0\n"),
            None => base.clone(),
        };
        assert_ne!(toml, dropped_shots(&starts));
        let said = "a stagnation layer 6 mm above the bar";
        let out = run_saying(toml, tolerance, (said, layer.is_some()));
        for (k, &(x0, z0, v0)) in starts.iter().enumerate() {
            let first = out.impacts.iter().find(|i| i.shot as usize == k).unwrap();
            let under = Under::Bar(radius);
            let lay = (layer.map(|d| (d, false)), under);
            let ([x, z], vx, vz, t) = off_axis_reference(&air, (x0, z0, v0), lay, 1e-7);
            let ([xh, _], vxh, vzh, _) = off_axis_reference(&air, (x0, z0, v0), lay, 5e-8);
            // The contact point: the centre's foot on the bar.
            let (nx, nz) = under.normal(x, z);
            let foot = (radius * nx, radius * nz - radius);
            let scale = first.speed_m_s + 1.0;
            let errors = [
                (first.x_m - foot.0).abs() / DIA,
                (first.z_m - foot.1).abs() / DIA,
                (first.vx_m_s - vx).abs() / scale,
                (first.vz_m_s - vz).abs() / scale,
                rel(first.time_s, t),
            ];
            println!(
                "layer {layer:?}, tolerance {tolerance:?}, shot {k}: centre moved {:.5e} m out, contact at x {:.6e} m \
                 (reference {:.6e}), vx {:.5e} m/s (reference {vx:.5e}), vz {:.7} m/s \
                 (reference {vz:.7}); errors {errors:?}",
                x - x0,
                first.x_m,
                foot.0,
                first.vx_m_s,
                first.vz_m_s,
            );
            assert!((xh - x).abs() < 1e-4 * (x - x0).abs().max(1e-9));
            assert!((vxh - vx).abs() < 1e-4 * vx.abs().max(1e-6));
            assert!(rel(vzh, vz) < 1e-9);
            assert!(errors.iter().all(|e| *e < 1e-5), "errors {errors:?}");
            if layer.is_some() {
                assert!(
                    x - x0 > 1e-8 && vx > 1e-3,
                    "the layer turns the air round the bar and the shot out: {} m, {vx} m/s",
                    x - x0
                );
                if tolerance.is_some() {
                    // The turn itself, resolved: the contact point's move from where a
                    // shot falling straight touches, and the tangential speed it gives.
                    let straight = radius * x0 / (radius + 0.5 * DIA);
                    let (moved, got) = (foot.0 - straight, first.x_m - straight);
                    assert!((got - moved).abs() < 1e-3 * moved, "{got} against {moved}");
                    assert!((first.vx_m_s - vx).abs() < 1e-3 * vx, "{}", first.vx_m_s);
                }
            } else {
                assert_eq!((x, vx), (x0, 0.0));
                assert!(first.vx_m_s.abs() < 1e-12);
            }
        }
    }
}
