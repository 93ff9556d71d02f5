//! Integrator stage: the Dormand-Prince step and the island integrator that owns the
//! clock of each group of shots (see `island.rs` for how steps are chosen).

pub mod dopri;
pub mod island;

pub use island::{IslandOutput, IslandPair, Physics, Scratch};
