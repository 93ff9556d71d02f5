//! Integrator stage: the Dormand-Prince step and the island integrator that owns the
//! clock of each group of shots (see `island.rs` for how steps are chosen).

pub mod dopri;
pub mod island;

pub use island::{IslandOutput, IslandPair, Physics, Scratch};

use crate::Vec3;

/// The vector held in `y[o..o + 3]`, with one bounds check rather than three: the
/// integrators read their flat states this way (on the pack stream the separate checks
/// of `Vec3::new(y[o], y[o + 1], y[o + 2])` cost 5 % of all instructions).
#[inline]
pub(crate) fn vec_at(y: &[f64], o: usize) -> Vec3 {
    let [a, b, c] = *<&[f64; 3]>::try_from(&y[o..o + 3]).expect("BUG: three values");
    Vec3::new(a, b, c)
}

/// Adds `a` to `y[o..o + 3]` (one bounds check).
#[inline]
pub(crate) fn add_at(y: &mut [f64], o: usize, a: &Vec3) {
    let [x, yy, z] = <&mut [f64; 3]>::try_from(&mut y[o..o + 3]).expect("BUG: three values");
    *x += a.x;
    *yy += a.y;
    *z += a.z;
}
