//! Shared helpers for the integration tests.
#![allow(dead_code)]

use peenflow::Vec3;
use peenflow::contact::{ContactSet, HertzLaw, PairContact, SpecimenContact};
use peenflow::forces::{ForceSet, ShotBody};
use peenflow::integrate::Physics;
use peenflow::state::{Domain, ShotId, ShotState};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs the peenflow binary with `args`.
pub fn peenflow(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_peenflow"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("cannot start peenflow")
}

/// Steel of the paper's Table 2.
pub const E_STEEL: f64 = 210e9;
/// Poisson's ratio of the paper's Table 2.
pub const NU_STEEL: f64 = 0.3;
/// Shot density, kg/m^3.
pub const RHO_SHOT: f64 = 7850.0;

/// A steel shot of diameter `d` at `pos` moving at `vel`.
pub fn shot(id: u32, d: f64, pos: Vec3, vel: Vec3) -> ShotState {
    let body = ShotBody {
        radius: 0.5 * d,
        mass: RHO_SHOT * std::f64::consts::PI / 6.0 * d * d * d,
    };
    ShotState::new(ShotId(id), pos, vel, body, 0.0)
}

/// Contact-only physics (no air, no gravity): steel on steel with the given restitutions.
pub fn contact_physics(specimen_e: Option<f64>, pair_e: Option<f64>) -> Physics {
    let law = |e| HertzLaw::new(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL, e);
    Physics {
        forces: ForceSet {
            drag: None,
            lateral: None,
            gravity: None,
            field: None,
            turbulence: None,
        },
        contacts: ContactSet {
            specimen: specimen_e.map(|e| SpecimenContact { law: law(e) }),
            wall: None,
            pair: pair_e.map(|e| PairContact { law: law(e) }),
            friction: None,
        },
        tolerance: 1e-6,
        contact_steps: 50.0,
        domain: Domain {
            radius: 10.0,
            top: 10.0,
        },
        max_step: 1e-3,
        method: peenflow::integrate::island::Method::Adaptive,
        sliding: true,
    }
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A regular stream through the nozzle without shot-shot contact (the independent
/// scheduler): `rate` shots/s entering at 5 m/s for `feed_ms`, a run of `run_ms`, and
/// `extra` TOML appended (e.g. a `[friction]` table).
pub fn stream_without_contact(
    rate: f64,
    feed_ms: f64,
    run_ms: f64,
    extra: &str,
) -> peenflow::scene::Scene {
    let text = format!(
        "duration_ms = {run_ms}\n[effects]\nshot_shot_contact = false\n[shots.feed]\ntype = \"stream\"\nrate_per_s = {rate}\nduration_ms = {feed_ms}\nentry_speed_m_s = 5.0\narrivals = \"regular\"\n{extra}"
    );
    peenflow::scene::Scene::from_toml(&text, "stream_without_contact.toml").unwrap()
}
