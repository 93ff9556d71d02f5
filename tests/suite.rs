//! The integration tests, as one test binary.
//!
//! `cargo test --release` builds test binaries with the release profile (fat LTO, one
//! code unit), so every test binary pays a whole-program link of about 25 s on two
//! cores. The 38 files as 38 binaries took 11 min of build in CI; as modules of this
//! one binary they link once. Each file below is one module, named as before
//! (`cargo test --release --test suite events::` runs tests/events.rs alone); a new test
//! file must be added here (`autotests = false` in Cargo.toml).

mod common;

mod accuracy;
mod angle;
mod blocks;
mod conservation;
mod coverage;
mod cut_steps;
mod cylinder;
mod determinism;
mod events;
mod export_cli;
mod fe_decks;
mod feeds;
mod friction;
mod fuzz_scene;
mod gear;
mod groove;
mod hard_cases;
mod hdf5_export;
mod hybrid;
mod jet_loading;
mod liggghts;
mod physics_default_scene;
mod physics_hertz;
mod physics_single_shot;
mod properties;
mod restitution_curve;
mod run_figure;
mod run_goes_bad;
mod scenes;
mod separate_clocks;
mod sleepers;
mod slow_kinks;
mod streaming;
mod sub_windows;
mod sweep;
mod traverse;
mod turbulence;
mod validation;
mod verlet;
