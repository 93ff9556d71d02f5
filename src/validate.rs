//! `peenflow validate`: the paper's reported outcomes and published trends against
//! peenflow, written as a Markdown report with figures (docs/validation.md is its output).
//!
//! * Table 2 scene over 5 seeds (default `rho*` core, and `rho_0`): lone-shot impact speed
//!   (paper: 65-70 m/s), share of shots hitting at 60-80 m/s (about 65 %), share never
//!   reaching the specimen in 10 ms (19 %), peak of the impact-radius histogram
//!   (5-10 mm) and share within 20 mm.
//! * Table 1 tests 1-5 over 5 seeds: lower pressure, smaller shots, more shots each give a
//!   broader spread of impact locations.
//! * Where the spread comes from: the Table 2 scene with shot-shot contact, the lateral
//!   force, the nozzle wall, rebounds switched off, and on the experiments' A5052 specimen,
//!   each with the seed-bootstrap interval of its change.
//! * Beyond the paper: impact speed against pressure for several shot sizes, with the
//!   fitted power law, against the published trend (speed rising about as p^0.5).

use crate::plot::{self, Bars, Series};
use crate::record::Impact;
use crate::scene::{CoreDensity, Scene, Switch};
use crate::sim::{RunOutput, Simulation};
use crate::summary::percentile;
use std::fmt::Write;
use std::path::Path;

/// A change applied to a scene (one row of the effect-off table).
type SceneChange = Box<dyn Fn(&mut Scene)>;

/// First-hit statistics pooled over seeds.
#[derive(Debug, Clone, Default)]
pub struct Pooled {
    /// Shots over all seeds.
    pub shots: usize,
    /// First-hit normal speeds, m/s.
    pub speeds: Vec<f64>,
    /// First-hit radii, mm.
    pub radii_mm: Vec<f64>,
    /// First-hit radii, mm, per seed (for the seed bootstrap of trends).
    pub radii_by_seed: Vec<Vec<f64>>,
    /// Shot-shot collisions over all seeds.
    pub collisions: u64,
    /// Radii of every impact (first hits and the re-hits of rebounding shots), mm, per
    /// seed: the experiments counted every indentation.
    pub all_radii_by_seed: Vec<Vec<f64>>,
}

impl Pooled {
    /// Share of shots (not of hits) whose first hit is at 60-80 m/s.
    pub fn share_60_80(&self) -> f64 {
        self.speeds
            .iter()
            .filter(|&&v| (60.0..80.0).contains(&v))
            .count() as f64
            / self.shots as f64
    }
    /// Share of shots that never reached the specimen.
    pub fn never(&self) -> f64 {
        1.0 - self.speeds.len() as f64 / self.shots as f64
    }
    /// Histogram of radii in 5 mm bins (counts), 10 bins.
    pub fn radius_histogram(&self) -> Vec<f64> {
        let mut h = vec![0.0; 10];
        for &r in &self.radii_mm {
            let k = ((r / 5.0) as usize).min(9);
            h[k] += 1.0;
        }
        h
    }
    /// Lower edge (mm) of the fullest 5 mm radius bin.
    pub fn radius_peak_mm(&self) -> f64 {
        let h = self.radius_histogram();
        let k = (0..h.len())
            .max_by(|&a, &b| h[a].total_cmp(&h[b]).then(b.cmp(&a)))
            .unwrap_or(0);
        5.0 * k as f64
    }
    /// Share of hits within 20 mm of the axis.
    pub fn within_20mm(&self) -> f64 {
        self.radii_mm.iter().filter(|&&r| r < 20.0).count() as f64
            / self.radii_mm.len().max(1) as f64
    }
    /// Percentile of the radii, mm.
    pub fn radius_p(&self, q: f64) -> f64 {
        let mut v = self.radii_mm.clone();
        v.sort_by(f64::total_cmp);
        percentile(&v, q)
    }
    /// Mean speed, m/s.
    pub fn mean_speed(&self) -> f64 {
        self.speeds.iter().sum::<f64>() / self.speeds.len().max(1) as f64
    }
    /// The same runs with every impact counted (radii only): what an indentation count
    /// on the specimen sees.
    pub fn every_impact(&self) -> Pooled {
        Pooled {
            radii_mm: self.all_radii_by_seed.concat(),
            radii_by_seed: self.all_radii_by_seed.clone(),
            ..Pooled::default()
        }
    }
}

/// Runs `scene` for `seeds` seeds from 1 and pools first hits. The seeds run in
/// parallel and are pooled in seed order (the same result on any thread count).
pub fn pooled(scene: &Scene, seeds: u64) -> Pooled {
    use rayon::prelude::*;
    let runs: Vec<RunOutput> = (1..=seeds)
        .into_par_iter()
        .map(|seed| {
            let mut s = scene.clone();
            s.seed = seed;
            Simulation::new(&s, &s.effects())
                .expect("BUG: validated scene")
                .run(&|_| {})
        })
        .collect();
    let mut p = Pooled::default();
    for out in runs {
        p.shots += out.shots.len();
        p.collisions += out.shots.iter().map(|s| s.collisions as u64).sum::<u64>() / 2;
        let mut mine = Vec::new();
        for m in out.impacts.iter().filter(|m| m.first_hit == 1) {
            p.speeds.push(m.normal_speed_m_s);
            p.radii_mm.push(m.radius_m() * 1e3);
            mine.push(m.radius_m() * 1e3);
        }
        p.radii_by_seed.push(mine);
        p.all_radii_by_seed
            .push(out.impacts.iter().map(|m| m.radius_m() * 1e3).collect());
    }
    p
}

fn lone_shot_speed(core: CoreDensity, pressure_mpa: f64, diameter_mm: f64) -> Option<f64> {
    let text = format!(
        "duration_ms = 40.0\ngravity_m_s2 = 0.0\n[air]\ngauge_pressure_mpa = {pressure_mpa}\n[jet]\ncore_density = \"{}\"\n[shots]\ndiameter_mm = {diameter_mm}\nmaterial = \"SUJ-2\"\n[shots.feed]\ntype = \"list\"\n[[shots.feed.shots]]\nposition_mm = [0.0, 0.0, 140.0]\n[effects]\nshot_shot_contact = false\n",
        match core {
            CoreDensity::RhoStar => "rho_star",
            CoreDensity::Rho0 => "rho_0",
        }
    );
    let scene = Scene::from_toml(&text, "validate").expect("BUG: generated scene");
    let out = Simulation::new(&scene, &scene.effects()).ok()?.run(&|_| {});
    out.impacts.first().map(|i: &Impact| i.normal_speed_m_s)
}

/// The paper's Table 1 test `test` (1-5) on the Table 2 scene.
pub fn table1(test: usize) -> Scene {
    let (d, p, n) = [
        (0.8, 0.6, 30),
        (0.8, 0.6, 40),
        (0.8, 0.3, 30),
        (0.5, 0.6, 30),
        (0.8, 0.6, 1),
    ][test - 1];
    let text = format!(
        "title = \"Table 1 test {test}\"\n[air]\ngauge_pressure_mpa = {p}\n[shots]\ndiameter_mm = {d}\n[shots.feed]\ntype = \"batch\"\ncount = {n}\nradial_offset_mm = [1.5, 2.6]\naxial_spread_mm = 10.0\n"
    );
    Scene::from_toml(&text, "table1").expect("BUG: generated scene")
}

/// 95 % interval of `q`-th percentile radius of `a` minus that of `b` (mm), by a seed
/// bootstrap: seeds are resampled with replacement (each seed's first hits stay
/// together, as collisions correlate them), 2000 times, with a fixed RNG seed.
pub fn percentile_difference_ci(a: &Pooled, b: &Pooled, q: f64) -> (f64, f64) {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(20_261_121);
    let draw = |p: &Pooled, rng: &mut rand_chacha::ChaCha8Rng| {
        let n = p.radii_by_seed.len();
        let mut v: Vec<f64> = (0..n)
            .flat_map(|_| p.radii_by_seed[rng.random_range(0..n)].iter().copied())
            .collect();
        v.sort_by(f64::total_cmp);
        percentile(&v, q)
    };
    let mut d: Vec<f64> = (0..2000)
        .map(|_| draw(a, &mut rng) - draw(b, &mut rng))
        .filter(|x| x.is_finite())
        .collect();
    d.sort_by(f64::total_cmp);
    (percentile(&d, 2.5), percentile(&d, 97.5))
}

/// Verdict on a trend the paper reports as `a > b`, from the 95 % interval of `a - b`.
pub fn trend_verdict(ci: (f64, f64)) -> &'static str {
    if ci.0 > 0.0 {
        "agrees"
    } else if ci.1 < 0.0 {
        "opposite"
    } else {
        "not resolved (within seed noise)"
    }
}

/// Least-squares power law `v = a p^n` through `(p, v)`: returns `n`.
pub fn power_law_exponent(points: &[(f64, f64)]) -> f64 {
    let k = points.len() as f64;
    let (sx, sy, sxx, sxy) = points
        .iter()
        .fold((0.0, 0.0, 0.0, 0.0), |(a, b, c, d), &(p, v)| {
            let (x, y) = (p.ln(), v.ln());
            (a + x, b + y, c + x * x, d + x * y)
        });
    (k * sxy - sx * sy) / (k * sxx - sx * sx)
}

fn verdict(ok: bool) -> &'static str {
    if ok { "agrees" } else { "differs" }
}

/// Runs everything and writes `validation.md` with figures under `out/figures`.
pub fn run(out: &Path, seeds: u64, progress: &dyn Fn(&str)) -> Result<String, plot::PlotError> {
    let fig = out.join("figures");
    std::fs::create_dir_all(&fig).map_err(|e| plot::PlotError::Draw {
        path: fig.display().to_string(),
        message: e.to_string(),
    })?;
    let mut md = String::new();
    let _ = writeln!(md, "# Validation against the paper and published trends\n");
    let _ = writeln!(
        md,
        "Generated by `peenflow validate --seeds {seeds}` (peenflow {}). Figures in `figures/`.\n",
        env!("CARGO_PKG_VERSION")
    );

    progress("lone shot");
    let v_star = lone_shot_speed(CoreDensity::RhoStar, 0.6, 0.8).unwrap_or(f64::NAN);
    let v_0 = lone_shot_speed(CoreDensity::Rho0, 0.6, 0.8).unwrap_or(f64::NAN);
    progress("paper scene");
    let base = Scene::default_scene();
    let paper = pooled(&base, seeds);
    let mut rho0_scene = base.clone();
    rho0_scene.jet.core_density = CoreDensity::Rho0;
    let paper0 = pooled(&rho0_scene, seeds);

    let _ = writeln!(md, "## The paper's scene (Table 2), {seeds} seeds\n");
    let _ = writeln!(
        md,
        "| outcome | paper | peenflow, `rho*` core (default) | peenflow, `rho_0` core | verdict |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    let in_range = |v: f64| (65.0..=70.0).contains(&v);
    let _ = writeln!(
        md,
        "| lone shot's impact speed, m/s | 65-70 | {v_star:.1} | {v_0:.1} | rho*: {}, rho_0: {} |",
        verdict(in_range(v_star)),
        verdict(in_range(v_0))
    );
    let row = |md: &mut String,
               name: &str,
               paper_text: &str,
               a: f64,
               b: f64,
               ok: &dyn Fn(f64) -> bool,
               pct: bool| {
        let f = |x: f64| {
            if pct {
                format!("{:.0} %", 100.0 * x)
            } else {
                format!("{x:.1}")
            }
        };
        let _ = writeln!(
            md,
            "| {name} | {paper_text} | {} | {} | rho*: {}, rho_0: {} |",
            f(a),
            f(b),
            verdict(ok(a)),
            verdict(ok(b))
        );
    };
    row(
        &mut md,
        "shots hitting at 60-80 m/s",
        "about 65 %",
        paper.share_60_80(),
        paper0.share_60_80(),
        &|x| (0.55..=0.75).contains(&x),
        true,
    );
    row(
        &mut md,
        "shots never reaching the specimen in 10 ms",
        "19 %",
        paper.never(),
        paper0.never(),
        &|x| (0.12..=0.26).contains(&x),
        true,
    );
    row(
        &mut md,
        "peak of the impact-radius histogram, mm (bin start)",
        "5-10",
        paper.radius_peak_mm(),
        paper0.radius_peak_mm(),
        &|x| x == 5.0,
        false,
    );
    row(
        &mut md,
        "hits within 20 mm of the centre",
        "most",
        paper.within_20mm(),
        paper0.within_20mm(),
        &|x| x > 0.5,
        true,
    );
    let _ = writeln!(
        md,
        "| mean normal impact speed of first hits, m/s | (60-80 for most) | {:.1} | {:.1} | |",
        paper.mean_speed(),
        paper0.mean_speed()
    );
    let _ = writeln!(md);

    let speed_bins: Vec<String> = (0..20).map(|k| format!("{}", 5 * k)).collect();
    let hist = |v: &[f64]| {
        let mut h = vec![0.0; 20];
        for &x in v {
            h[((x / 5.0) as usize).min(19)] += 1.0;
        }
        h
    };
    plot::bars(
        &fig.join("impact_speed"),
        "Normal impact speed of first hits (cf. paper Fig. 12)",
        ("speed, m/s (5 m/s bins, lower edge)", "shots"),
        &speed_bins,
        &[
            Bars {
                name: "rho* core".into(),
                values: hist(&paper.speeds),
            },
            Bars {
                name: "rho_0 core".into(),
                values: hist(&paper0.speeds),
            },
        ],
    )?;
    let radius_bins: Vec<String> = (0..10).map(|k| format!("{}", 5 * k)).collect();
    plot::bars(
        &fig.join("impact_radius"),
        "Impact radius of first hits (cf. paper Fig. 13)",
        (
            "radius, mm (5 mm bins, lower edge; last bin: 45 and more)",
            "shots",
        ),
        &radius_bins,
        &[
            Bars {
                name: "rho* core".into(),
                values: paper.radius_histogram(),
            },
            Bars {
                name: "rho_0 core".into(),
                values: paper0.radius_histogram(),
            },
        ],
    )?;
    let _ = writeln!(
        md,
        "![impact speeds](figures/impact_speed.png)\n\n![impact radii](figures/impact_radius.png)\n"
    );

    progress("Table 1");
    let tests: Vec<Pooled> = (1..=5).map(|t| pooled(&table1(t), seeds)).collect();
    let _ = writeln!(
        md,
        "## Table 1 trends (measured in the paper), {seeds} seeds each\n"
    );
    let _ = writeln!(
        md,
        "| test | D, mm | P, MPa | N | hits | shot-shot collisions per shot | median radius, mm | 90th-percentile radius, mm | within 20 mm |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for (k, p) in tests.iter().enumerate() {
        let (d, pr, n) = [
            (0.8, 0.6, 30),
            (0.8, 0.6, 40),
            (0.8, 0.3, 30),
            (0.5, 0.6, 30),
            (0.8, 0.6, 1),
        ][k];
        let _ = writeln!(
            md,
            "| {} | {d} | {pr} | {n} | {} | {:.2} | {:.2} | {:.2} | {:.0} % |",
            k + 1,
            p.radii_mm.len(),
            2.0 * p.collisions as f64 / p.shots.max(1) as f64,
            p.radius_p(50.0),
            p.radius_p(90.0),
            100.0 * p.within_20mm()
        );
    }
    let p90 = |k: usize| tests[k].radius_p(90.0);
    let ci = |a: usize, b: usize| percentile_difference_ci(&tests[a], &tests[b], 90.0);
    let _ = writeln!(
        md,
        "\nVerdicts use the 95 % interval of the difference of the 90th-percentile radii from a \
         bootstrap over seeds (2000 resamples; a seed's hits stay together): \"agrees\" when \
         the interval lies on the paper's side of zero, \"opposite\" on the other side, \"not \
         resolved\" when it straddles zero (more seeds narrow it).\n"
    );
    let _ = writeln!(
        md,
        "| trend (the paper's measurements, its Figs. 3-5) | peenflow (90th-percentile radius) | 95 % interval of the difference | verdict | every indentation (re-hits of rebounds too): interval, verdict |\n|---|---|---|---|---|"
    );
    for (name, a, b) in [
        ("lower pressure spreads wider (test 3 vs 1)", 2usize, 0usize),
        ("smaller shots spread wider (test 4 vs 1)", 3, 0),
        ("more shots spread wider (test 1 vs 5)", 0, 4),
        ("more shots spread wider (test 2 vs 1)", 1, 0),
    ] {
        let c = ci(a, b);
        let e = percentile_difference_ci(&tests[a].every_impact(), &tests[b].every_impact(), 90.0);
        let _ = writeln!(
            md,
            "| {name} | {:.2} vs {:.2} mm | {:+.2} to {:+.2} mm | {} | {:+.2} to {:+.2} mm, {} |",
            p90(a),
            p90(b),
            c.0,
            c.1,
            trend_verdict(c),
            e.0,
            e.1,
            trend_verdict(e)
        );
    }
    let _ = writeln!(
        md,
        "\nReading it: with the paper's constants the lateral jet force moves a lone shot by \
         well under 0.1 mm (model-notes), so the spread comes from shot-shot collisions (the \
         next section switches them off). More shots collide more and spread wider, as the \
         paper finds. Smaller shots in the same bore collide less often (collisions per shot \
         above) and spread narrower: the opposite of the paper. Lower pressure slows every \
         shot alike and leaves the collision pattern, hence the spread, unresolved from \
         seed noise. The paper's measured trends point to a dispersion mechanism the \
         mean-flow model lacks; the candidate is turbulent dispersion in the jet (velocity \
         fluctuations of the mixing layer, followed more closely by small, slow shots: their \
         Stokes number scales as D^2 and with the speed). The next section switches it on.\n\n\
         What the paper's trends are, and the decision taken. Table 1's trends are \
         measurements (the paper's Figs. 3-5, indentations counted on the specimen); the \
         paper's own simulation reports only the Table 2 scene (Figs. 12-13) and leaves the \
         direct comparison with the experiments to future work. The text gives the measured \
         histograms only as the trends, so there are no numbers to calibrate a further \
         mechanism against. peenflow therefore implements the published model as it stands, \
         reports where it departs from the measurements (here) and guards what the model \
         does in each of the three comparisons (tests/validation.rs: more shots wider, \
         smaller shots narrower, pressure within seed noise), so that a physics change in \
         any of them fails CI. Counting every indentation, re-hits of rebounding shots \
         included (last column), gives the same verdicts.\n"
    );
    plot::bars(
        &fig.join("table1_radius"),
        "Impact radius by Table 1 test (cf. paper Figs. 3-5)",
        ("radius, mm (5 mm bins, lower edge)", "share of hits"),
        &radius_bins,
        &tests
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let h = p.radius_histogram();
                let n: f64 = h.iter().sum::<f64>().max(1.0);
                Bars {
                    name: format!("test {}", k + 1),
                    values: h.iter().map(|c| c / n).collect(),
                }
            })
            .collect::<Vec<_>>(),
    )?;
    let _ = writeln!(md, "\n![Table 1 radii](figures/table1_radius.png)\n");

    progress("turbulent dispersion");
    let _ = writeln!(
        md,
        "## Beyond the paper: turbulent dispersion ({seeds} seeds)\n\n\
         The paper's jet is a mean flow. With `jet.turbulence_intensity` > 0 shots also \
         meet random eddies in the mixing layer and developed jet (discrete random walk, \
         Gosman & Ioannides 1983; docs/model.md). Free round jets have intensities of \
         about 0.15-0.25 there. Table 1's trends with it:\n"
    );
    let _ = writeln!(
        md,
        "| intensity | p90 radius, tests 1 / 3 / 4 / 5, mm | lower pressure wider (3 vs 1) | smaller shots wider (4 vs 1) | more shots wider (1 vs 5) |\n|---|---|---|---|---|"
    );
    for intensity in [0.25, 0.5] {
        let runs: Vec<Pooled> = [1usize, 3, 4, 5]
            .iter()
            .map(|&t| {
                let mut sc = table1(t);
                sc.jet.turbulence_intensity = intensity;
                pooled(&sc, seeds)
            })
            .collect();
        let cell = |a: usize, b: usize| {
            let c = percentile_difference_ci(&runs[a], &runs[b], 90.0);
            format!("{:+.2} to {:+.2} mm: {}", c.0, c.1, trend_verdict(c))
        };
        let _ = writeln!(
            md,
            "| {intensity} | {:.2} / {:.2} / {:.2} / {:.2} | {} | {} | {} |",
            runs[0].radius_p(90.0),
            runs[1].radius_p(90.0),
            runs[2].radius_p(90.0),
            runs[3].radius_p(90.0),
            cell(1, 0),
            cell(2, 0),
            cell(0, 3)
        );
    }
    let _ = writeln!(
        md,
        "\nReading it: a lone 0.8 mm shot is scattered by only about 0.3 mm (per axis, at \
         intensity 0.2; tests/turbulence.rs): its drag relaxation time (milliseconds) is far \
         longer than an eddy's life (tens of microseconds). But the small scatter feeds the \
         collisions, and small shots respond more: the size trend, opposite without \
         turbulence, becomes unresolved at 0.25 and turns towards the paper's at 0.5 (an \
         intensity above what free jets show). Turbulence of realistic intensity does not \
         produce the paper's 5-10 mm radius peak.\n"
    );

    progress("effects");
    let _ = writeln!(
        md,
        "## Where the spread comes from (Table 2 scene, {seeds} seeds)\n"
    );
    let _ = writeln!(
        md,
        "| run | median radius, mm | 90th-percentile radius, mm | change of the 90th percentile from all effects, 95 % interval, mm | shots never reaching, % | mean normal speed, m/s |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    let _ = writeln!(
        md,
        "| all effects | {:.2} | {:.2} | | {:.0} | {:.1} |",
        paper.radius_p(50.0),
        paper.radius_p(90.0),
        100.0 * paper.never(),
        paper.mean_speed()
    );
    let off = |idx: usize| {
        move |s: &mut Scene| {
            s.effects.switches[idx] = Switch::Off;
        }
    };
    let variants: [(&str, SceneChange); 6] = [
        ("no shot-shot contact", Box::new(off(4))),
        ("no lateral force", Box::new(off(1))),
        ("no nozzle wall", Box::new(off(5))),
        (
            "no rebounds (shot-specimen restitution 0.05)",
            Box::new(|s: &mut Scene| {
                s.restitution.shot_specimen = 0.05;
                s.restitution.shot_specimen_curve = None;
            }),
        ),
        (
            "A5052 specimen (the experiments' material)",
            Box::new(|s: &mut Scene| {
                s.specimen_material =
                    crate::scene::material::builtin("A5052").expect("BUG: built-in material")
            }),
        ),
        (
            "A5052 specimen with the restitution CalculiX measures (0.34 at 20 m/s to 0.18 at 100 m/s)",
            Box::new(|s: &mut Scene| {
                s.specimen_material =
                    crate::scene::material::builtin("A5052").expect("BUG: built-in material");
                let curve = crate::contact::restitution::a5052_calculix();
                s.restitution.shot_specimen = curve.at(f64::INFINITY);
                s.restitution.shot_specimen_curve = Some(curve);
            }),
        ),
    ];
    let mut p90s = Vec::new();
    let mut verdicts = Vec::new();
    for (name, change) in variants {
        let mut s = base.clone();
        change(&mut s);
        let p = pooled(&s, seeds);
        let c = percentile_difference_ci(&p, &paper, 90.0);
        p90s.push(p.radius_p(90.0));
        verdicts.push(if c.0 > 0.0 || c.1 < 0.0 {
            "a significant change"
        } else {
            "within seed noise"
        });
        let _ = writeln!(
            md,
            "| {name} | {:.2} | {:.2} | {:+.2} to {:+.2} | {:.0} | {:.1} |",
            p.radius_p(50.0),
            p.radius_p(90.0),
            c.0,
            c.1,
            100.0 * p.never(),
            p.mean_speed()
        );
    }
    let all = paper.radius_p(90.0);
    let share = |p90: f64| 100.0 * (all - p90) / all;
    let _ = writeln!(
        md,
        "\nReading it (all effects: 90th-percentile radius {all:.2} mm). Without shot-shot \
         contact it is {:.2} mm ({}; {:.0} % of the radius comes from collisions in \
         flight, the rest is the start offset of 1.5-2.6 mm carried to the specimen). \
         Without rebounds it is {:.2} mm ({}; {:.0} %: shots bouncing off the specimen \
         and meeting those still coming). Switching off the lateral force ({:+.0} %) is \
         {}, the nozzle wall ({:+.0} %) {}; the experiments' softer A5052 specimen, at \
         the same restitution, is {} ({:.2} mm), and with the restitution a shot keeps \
         on it by CalculiX's single impacts (docs/fe-coupling.md) {} ({:.2} mm).\n",
        p90s[0],
        verdicts[0],
        share(p90s[0]),
        p90s[3],
        verdicts[3],
        share(p90s[3]),
        -share(p90s[1]),
        verdicts[1],
        -share(p90s[2]),
        verdicts[2],
        verdicts[4],
        p90s[4],
        verdicts[5],
        p90s[5]
    );

    progress("pressure sweep");
    let pressures = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8];
    let sizes = [0.063, 0.3, 0.71];
    let mut series = Vec::new();
    let _ = writeln!(md, "## Beyond the paper: impact speed against pressure\n");
    let _ = writeln!(
        md,
        "A lone SUJ-2 shot on the axis from the inlet, paper jet, `rho*` core. Published: Stevenson & Hutchings (1995) measured 16-85 m/s for 63-710 um particles through cylindrical nozzles and fitted a power law in pressure; fine-shot PIV studies report speed rising about as p^0.5.\n"
    );
    let _ = writeln!(
        md,
        "| shot diameter, mm | speeds at 0.1 ... 0.8 MPa, m/s | fitted exponent n (v ~ p^n) | verdict against p^0.5 (0.35-0.65) |"
    );
    let _ = writeln!(md, "|---|---|---|---|");
    for &d in &sizes {
        let pts: Vec<(f64, f64)> = pressures
            .iter()
            .filter_map(|&p| lone_shot_speed(CoreDensity::RhoStar, p, d).map(|v| (p, v)))
            .collect();
        let n = power_law_exponent(&pts);
        let speeds: Vec<String> = pts.iter().map(|p| format!("{:.0}", p.1)).collect();
        let _ = writeln!(
            md,
            "| {d} | {} | {n:.2} | {} |",
            speeds.join(", "),
            verdict((0.35..=0.65).contains(&n))
        );
        series.push(Series {
            name: format!("{} mm", d),
            points: pts,
        });
    }
    series.push(Series {
        name: "p^0.5 (through the 0.71 mm point at 0.6 MPa)".into(),
        points: {
            let v06 = series[2]
                .points
                .iter()
                .find(|p| (p.0 - 0.6).abs() < 1e-9)
                .map(|p| p.1)
                .unwrap_or(1.0);
            pressures
                .iter()
                .map(|&p| (p, v06 * (p / 0.6).sqrt()))
                .collect()
        },
    });
    plot::lines(
        &fig.join("speed_vs_pressure"),
        "Impact speed against gauge pressure",
        ("gauge pressure, MPa", "impact speed, m/s"),
        &series,
        true,
    )?;
    let _ = writeln!(
        md,
        "\n![speed against pressure](figures/speed_vs_pressure.png)\n"
    );
    Ok(md)
}
