//! Running a sweep into a directory, resuming, sharding and merging.
//!
//! Directory layout:
//! ```text
//! DIR/sweep.json          manifest: sweep text, base scene, seeds, every case's name,
//!                         values and hash (written first; shards and merge check it)
//! DIR/<case>/scene.toml   the case's resolved scene (seed = the sweep's first seed)
//! DIR/<case>/impacts.h5   impacts of all the case's seeds (column `seed`)
//! DIR/<case>/case.json    per-seed numbers and statistics across seeds; its `hash`
//!                         marks the case finished
//! DIR/<case>/speed.png|svg, radius.png|svg
//! DIR/sweep.h5, cases.csv, figures/   assembled when every case is present
//! ```
//! A case is computed in `DIR/.<case>.tmp-<pid>/` and renamed into place when complete,
//! so a killed sweep leaves finished cases and temporary directories, never a
//! half-written case; the next run removes the temporaries and skips finished cases.

use super::plan::{Case, Plan, show};
use super::stats::{AcrossSeeds, STATS};
use crate::export::hdf5::{self as h5, H5Error};
use crate::output::{self, OutputError};
use crate::plot::{self, PlotError};
use crate::scene::SceneError;
use crate::sim::{RunOutput, RunTail, Simulation};
use crate::summary::Summary;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;
use thiserror::Error;

/// Format tag of sweep.json and case.json.
pub const MANIFEST_FORMAT: &str = "peenflow-sweep/1";

/// Errors while running, resuming or merging a sweep.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SweepRunError {
    /// Output files.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// HDF5.
    #[error(transparent)]
    H5(#[from] H5Error),
    /// Plots.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A case's scene could not start (e.g. shot placement for one seed).
    #[error("case `{case}`, seed {seed}: {source}")]
    Case {
        /// Case.
        case: String,
        /// Seed.
        seed: u64,
        /// Cause.
        source: Box<SceneError>,
    },
    /// The directory or the shard outputs do not fit.
    #[error("{path}: {message}")]
    Dir {
        /// Directory or file.
        path: String,
        /// What is wrong and what to do.
        message: String,
    },
}

/// "3 of 8 cases ... (a, b, c)": names up to five missing cases.
pub(crate) fn missing_cases(
    dir: &Path,
    missing: &[String],
    total: usize,
    what: &str,
    advice: &str,
) -> SweepRunError {
    let shown: Vec<&str> = missing.iter().take(5).map(String::as_str).collect();
    dir_err(
        dir,
        format!(
            "{} of {total} cases {what} ({}{}){advice}",
            missing.len(),
            shown.join(", "),
            if missing.len() > 5 { ", ..." } else { "" }
        ),
    )
}

fn dir_err(path: &Path, message: impl Into<String>) -> SweepRunError {
    SweepRunError::Dir {
        path: path.display().to_string(),
        message: message.into(),
    }
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> SweepRunError + '_ {
    move |e| dir_err(path, e.to_string())
}

/// One case in the manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestCase {
    /// Position in the sweep.
    pub index: usize,
    /// Directory name.
    pub name: String,
    /// Content hash (tool version, resolved scene, seeds).
    pub hash: String,
    /// Values of the varied parameters, in the manifest's parameter order.
    pub values: Vec<toml::Value>,
    /// Resolved scene text.
    pub scene: String,
}

/// sweep.json: what a sweep directory holds or will hold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Format tag.
    pub format: String,
    /// Tool version.
    pub tool_version: String,
    /// Title.
    pub title: String,
    /// Sweep file as given.
    pub sweep_path: String,
    /// Sweep file text.
    pub sweep_text: String,
    /// Base scene file.
    pub base_path: String,
    /// Base scene text.
    pub base_text: String,
    /// Seeds.
    pub seeds: Vec<u64>,
    /// "product" or "zip".
    pub combine: String,
    /// Varied parameters.
    pub parameters: Vec<String>,
    /// Hash over the cases' hashes.
    pub sweep_hash: String,
    /// The cases.
    pub cases: Vec<ManifestCase>,
}

impl Manifest {
    /// The manifest of a plan.
    pub fn of(plan: &Plan) -> Manifest {
        Manifest {
            format: MANIFEST_FORMAT.into(),
            tool_version: env!("CARGO_PKG_VERSION").into(),
            title: plan.title.clone(),
            sweep_path: plan.path.clone(),
            sweep_text: plan.text.clone(),
            base_path: plan.base_path.clone(),
            base_text: plan.base_text.clone(),
            seeds: plan.seeds.clone(),
            combine: plan.combine.name().into(),
            parameters: plan.parameters.clone(),
            sweep_hash: plan.hash(),
            cases: plan
                .cases
                .iter()
                .map(|c| ManifestCase {
                    index: c.index,
                    name: c.name.clone(),
                    hash: c.hash.clone(),
                    values: c.values.clone(),
                    scene: c.scene_text.clone(),
                })
                .collect(),
        }
    }

    /// Reads `dir/sweep.json`.
    pub fn read(dir: &Path) -> Result<Manifest, SweepRunError> {
        let p = dir.join("sweep.json");
        let text = std::fs::read_to_string(&p).map_err(|e| {
            dir_err(
                dir,
                format!("not a sweep directory: cannot read sweep.json ({e})"),
            )
        })?;
        let m: Manifest = serde_json::from_str(&text)
            .map_err(|e| dir_err(&p, format!("not a peenflow sweep manifest ({e})")))?;
        if m.format != MANIFEST_FORMAT {
            return Err(dir_err(
                &p,
                format!("format `{}`, expected `{MANIFEST_FORMAT}`", m.format),
            ));
        }
        Ok(m)
    }

    fn write(&self, dir: &Path) -> Result<(), SweepRunError> {
        let mut json = serde_json::to_vec_pretty(self).expect("BUG: manifest serialises");
        json.push(b'\n');
        output::write_atomic(&dir.join("sweep.json"), &json)?;
        Ok(())
    }
}

/// One seed of a case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeedRun {
    /// Seed.
    pub seed: u64,
    /// Shots fed.
    pub shots: usize,
    /// Shots that hit.
    pub shots_hit: usize,
    /// Impacts (incl. rebound hits).
    pub impacts: usize,
    /// Shots that had to be stopped.
    pub events: usize,
    /// Wall time, s (not part of sweep.h5).
    pub wall_time_s: f64,
    /// The [`STATS`] of this run, by name.
    pub stats: BTreeMap<String, Option<f64>>,
}

/// case.json: a finished case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    /// Format tag.
    pub format: String,
    /// Case name.
    pub name: String,
    /// Position in the sweep.
    pub index: usize,
    /// Content hash (see [`Case::hash`]).
    pub hash: String,
    /// Varied parameters and their values.
    pub parameters: Vec<(String, toml::Value)>,
    /// Per seed.
    pub runs: Vec<SeedRun>,
    /// [`STATS`] across seeds, by name.
    pub stats: BTreeMap<String, AcrossSeeds>,
    /// Pooled first-hit histograms (all seeds): normal speed (5 m/s bins) and radius
    /// (5 mm bins), as in the run summary.
    pub speed_histogram: crate::summary::Histogram,
    /// See `speed_histogram`.
    pub radius_histogram: crate::summary::Histogram,
}

impl CaseResult {
    /// Reads `dir/case.json`, or `None` if there is none or it is unreadable.
    pub fn read(dir: &Path) -> Option<CaseResult> {
        let text = std::fs::read_to_string(dir.join("case.json")).ok()?;
        serde_json::from_str(&text).ok()
    }
}

/// How to run.
#[derive(Debug, Clone)]
pub struct Options {
    /// Output directory.
    pub out: PathBuf,
    /// Shard `(k, n)`, 1-based.
    pub shard: Option<(usize, usize)>,
    /// Replace a directory holding another sweep or other files.
    pub force: bool,
}

/// What a sweep run did.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// Cases this run computed.
    pub ran: Vec<String>,
    /// Cases found finished and skipped.
    pub skipped: Vec<String>,
    /// Cases replaced because their hash changed.
    pub replaced: Vec<String>,
    /// Shots stopped across the cases run now.
    pub events: usize,
    /// sweep.h5 written (all cases present).
    pub assembled: bool,
}

/// Runs the plan's cases (of one shard) into `opts.out`, skipping finished ones;
/// `progress(done, total, case)` is called as cases finish. Without a shard the sweep
/// is assembled at the end (sweep.h5, cases.csv, figures).
pub fn run(
    plan: &Plan,
    opts: &Options,
    progress: &(dyn Fn(usize, usize, &str) + Sync),
) -> Result<Report, SweepRunError> {
    let dir = &opts.out;
    let manifest = Manifest::of(plan);
    prepare(dir, &manifest, opts.force)?;
    manifest.write(dir)?;
    remove_temporaries(dir)?;
    let cases: Vec<&Case> = match opts.shard {
        Some((k, n)) => plan.shard(k, n),
        None => plan.cases.iter().collect(),
    };
    let mut report = Report::default();
    let mut todo = Vec::new();
    for c in &cases {
        let here = dir.join(&c.name);
        match CaseResult::read(&here) {
            Some(r)
                if r.hash == c.hash && here.join(crate::export::hdf5::IMPACT_FILE).is_file() =>
            {
                report.skipped.push(c.name.clone())
            }
            Some(_) => {
                report.replaced.push(c.name.clone());
                todo.push(*c);
            }
            None => todo.push(*c),
        }
    }
    let total = cases.len();
    let done = std::sync::atomic::AtomicUsize::new(report.skipped.len());
    progress(report.skipped.len(), total, "");
    let results: Vec<Result<usize, SweepRunError>> = todo
        .par_iter()
        .map(|c| {
            let events = run_case(c, &plan.parameters, &plan.seeds, dir)?;
            let d = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
            progress(d, total, &c.name);
            Ok(events)
        })
        .collect();
    for (c, r) in todo.iter().zip(results) {
        report.events += r?;
        report.ran.push(c.name.clone());
    }
    if opts.shard.is_none() {
        super::assemble::assemble(dir)?;
        report.assembled = true;
    }
    Ok(report)
}

/// Checks `dir` can take the sweep: missing, empty, or holding the same sweep (resume).
fn prepare(dir: &Path, manifest: &Manifest, force: bool) -> Result<(), SweepRunError> {
    if dir.exists() && dir.is_dir() && dir.join("sweep.json").exists() {
        let old = Manifest::read(dir);
        let same = old
            .as_ref()
            .map(|m| m.sweep_hash == manifest.sweep_hash)
            .unwrap_or(false);
        if !same && !force {
            let what = old
                .map(|m| format!("another sweep (\"{}\", {} cases)", m.title, m.cases.len()))
                .unwrap_or_else(|_| "an unreadable sweep.json".into());
            return Err(dir_err(
                dir,
                format!(
                    "holds {what}; use another --out, or --force to run this sweep there \
                     (cases whose scene changed are re-run)"
                ),
            ));
        }
        return Ok(());
    }
    output::prepare_dir(dir, force)?;
    Ok(())
}

fn remove_temporaries(dir: &Path) -> Result<(), SweepRunError> {
    for entry in std::fs::read_dir(dir).map_err(io_err(dir))? {
        let entry = entry.map_err(io_err(dir))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') && (name.contains(".tmp-") || name.contains(".old-")) {
            let p = entry.path();
            if p.is_dir() {
                std::fs::remove_dir_all(&p).map_err(io_err(&p))?;
            } else {
                std::fs::remove_file(&p).map_err(io_err(&p))?;
            }
        }
    }
    Ok(())
}

/// Runs one case over its seeds, writes its directory atomically; returns the number of
/// shots that had to be stopped.
fn run_case(
    case: &Case,
    parameters: &[String],
    seeds: &[u64],
    dir: &Path,
) -> Result<usize, SweepRunError> {
    let runs: Vec<(u64, RunOutput, Summary)> = seeds
        .par_iter()
        .map(|&seed| {
            let mut scene = case.scene.clone();
            scene.seed = seed;
            let effects = scene.effects();
            let started = Instant::now();
            let out = Simulation::new(&scene, &effects)
                .map_err(|source| SweepRunError::Case {
                    case: case.name.clone(),
                    seed,
                    source: Box::new(source),
                })?
                .run(&|_| {});
            let wall = started.elapsed().as_secs_f64();
            let summary = Summary::new(&scene, &effects.decisions, &out, wall, 1);
            Ok((seed, out, summary))
        })
        .collect::<Result<_, SweepRunError>>()?;
    let tmp = dir.join(format!(".{}.tmp-{}", case.name, std::process::id()));
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(io_err(&tmp))?;
    }
    std::fs::create_dir_all(&tmp).map_err(io_err(&tmp))?;
    let events = write_case(case, parameters, &runs, &tmp)?;
    let dest = dir.join(&case.name);
    if dest.exists() {
        let old = dir.join(format!(".{}.old-{}", case.name, std::process::id()));
        std::fs::rename(&dest, &old).map_err(io_err(&dest))?;
        std::fs::rename(&tmp, &dest).map_err(io_err(&dest))?;
        std::fs::remove_dir_all(&old).map_err(io_err(&old))?;
    } else {
        std::fs::rename(&tmp, &dest).map_err(io_err(&dest))?;
    }
    Ok(events)
}

fn write_case(
    case: &Case,
    parameters: &[String],
    runs: &[(u64, RunOutput, Summary)],
    tmp: &Path,
) -> Result<usize, SweepRunError> {
    let header = format!(
        "# peenflow sweep case `{}`: the base scene with {}\n# seeds run: {}\n",
        case.name,
        case_values_text(case),
        runs.iter()
            .map(|r| r.0.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    output::write_atomic(
        &tmp.join("scene.toml"),
        format!("{header}{}", case.scene_text).as_bytes(),
    )?;
    // Pool the seeds into one output: impacts and shots concatenated in seed order.
    let mut pooled = RunOutput {
        impacts: Vec::new(),
        shots: Vec::new(),
        tail: RunTail {
            events: Vec::new(),
            work: Default::default(),
            windows: 0,
            window_redos: 0,
            end_time: 0.0,
            snapshots: Vec::new(),
            scheduler: runs.first().map_or("windows", |r| r.1.scheduler),
            scheduler_note: None,
            peak_shots_held: 0,
            air_speed_factor: runs.first().map_or(1.0, |r| r.1.air_speed_factor),
        },
    };
    let mut impact_seeds = Vec::new();
    let mut shot_seeds = Vec::new();
    for (seed, out, _) in runs {
        pooled.impacts.extend(out.impacts.iter().cloned());
        impact_seeds.extend(std::iter::repeat_n(*seed, out.impacts.len()));
        pooled.shots.extend(out.shots.iter().cloned());
        shot_seeds.extend(std::iter::repeat_n(*seed, out.shots.len()));
        pooled.events.extend(out.events.iter().cloned());
        pooled.work.add(&out.work);
        pooled.windows += out.windows;
        pooled.window_redos += out.window_redos;
        pooled.end_time = pooled.end_time.max(out.end_time);
        pooled.peak_shots_held = pooled.peak_shots_held.max(out.peak_shots_held);
        if let Some(note) = &out.scheduler_note {
            pooled.scheduler = out.scheduler;
            pooled.scheduler_note = Some(format!("seed {seed}: {note}"));
        }
    }
    let mut scene = case.scene.clone();
    scene.seed = runs[0].0;
    let effects = scene.effects();
    let wall: f64 = runs.iter().map(|r| r.2.wall_time_s).sum();
    let pooled_summary = Summary::pooled(&scene, &effects.decisions, &pooled, wall, 1, runs.len());
    h5::write(
        &tmp.join(crate::export::hdf5::IMPACT_FILE),
        &h5::ImpactFileData {
            head: h5::FileHead {
                scene_text: &case.scene_text,
                scene_path: &scene.path,
                title: &scene.title,
                seed: scene.seed,
                simulated_time: pooled.end_time,
                specimen: &scene.specimen_shape,
            },
            impacts: &pooled.impacts,
            shots: &pooled.shots,
            summary: &pooled_summary,
            seeds: Some((&impact_seeds, &shot_seeds)),
        },
    )?;
    let seed_runs: Vec<SeedRun> = runs
        .iter()
        .map(|(seed, out, s)| SeedRun {
            seed: *seed,
            shots: s.shots,
            shots_hit: s.shots_hit,
            impacts: s.impacts,
            events: out.events.len(),
            wall_time_s: s.wall_time_s,
            stats: STATS
                .iter()
                .map(|d| (d.name.to_string(), (d.of)(s)))
                .collect(),
        })
        .collect();
    let stats = STATS
        .iter()
        .map(|d| {
            let v: Vec<Option<f64>> = runs.iter().map(|r| (d.of)(&r.2)).collect();
            (d.name.to_string(), AcrossSeeds::of(&v))
        })
        .collect();
    let result = CaseResult {
        format: MANIFEST_FORMAT.into(),
        name: case.name.clone(),
        index: case.index,
        hash: case.hash.clone(),
        parameters: parameters
            .iter()
            .cloned()
            .zip(case.values.iter().cloned())
            .collect(),
        runs: seed_runs,
        stats,
        speed_histogram: pooled_summary.normal_speed_histogram.clone(),
        radius_histogram: pooled_summary.radius_histogram.clone(),
    };
    case_plots(&result, tmp)?;
    let mut json = serde_json::to_vec_pretty(&result).expect("BUG: case result serialises");
    json.push(b'\n');
    output::write_atomic(&tmp.join("case.json"), &json)?;
    Ok(pooled.events.len())
}

fn case_values_text(case: &Case) -> String {
    case.values.iter().map(show).collect::<Vec<_>>().join(", ")
}

/// Share (%) of each histogram bin.
pub fn shares(h: &crate::summary::Histogram) -> Vec<f64> {
    let total: usize = h.counts.iter().sum::<usize>() + h.overflow;
    h.counts
        .iter()
        .map(|&c| {
            if total > 0 {
                100.0 * c as f64 / total as f64
            } else {
                0.0
            }
        })
        .collect()
}

/// Bin labels `lo-hi` of a histogram.
pub fn bin_labels(h: &crate::summary::Histogram) -> Vec<String> {
    h.lower_edges
        .iter()
        .map(|lo| format!("{}-{}", lo, lo + h.bin_width))
        .collect()
}

fn case_plots(r: &CaseResult, dir: &Path) -> Result<(), PlotError> {
    let seeds = r.runs.len();
    for (stem, h, label) in [
        (
            "speed",
            &r.speed_histogram,
            "normal impact speed of first hits, m/s",
        ),
        (
            "radius",
            &r.radius_histogram,
            "impact radius of first hits, mm",
        ),
    ] {
        plot::bars(
            &dir.join(stem),
            &format!("{}: {} ({seeds} seed(s) pooled)", r.name, h.quantity),
            (label, "share of first hits, %"),
            &bin_labels(h),
            &[plot::Bars {
                name: r.name.clone(),
                values: shares(h),
            }],
        )?;
    }
    Ok(())
}
