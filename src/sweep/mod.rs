//! Sweeps: one base scene, parameters varied over lists or ranges (cartesian product or
//! zipped), every case run over a set of seeds, in parallel; resumable, shardable across
//! a cluster, merged into one sweep.h5. See docs/cluster.md.
//!
//! Stages: [`plan`] (sweep file -> validated cases with content hashes), [`run`]
//! (cases -> case directories, atomically; skip finished ones), [`merge`] (shard
//! directories -> one), [`assemble`] (case directories -> sweep.h5, cases.csv, figures).

pub mod assemble;
pub mod merge;
pub mod plan;
pub mod run;
pub mod stats;

pub use plan::{Case, Combine, Plan, SweepError};
pub use run::{Manifest, Options, Report, SweepRunError};
