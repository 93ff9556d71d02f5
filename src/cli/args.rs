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
    /// shots.csv and summary.json.
    Run(RunArgs),
    /// Write a commented scene file (the paper's Table 2 scene) to start from.
    Init(InitArgs),
    /// List the built-in materials.
    Materials,
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
}

/// `peenflow init`.
#[derive(Debug, clap::Args)]
pub struct InitArgs {
    /// Where to write the scene (`-` for standard output).
    #[arg(default_value = "scene.toml")]
    pub path: PathBuf,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
}
