//! Command-line arguments (clap derive): every flag documented once, here.

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Shot peening from the nozzle to the part: simulate shots through the air jet,
/// record every impact for FE analyses.
#[derive(Debug, Parser)]
#[command(name = "peenflow", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scene (default: the paper's Table 2 scene) and write impacts.csv,
    /// impacts.h5, shots.csv, summary.json and impacts.png/svg.
    Run(RunArgs),
    /// Write a commented scene file to start from: the paper's Table 2 scene, or one of
    /// the examples (--example NAME; --list shows them).
    Init(InitArgs),
    /// Export impacts (from a run's impacts.h5) as FE decks, VTK or CSV.
    Export(ExportArgs),
    /// Measure what accuracy costs in time: a ladder of integrator settings against a
    /// converged reference; table, accuracy.csv and a log-log plot.
    Accuracy(AccuracyArgs),
    /// Compare with the paper's outcomes and published trends; write validation.md
    /// and figures.
    Validate(ValidateArgs),
    /// Run a sweep over process conditions and seeds (resumable, shardable):
    /// `DIR/<case>/impacts.h5` per case and `DIR/sweep.h5` with all impacts and statistics.
    Sweep(SweepArgs),
    /// Combine the output directories of a sharded sweep into one sweep.h5.
    Merge(MergeArgs),
    /// Coverage from a run's impacts: map, coverage against time, Avrami fit, time to
    /// 98 % coverage; adds /coverage to the impact file.
    Coverage(CoverageArgs),
    /// List the built-in materials.
    Materials,
}

/// `peenflow coverage`.
#[derive(Debug, clap::Args)]
pub struct CoverageArgs {
    /// Impact file written by `peenflow run` (impacts.h5); with --gear-teeth, the files
    /// of runs on one rack at several offsets (a sweep's `DIR/*/impacts.h5`).
    #[arg(required = true, num_args = 1..)]
    pub impacts: Vec<PathBuf>,
    /// Window on the specimen, mm: x0,y0,x1,y1 (default: a square around the median
    /// impact point, half side the median distance of the impacts from it). On a
    /// cylindrical specimen, on its unrolled surface: the arc length around the bar from
    /// its crest, then the distance along its axis.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub window: Option<Vec<f64>>,
    /// Cell size, um (default: a fifth of the median dent radius; enlarged, with a note,
    /// where the window would need more than 2000 cells along a side).
    #[arg(long, allow_negative_numbers = true)]
    pub cell_um: Option<f64>,
    /// Target material (default: the scene's specimen). With a yield strength the dents
    /// are plastic; without, the Hertz contact footprint.
    #[arg(long)]
    pub target_material: Option<String>,
    /// Measured dents instead of the material's model: SPEED:RATIO,... with the normal
    /// impact speed in m/s and the dent radius over the shot radius, e.g. from
    /// `bench/fe_calibrate.py` (power law between points; docs/coverage.md).
    #[arg(long, value_delimiter = ',', value_name = "SPEED:RATIO")]
    pub dent_curve: Option<Vec<String>>,
    /// Output directory (coverage.csv, coverage.json, coverage_map, coverage_curve).
    #[arg(short, long, default_value = "coverage-out")]
    pub out: PathBuf,
    /// Write into a directory that already holds files.
    #[arg(long)]
    pub force: bool,
    /// Leave the impact file as it is (do not add /coverage).
    #[arg(long)]
    pub no_h5: bool,
    /// Seed to use from a sweep case's impacts.h5, which pools several (default: the
    /// first; the moving nozzle's figures pool them all).
    #[arg(long)]
    pub seed: Option<u64>,
    /// A moving nozzle: its traverse speed over the part, mm/s. Coverage of one pass
    /// across the track, and the speed and passes for full coverage, from this run's
    /// still nozzle (traverse.csv, traverse.png; docs/coverage.md).
    #[arg(long, allow_negative_numbers = true)]
    pub traverse_mm_s: Option<f64>,
    /// Direction of travel in the specimen plane, degrees from +x (default 0; with
    /// --traverse-mm-s). On a cylindrical specimen, on its unrolled surface: 0 is the
    /// bar turning under the nozzle (its surface speed), 90 the nozzle moving along it.
    #[arg(long, allow_negative_numbers = true)]
    pub traverse_deg: Option<f64>,
    /// Distance between neighbouring passes of a raster, mm (with --traverse-mm-s;
    /// raster.csv).
    #[arg(long, allow_negative_numbers = true)]
    pub pitch_mm: Option<f64>,
    /// A turning gear of this many teeth, the nozzle moving along its axis at
    /// --traverse-mm-s: coverage across a tooth space from still-nozzle runs on a rack
    /// at offsets over one pitch (gear.csv, gear.json, gear.png; docs/coverage.md).
    #[arg(long, allow_negative_numbers = true)]
    pub gear_teeth: Option<i64>,
    /// The turning gear's speed, rev/min (with --gear-teeth): checks the helical bands
    /// a large feed per revolution leaves along the axis.
    #[arg(long, allow_negative_numbers = true)]
    pub gear_rpm: Option<f64>,
}

/// `peenflow sweep`.
#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// Sweep file (TOML): base scene, `[vary]` parameters, seeds (see docs/cluster.md).
    pub sweep: PathBuf,
    /// Output directory. Run again with the same directory to resume.
    #[arg(short, long, default_value = "sweep-out")]
    pub out: PathBuf,
    /// Run only shard K of N (1-based): every N-th case starting at the K-th. Combine the
    /// shards with `peenflow merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Use a directory that holds other files or another sweep (changed cases re-run).
    #[arg(long)]
    pub force: bool,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(short = 'j', long)]
    pub threads: Option<usize>,
    /// Print the cases and exit without running.
    #[arg(long)]
    pub list: bool,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `peenflow merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Output directories of the shards (`peenflow sweep --shard K/N --out DIR`).
    #[arg(required = true, num_args = 1..)]
    pub dirs: Vec<PathBuf>,
    /// Where to gather the cases and write sweep.h5 (default: the first directory).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Use an --out directory that holds other files.
    #[arg(long)]
    pub force: bool,
}

/// `peenflow run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Scene file (TOML). Without it the embedded Table 2 scene runs.
    pub scene: Option<PathBuf>,
    /// Output directory.
    #[arg(short, long, default_value = "peenflow-out")]
    pub out: PathBuf,
    /// Write into an output directory that already holds files.
    #[arg(long)]
    pub force: bool,
    /// Override the scene's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(short = 'j', long)]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
    /// Also export the impacts in these formats into the output directory
    /// (abaqus, lsdyna, calculix, vtk, csv; default export options).
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub export: Vec<String>,
    /// Record shot positions every INTERVAL ms and write a ParaView series
    /// (snapshots/shots.pvd).
    #[arg(long, value_name = "INTERVAL_MS", allow_negative_numbers = true)]
    pub snapshots: Option<f64>,
    /// Target material of exported decks (default: the scene's specimen).
    #[arg(long)]
    pub target_material: Option<String>,
}

/// `peenflow export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Impact file written by `peenflow run` (impacts.h5).
    pub impacts: PathBuf,
    /// Formats: abaqus, lsdyna, calculix, vtk, csv (comma-separated or repeated).
    #[arg(short, long, value_delimiter = ',', num_args = 1.., required = true)]
    pub format: Vec<String>,
    /// Your own deck template (minijinja) instead of the built-in one.
    #[arg(long)]
    pub template: Option<PathBuf>,
    /// Deck units: si (m, kg, s, Pa) or mm-t-s (mm, tonne, s, MPa).
    #[arg(long, default_value = "mm-t-s")]
    pub units: String,
    /// Window on the specimen, mm: x0,y0,x1,y1.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub window: Option<Vec<f64>>,
    /// Time window, ms: t0,t1.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub time_window: Option<Vec<f64>>,
    /// Only first hits (no rebound hits).
    #[arg(long)]
    pub first_hits_only: bool,
    /// The first N impacts (after the windows).
    #[arg(long, conflicts_with = "sample")]
    pub first: Option<usize>,
    /// A random sample of N impacts (after the windows), drawn with --seed.
    #[arg(long)]
    pub sample: Option<usize>,
    /// Seed of --sample (default: the run's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Elastic meshed shots instead of rigid ones.
    #[arg(long)]
    pub elastic: bool,
    /// Target material (default: the scene's specimen; it needs a yield strength).
    #[arg(long)]
    pub target_material: Option<String>,
    /// Element size under the impacts, mm (default: shot radius / 4).
    #[arg(long, allow_negative_numbers = true)]
    pub element_size_mm: Option<f64>,
    /// Shot mesh resolution: cells along each edge of the mapped cube (default 4 for rigid
    /// shots, 6 for elastic ones; docs/fe-coupling.md has what ccx measured with each).
    #[arg(long)]
    pub shot_cells: Option<usize>,
    /// Output directory.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Overwrite existing files.
    #[arg(long)]
    pub force: bool,
}

/// `peenflow init`.
#[derive(Debug, clap::Args)]
pub struct InitArgs {
    /// Where to write the scene (`-` for standard output; default scene.toml, or
    /// NAME.toml with --example).
    pub path: Option<PathBuf>,
    /// Write the example scene NAME instead of the Table 2 scene (see --list).
    #[arg(long, value_name = "NAME")]
    pub example: Option<String>,
    /// List the examples and what each shows.
    #[arg(long, conflicts_with = "example")]
    pub list: bool,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
}

/// `peenflow accuracy`.
#[derive(Debug, clap::Args)]
pub struct AccuracyArgs {
    /// Scene file (default: the embedded Table 2 scene).
    pub scene: Option<PathBuf>,
    /// Recommend the cheapest setting whose error is at most this (e.g. 0.1%).
    #[arg(long)]
    pub target: Option<String>,
    /// Seeds per setting when shot-shot contact makes trajectories chaotic.
    #[arg(long, default_value_t = 5)]
    pub seeds: u64,
    /// Output directory (accuracy.csv, accuracy.png, accuracy.svg).
    #[arg(short, long, default_value = "accuracy-out")]
    pub out: PathBuf,
    /// Write into a directory that already holds files.
    #[arg(long)]
    pub force: bool,
    /// Worker threads.
    #[arg(short = 'j', long)]
    pub threads: Option<usize>,
}

/// `peenflow validate`.
#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// Seeds per scene.
    #[arg(long, default_value_t = 5)]
    pub seeds: u64,
    /// Output directory (validation.md, figures/).
    #[arg(short, long, default_value = "validation-out")]
    pub out: PathBuf,
    /// Write into a directory that already holds files.
    #[arg(long)]
    pub force: bool,
}
