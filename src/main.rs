//! `peenflow` binary: parse arguments, run, turn an error into one message and exit 2.

use clap::Parser;

// mimalloc: the event scheduler's clusters allocate small buffers per contact; with the
// system allocator that was 3 % of the pack stream's instructions (docs/performance-history.md).
#[cfg(feature = "mimalloc")]
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let cli = peenflow::cli::Cli::parse();
    if let Err(e) = peenflow::cli::run(cli) {
        eprintln!("peenflow: error: {}", peenflow::cli::error_message(&e));
        std::process::exit(2);
    }
}
