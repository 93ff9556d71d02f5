//! Regression guards on the validation outcomes the model reproduces (docs/validation.md),
//! so that a physics change that moves them fails CI. Over 5 seeds of the Table 2 scene:
//! about a fifth of the shots never reach the specimen (paper: 19 %; measured 17 %);
//! shot-shot collisions are what spreads the impacts (90th-percentile radius with them at
//! least 1.5x that without); more shots spread wider (30 against 1). The lone shot lands at
//! 60.1 m/s with the rho* core and 71.2 m/s with rho_0 (model-notes: ~60 and ~71).
//! The paper's pressure and shot-size trends (measurements, its Figs. 3-5) are not
//! reproduced by this model (docs/validation.md): what the model does instead is guarded
//! (smaller shots spread narrower; pressure moves the spread by less than the seed noise),
//! so a physics change that moves either fails here.

use crate::common;
use common::*;
use peenflow::scene::{Scene, Switch};
use peenflow::validate::{pooled, power_law_exponent};

#[test]
fn never_reaching_share_is_near_the_papers_19_percent() {
    let p = pooled(&Scene::default_scene(), 5);
    println!("never reaching: {:.1} %", 100.0 * p.never());
    assert!((0.10..=0.28).contains(&p.never()));
    assert!(p.within_20mm() > 0.9);
}

#[test]
fn collisions_spread_the_impacts_and_more_shots_spread_wider() {
    let base = Scene::default_scene();
    let with = pooled(&base, 5);
    let mut off = base.clone();
    off.effects.switches[4] = Switch::Off;
    let without = pooled(&off, 5);
    println!(
        "p90 radius: {:.2} mm with collisions, {:.2} mm without",
        with.radius_p(90.0),
        without.radius_p(90.0)
    );
    assert!(with.radius_p(90.0) > 1.5 * without.radius_p(90.0));
    let mut one = base.clone();
    one.feed = peenflow::scene::Feed::Batch {
        count: 1,
        radial_min: 1.5e-3,
        radial_max: 2.6e-3,
        axial_spread: 10e-3,
    };
    let single = pooled(&one, 5);
    assert!(with.radius_p(90.0) > single.radius_p(90.0));
}

#[test]
fn power_law_fit_recovers_a_known_exponent() {
    let pts: Vec<(f64, f64)> = [0.1, 0.3, 0.6, 0.9]
        .iter()
        .map(|&p: &f64| (p, 7.0 * p.powf(0.43)))
        .collect();
    assert!((power_law_exponent(&pts) - 0.43).abs() < 1e-12);
}

#[test]
fn validate_command_writes_the_report() {
    let tmp = tempfile::tempdir().unwrap();
    let o = peenflow(&["validate", "--seeds", "1", "--out", "v"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(tmp.path().join("v/validation.md")).unwrap();
    assert!(
        md.contains("| lone shot's impact speed, m/s | 65-70 | 60.1 | 71.2 |"),
        "{md}"
    );
    for f in [
        "impact_speed",
        "impact_radius",
        "table1_radius",
        "speed_vs_pressure",
    ] {
        for ext in ["png", "svg"] {
            assert!(
                tmp.path().join(format!("v/figures/{f}.{ext}")).exists(),
                "{f}.{ext}"
            );
        }
    }
}

#[test]
fn seed_bootstrap_verdicts() {
    use peenflow::validate::{Pooled, percentile_difference_ci, trend_verdict};
    let make = |base: f64| Pooled {
        collisions: 0,
        all_radii_by_seed: vec![],
        shots: 100,
        speeds: vec![],
        radii_mm: vec![],
        radii_by_seed: (0..10)
            .map(|s| {
                (0..10)
                    .map(|k| base + 0.1 * k as f64 + 0.01 * s as f64)
                    .collect()
            })
            .collect(),
    };
    let (wide, narrow) = (make(5.0), make(2.0));
    let ci = percentile_difference_ci(&wide, &narrow, 90.0);
    assert!(ci.0 > 2.5 && ci.1 < 3.5, "{ci:?}");
    assert_eq!(trend_verdict(ci), "agrees");
    assert_eq!(
        trend_verdict(percentile_difference_ci(&narrow, &wide, 90.0)),
        "opposite"
    );
    assert!(
        trend_verdict(percentile_difference_ci(&wide, &wide, 90.0)).starts_with("not resolved")
    );
}

/// In this model the spread comes from shot-shot collisions, and 0.5 mm shots in the same
/// bore collide less: they spread *narrower* than 0.8 mm shots, the opposite of the
/// paper's Table 1 (docs/validation.md). Guarded over 20 seeds (measured interval of the
/// difference of 90th-percentile radii: -2.4 to -0.7 mm), so a change of the collision
/// physics that moves it shows up.
#[test]
fn smaller_shots_spread_narrower_in_this_model() {
    use peenflow::validate::{percentile_difference_ci, table1, trend_verdict};
    let t1 = pooled(&table1(1), 20);
    let t4 = pooled(&table1(4), 20);
    let ci = percentile_difference_ci(&t4, &t1, 90.0);
    println!("p90 0.5 mm minus 0.8 mm: {ci:?}");
    assert_eq!(trend_verdict(ci), "opposite");
}

/// Lower pressure slows every shot alike and leaves the collision pattern as it is: in
/// this model the 0.3 MPa and 0.6 MPa spreads differ by less than the seed noise (measured
/// over 20 seeds: interval of the difference of 90th-percentile radii -0.8 to +1.1 mm; the
/// paper measured a wider spread at 0.3 MPa). A change that makes pressure move the spread
/// either way (e.g. a dispersion mechanism that depends on shot speed) resolves the interval
/// and fails here, to be re-judged against the paper's trend.
#[test]
fn pressure_moves_the_spread_less_than_the_seed_noise_in_this_model() {
    use peenflow::validate::{percentile_difference_ci, table1, trend_verdict};
    let t1 = pooled(&table1(1), 20);
    let t3 = pooled(&table1(3), 20);
    let ci = percentile_difference_ci(&t3, &t1, 90.0);
    println!("p90 0.3 MPa minus 0.6 MPa: {ci:?}");
    assert!(trend_verdict(ci).starts_with("not resolved"), "{ci:?}");
    assert!(
        ci.1 - ci.0 < 3.0,
        "interval too wide to mean anything: {ci:?}"
    );
}
