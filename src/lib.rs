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

/// `x.floor() as i64`, to the bit (saturating as that does; NaN gives 0), without the
/// library call `floor` is on the baseline x86-64 target (no SSE4.1 rounding
/// instruction): the cell of a coordinate, computed several times per scan
/// (measured: `floor` was 0.7 % of the matched pack's instructions).
#[inline]
pub fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    i.saturating_sub(i64::from(x < i as f64))
}

#[cfg(test)]
mod tests {
    #[test]
    fn floor_i64_is_floor_as_i64() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.0 - f64::EPSILON,
            -1.0 + f64::EPSILON,
            -1.0 - f64::EPSILON,
            2f64.powi(52) + 1.0,
            -(2f64.powi(52)) - 1.0,
            2f64.powi(63),
            -(2f64.powi(63)),
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        // A spread of magnitudes and fractions, both signs.
        let mut x = 1e-6;
        while x < 1e20 {
            for f in [1.0, 1.37, 2.5, 7.999] {
                xs.push(x * f);
                xs.push(-x * f);
            }
            x *= 3.1;
        }
        for x in xs {
            assert_eq!(super::floor_i64(x), x.floor() as i64, "x = {x:e}");
        }
    }
}
