//! `peenflow accuracy`: what accuracy costs in time.
//!
//! Runs a scene over a ladder of settings, the integrator tolerance of the adaptive
//! method and, for contrast, the fixed step of a velocity-Verlet baseline (how classic DEM
//! codes integrate) and of the hybrid method (adaptive in flight at the scene's
//! tolerance, that step inside contacts), and measures against a converged reference run
//! (tolerance 1e-10; on the history tangential law, which the adaptive method cannot
//! carry, the hybrid method at tolerance 1e-10 and 0.25 ns, without the adaptive rows)
//! the errors of what FE users consume: impact speed, impact position, impact time, hit
//! fraction; with wall time and step counts.
//!
//! Without shot-shot contact every shot's trajectory is deterministic and impacts are
//! compared one by one. With shot-shot contact the trajectories are chaotic (a 1e-12
//! difference grows until collisions differ), so single impacts cannot be compared: the
//! study then pools first hits over several seeds and compares distributions (mean and
//! percentiles of the normal impact speed and of the impact radius, the Wasserstein-1
//! distance between the speed distributions, the hit fraction).

use crate::integrate::island::Method;
use crate::record::Impact;
use crate::scene::Scene;
use crate::sim::Simulation;
use serde::Serialize;
use std::time::Instant;

/// One setting of the ladder.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Setting {
    /// Adaptive method at this relative tolerance.
    Tolerance(f64),
    /// Velocity Verlet at this fixed step, s.
    Verlet(f64),
    /// The hybrid method (the scene's tolerance in flight) with this step in contacts, s.
    Hybrid(f64),
    /// The reference of a scene on the history tangential law: the hybrid method at
    /// tolerance 1e-10 in flight and this step in contacts, s.
    HybridConverged(f64),
}

impl Setting {
    /// Method label.
    pub fn method(&self) -> &'static str {
        match self {
            Setting::Tolerance(_) => "adaptive",
            Setting::Verlet(_) => "verlet",
            Setting::Hybrid(_) | Setting::HybridConverged(_) => "hybrid",
        }
    }

    /// Human label.
    pub fn label(&self) -> String {
        match self {
            Setting::Tolerance(t) => format!("tolerance {t:e}"),
            Setting::Verlet(h) => format!("verlet step {} ns", h * 1e9),
            Setting::Hybrid(h) => format!("hybrid, step {} ns in contacts", h * 1e9),
            Setting::HybridConverged(h) => format!(
                "the hybrid method at tolerance 1e-10 with steps of {} ns in contacts",
                h * 1e9
            ),
        }
    }

    /// Sets `scene`'s integrator to this setting.
    pub fn apply(&self, scene: &mut Scene) {
        match *self {
            Setting::Tolerance(t) => {
                scene.integrator.tolerance = t;
                scene.integrator.method = Method::Adaptive;
            }
            Setting::Verlet(h) => scene.integrator.method = Method::Verlet { step: h },
            Setting::Hybrid(h) => scene.integrator.method = Method::Hybrid { step: h },
            Setting::HybridConverged(h) => {
                scene.integrator.tolerance = 1e-10;
                scene.integrator.method = Method::Hybrid { step: h };
            }
        }
    }

    /// The tolerance, or the fixed step in s.
    pub fn value(&self) -> f64 {
        match *self {
            Setting::Tolerance(v)
            | Setting::Verlet(v)
            | Setting::Hybrid(v)
            | Setting::HybridConverged(v) => v,
        }
    }
}

/// How outputs are compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Impact by impact (no shot-shot contact).
    Pairwise,
    /// Distributions over seeds (shot-shot contact makes trajectories chaotic).
    Distribution,
}

/// One row of accuracy.csv.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// "adaptive", "verlet" or "hybrid".
    pub method: &'static str,
    /// Tolerance, or fixed step in s.
    pub setting: f64,
    /// Wall time of the runs of this setting (one per seed; short runs averaged over
    /// repetitions), s.
    pub wall_time_s: f64,
    /// Shot-steps.
    pub shot_steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Relative error of the impact speed (pairwise: largest; distribution: of the mean
    /// normal speed).
    pub speed_error: f64,
    /// Impact position error, m (pairwise: largest; distribution: of the median radius).
    pub position_error_m: f64,
    /// Impact time error, s (pairwise: largest; distribution: of the mean time).
    pub time_error_s: f64,
    /// Hit-fraction difference.
    pub hit_fraction_error: f64,
    /// Wasserstein-1 distance of the normal-speed distributions over the mean speed
    /// (distribution mode; 0 in pairwise mode).
    pub speed_distribution_distance: f64,
    /// Normal-speed percentiles p10 / p50 / p90 errors, relative (distribution mode).
    pub speed_percentile_error: f64,
    /// The figure of merit compared with `--target`: the largest relative error among
    /// speed, time (over the reference's mean impact time), position (over the shot
    /// diameter) and, in distribution mode, the distribution distance and hit fraction.
    pub error: f64,
}

/// The study.
#[derive(Debug, Clone, Serialize)]
pub struct Study {
    /// Comparison mode.
    pub mode: Mode,
    /// Seeds used per setting.
    pub seeds: u64,
    /// Reference setting.
    pub reference: String,
    /// Rows.
    pub rows: Vec<Row>,
}

struct Outcome {
    impacts: Vec<Vec<Impact>>,
    hit_fraction: f64,
    wall: f64,
    shot_steps: u64,
    rhs: u64,
}

fn run(scene: &Scene, setting: Setting, seeds: &[u64], min_time: f64) -> Outcome {
    let mut s = scene.clone();
    setting.apply(&mut s);
    let effects = s.effects();
    let mut o = Outcome {
        impacts: vec![],
        hit_fraction: 0.0,
        wall: 0.0,
        shot_steps: 0,
        rhs: 0,
    };
    let mut hits = 0.0;
    for &seed in seeds {
        s.seed = seed;
        // Short runs are timed over repetitions (at least `min_time` in all) and averaged.
        let mut reps = 0u32;
        let mut spent = 0.0;
        let out = loop {
            let sim = Simulation::new(&s, &effects).expect("BUG: the scene was validated");
            let start = Instant::now();
            let out = sim.run(&|_| {});
            spent += start.elapsed().as_secs_f64();
            reps += 1;
            if spent >= min_time || reps >= 1000 {
                break out;
            }
        };
        o.wall += spent / reps as f64;
        o.shot_steps += out.work.shot_steps;
        o.rhs += out.work.rhs_evaluations;
        hits +=
            out.shots.iter().filter(|s| s.hits > 0).count() as f64 / out.shots.len().max(1) as f64;
        o.impacts.push(out.impacts);
    }
    o.hit_fraction = hits / seeds.len() as f64;
    o
}

fn percentile(v: &[f64], q: f64) -> f64 {
    crate::summary::percentile(v, q)
}

/// Wasserstein-1 distance between two empirical distributions (sorted samples), by
/// integrating the difference of their quantile functions on a common grid.
pub fn wasserstein1(a: &[f64], b: &[f64]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    let n = 1000;
    (0..n)
        .map(|k| {
            let q = 100.0 * (k as f64 + 0.5) / n as f64;
            (percentile(a, q) - percentile(b, q)).abs()
        })
        .sum::<f64>()
        / n as f64
}

fn compare(
    mode: Mode,
    reference: &Outcome,
    o: &Outcome,
    diameter: f64,
) -> (f64, f64, f64, f64, f64, f64, f64) {
    let rel = |a: f64, b: f64| {
        if b == 0.0 {
            (a - b).abs()
        } else {
            ((a - b) / b).abs()
        }
    };
    match mode {
        Mode::Pairwise => {
            let (mut es, mut ep, mut et, mut t_scale) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            let mut missing = 0usize;
            for (ri, oi) in reference.impacts.iter().zip(&o.impacts) {
                // Match impacts by shot and order of its hits.
                let mut by_shot = std::collections::BTreeMap::<u32, Vec<&Impact>>::new();
                for m in oi {
                    by_shot.entry(m.shot).or_default().push(m);
                }
                let mut seen = std::collections::BTreeMap::<u32, usize>::new();
                for r in ri {
                    let k = seen.entry(r.shot).or_insert(0);
                    match by_shot.get(&r.shot).and_then(|v| v.get(*k)) {
                        Some(m) => {
                            es = es.max(rel(m.speed_m_s, r.speed_m_s));
                            ep = ep.max(((m.x_m - r.x_m).powi(2) + (m.y_m - r.y_m).powi(2)).sqrt());
                            et = et.max((m.time_s - r.time_s).abs());
                            t_scale = t_scale.max(r.time_s);
                        }
                        None => missing += 1,
                    }
                    *k += 1;
                }
                missing += oi.len().saturating_sub(ri.len());
            }
            let eh = (o.hit_fraction - reference.hit_fraction).abs();
            let mut err = es.max(et / t_scale.max(1e-12)).max(ep / diameter).max(eh);
            if missing > 0 {
                err = err.max(1.0);
            }
            (es, ep, et, eh, 0.0, 0.0, err)
        }
        Mode::Distribution => {
            let pool = |o: &Outcome, f: fn(&Impact) -> f64| {
                let mut v: Vec<f64> = o
                    .impacts
                    .iter()
                    .flatten()
                    .filter(|m| m.first_hit == 1)
                    .map(f)
                    .collect();
                v.sort_by(f64::total_cmp);
                v
            };
            let (sr, so) = (
                pool(reference, |m| m.normal_speed_m_s),
                pool(o, |m| m.normal_speed_m_s),
            );
            let (rr, ro) = (pool(reference, |m| m.radius_m()), pool(o, |m| m.radius_m()));
            let (tr, to) = (pool(reference, |m| m.time_s), pool(o, |m| m.time_s));
            if sr.is_empty() || so.is_empty() {
                return (
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::INFINITY,
                    1.0,
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::INFINITY,
                );
            }
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
            let es = rel(mean(&so), mean(&sr));
            let ep = (percentile(&ro, 50.0) - percentile(&rr, 50.0)).abs();
            let et = (mean(&to) - mean(&tr)).abs();
            let eh = (o.hit_fraction - reference.hit_fraction).abs();
            let w1 = wasserstein1(&so, &sr) / mean(&sr);
            let pe = [10.0, 50.0, 90.0]
                .iter()
                .map(|&q| rel(percentile(&so, q), percentile(&sr, q)))
                .fold(0.0, f64::max);
            let err = es.max(w1).max(eh).max(et / mean(&tr));
            (es, ep, et, eh, w1, pe, err)
        }
    }
}

/// The ladder for `scene`: [`ladder`], without the fixed-step rows when the scene has
/// turbulent dispersion (those methods do not renew eddies; the scene loader refuses them
/// with it), and without the adaptive rows when it is on the history tangential law
/// (the adaptive method cannot carry it; its reference is then [`reference_for`]'s).
pub fn ladder_for(scene: &Scene) -> Vec<Setting> {
    let mut v = ladder();
    if scene.friction.history {
        v.retain(|s| !matches!(s, Setting::Tolerance(_)));
    } else if scene.effects().turbulent_dispersion {
        v.retain(|s| matches!(s, Setting::Tolerance(_)));
    }
    v
}

/// The converged run a study compares with: the adaptive method at tolerance 1e-10; on
/// the history tangential law, which needs a fixed step inside contacts, the hybrid
/// method at tolerance 1e-10 with 0.25 ns steps in contacts (its rebounds converge at
/// order about 1.4 in the step: 6e-4 of the impact speed at 20 ns, some 1e-6 at 0.25 ns;
/// tests/hybrid.rs).
pub fn reference_for(scene: &Scene) -> Setting {
    if scene.friction.history {
        Setting::HybridConverged(0.25e-9)
    } else {
        Setting::Tolerance(1e-10)
    }
}

/// The default ladder.
pub fn ladder() -> Vec<Setting> {
    let mut v: Vec<Setting> = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
        .iter()
        .map(|&t| Setting::Tolerance(t))
        .collect();
    v.extend(
        [100e-9, 50e-9, 20e-9, 10e-9]
            .iter()
            .map(|&h| Setting::Verlet(h)),
    );
    v.extend(
        [100e-9, 50e-9, 20e-9, 10e-9, 5e-9]
            .iter()
            .map(|&h| Setting::Hybrid(h)),
    );
    v
}

/// Runs the study. Runs shorter than `min_time` (s) are repeated until that much time has
/// passed and their mean is reported (the CLI uses 0.05 s). `progress(k, n)` after each
/// setting.
pub fn study(
    scene: &Scene,
    seeds: u64,
    settings: &[Setting],
    min_time: f64,
    progress: &dyn Fn(usize, usize),
) -> Study {
    let effects = scene.effects();
    let mode = if effects.shot_shot_contact {
        Mode::Distribution
    } else {
        Mode::Pairwise
    };
    let seeds_list: Vec<u64> = match mode {
        Mode::Pairwise => vec![scene.seed],
        Mode::Distribution => (0..seeds).map(|k| scene.seed + k).collect(),
    };
    let reference_setting = reference_for(scene);
    let reference = run(scene, reference_setting, &seeds_list, 0.0);
    let diameter = scene.sizes.max_diameter();
    let mut rows = Vec::new();
    for (k, &st) in settings.iter().enumerate() {
        let o = run(scene, st, &seeds_list, min_time);
        let (es, ep, et, eh, w1, pe, err) = compare(mode, &reference, &o, diameter);
        rows.push(Row {
            method: st.method(),
            setting: st.value(),
            wall_time_s: o.wall,
            shot_steps: o.shot_steps,
            rhs_evaluations: o.rhs,
            speed_error: es,
            position_error_m: ep,
            time_error_s: et,
            hit_fraction_error: eh,
            speed_distribution_distance: w1,
            speed_percentile_error: pe,
            error: err,
        });
        progress(k + 1, settings.len());
    }
    Study {
        mode,
        seeds: seeds_list.len() as u64,
        reference: reference_setting.label(),
        rows,
    }
}

impl Study {
    /// The cheapest row (least wall time) whose error is at most `target`.
    pub fn recommend(&self, target: f64) -> Option<&Row> {
        self.rows
            .iter()
            .filter(|r| r.error <= target)
            .min_by(|a, b| a.wall_time_s.total_cmp(&b.wall_time_s))
    }

    /// The table as text.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "comparison: {} against {} ({} seed{})",
            match self.mode {
                Mode::Pairwise => "impact by impact",
                Mode::Distribution =>
                    "distributions of first hits over seeds (shot-shot collisions make single trajectories chaotic)",
            },
            self.reference,
            self.seeds,
            if self.seeds == 1 { "" } else { "s" }
        );
        let _ = writeln!(
            s,
            "{:<9} {:>10} {:>10} {:>12} {:>10} {:>11} {:>11} {:>9} {:>10}",
            "method",
            "setting",
            "wall s",
            "shot-steps",
            "speed err",
            "pos err um",
            "time err us",
            "hit err",
            "error"
        );
        for r in &self.rows {
            let setting = if r.method == "adaptive" {
                format!("{:e}", r.setting)
            } else {
                format!("{} ns", r.setting * 1e9)
            };
            let _ = writeln!(
                s,
                "{:<9} {:>10} {:>10.4} {:>12} {:>10.2e} {:>11.3} {:>11.4} {:>9.4} {:>10.2e}",
                r.method,
                setting,
                r.wall_time_s,
                r.shot_steps,
                r.speed_error,
                r.position_error_m * 1e6,
                r.time_error_s * 1e6,
                r.hit_fraction_error,
                r.error
            );
        }
        s
    }

    /// accuracy.csv.
    pub fn csv(&self) -> Vec<u8> {
        let mut w = csv::Writer::from_writer(Vec::new());
        for r in &self.rows {
            w.serialize(r).expect("BUG: rows serialise");
        }
        w.into_inner().expect("BUG: in-memory writer")
    }

    /// Curves of error against wall time, one per method the ladder ran.
    pub fn series(&self) -> Vec<crate::plot::Series> {
        ["adaptive", "verlet", "hybrid"]
            .iter()
            .map(|m| crate::plot::Series {
                name: match *m {
                    "adaptive" => "adaptive (tolerance ladder)".into(),
                    "verlet" => "velocity Verlet (fixed step)".into(),
                    _ => "hybrid (fixed step in contacts)".into(),
                },
                points: self
                    .rows
                    .iter()
                    .filter(|r| r.method == *m)
                    .map(|r| (r.wall_time_s, r.error.max(1e-12)))
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    }
}

/// Parses a target such as `0.1%` or `0.001`.
pub fn parse_target(s: &str) -> Option<f64> {
    let t = s.trim();
    let v = if let Some(p) = t.strip_suffix('%') {
        p.trim().parse::<f64>().ok()? / 100.0
    } else {
        t.parse::<f64>().ok()?
    };
    (v > 0.0 && v.is_finite()).then_some(v)
}
