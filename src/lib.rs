//! peenflow: shot-peening shots from the nozzle to the part.
//!
//! Shots are accelerated by the paper's empirical compressed-air jet (drag and a lateral
//! jet force), collide with each other, the nozzle bore and the specimen (Hertz contact
//! with calibrated damping), and every shot-specimen contact is recorded for downstream
//! finite-element impact analyses. See docs/ARCHITECTURE.md for the pipeline.

#![warn(missing_docs)]

pub mod accuracy;
pub mod cli;
pub mod contact;
pub mod counters;
pub mod coverage;
pub mod events;
pub mod export;
pub mod feed;
pub mod flow;
pub mod forces;
pub mod integrate;
pub mod mesh;
pub mod output;
pub mod plot;
pub mod record;
pub mod scene;
pub mod sim;
pub mod state;
pub mod summary;
pub mod sweep;
pub mod validate;

/// 3-vector of `f64` (SI units throughout).
pub type Vec3 = nalgebra::Vector3<f64>;
