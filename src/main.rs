//! `peenflow` binary: parse arguments, run, turn an error into one message and exit 2.

use clap::Parser;

fn main() {
    let cli = peenflow::cli::Cli::parse();
    if let Err(e) = peenflow::cli::run(cli) {
        eprintln!("peenflow: error: {e:#}");
        std::process::exit(2);
    }
}
