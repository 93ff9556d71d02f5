//! Shot-specimen restitution that depends on the impact speed (beyond the paper).
//!
//! The paper gives one restitution per material pair. A shot that dents the specimen
//! loses a share of its energy to plastic work that grows with the impact speed, so a
//! shot's rebound from a soft specimen is slower, relative to its impact, the faster it
//! hits (Johnson's fully plastic impact: `e ~ v^(-1/4)`). `[restitution]
//! shot_specimen_curve` gives `e` at a few normal impact speeds, for instance measured by
//! single-impact FE runs of peenflow's own decks (docs/fe-coupling.md); between the points
//! `e` is a power law of the speed (straight in log-log), beyond the first and last it
//! stays at their values.
//!
//! Each specimen contact takes the Tsuji damping that returns `e(v)` for its normal speed
//! `v` at the touch, and keeps it until it ends (`ShotState::specimen_damping`): the
//! damping is the contact's, not the instant's, so the rebound is exactly `e(v) v`.
//! [`SpeedLaw`] holds the curve and a table of the damping against `ln e` (the
//! calibration [`damping_for_restitution`] costs milliseconds a call; the table is built
//! once, in about 0.07 s, and a lookup costs 60 ns).

use super::hertz::{damping_for_restitution, restitution_for_damping};

/// Most points a curve may have.
pub const MAX_POINTS: usize = 32;

/// Restitution against the normal impact speed: points `(v_i, e_i)`, speeds increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct RestitutionCurve {
    /// Normal impact speeds, m/s, increasing.
    speeds: Vec<f64>,
    /// Restitution at each speed, in (0, 1].
    values: Vec<f64>,
}

impl RestitutionCurve {
    /// A curve through `(speeds[i], values[i])`. The scene loader checks the points
    /// (speeds increasing and positive, values in (0, 1], 1 to [`MAX_POINTS`] of them).
    pub fn new(speeds: Vec<f64>, values: Vec<f64>) -> Self {
        assert!(
            !speeds.is_empty() && speeds.len() == values.len() && speeds.len() <= MAX_POINTS,
            "BUG: restitution curve of {} speeds and {} values",
            speeds.len(),
            values.len()
        );
        RestitutionCurve { speeds, values }
    }

    /// The points, `(speed m/s, e)`.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.speeds.iter().copied().zip(self.values.iter().copied())
    }

    /// Restitution at normal impact speed `v` (m/s): a power law between neighbouring
    /// points, the end points' values beyond them.
    pub fn at(&self, v: f64) -> f64 {
        let n = self.speeds.len();
        if v <= self.speeds[0] {
            return self.values[0];
        }
        if v >= self.speeds[n - 1] {
            return self.values[n - 1];
        }
        let i = self.speeds.partition_point(|&s| s <= v) - 1;
        power_law(
            v,
            (self.speeds[i], self.values[i]),
            (self.speeds[i + 1], self.values[i + 1]),
        )
    }

    /// Smallest and largest restitution on the curve.
    pub fn bounds(&self) -> (f64, f64) {
        let lo = self.values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self
            .values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    }
}

/// The curve CalculiX measures for a rigid 0.8 mm Table 2 steel shot on A5052 with
/// 0.05 mm elements under the impact (`python3 bench/fe_calibrate.py --target-material
/// A5052 --element-size-mm 0.05`, session 48: docs/fe-coupling.md);
/// `examples/a5052_restitution_curve.toml` holds the same points.
pub fn a5052_calculix() -> RestitutionCurve {
    RestitutionCurve::new(
        vec![20.0, 35.0, 50.0, 70.0, 100.0],
        vec![0.342, 0.289, 0.253, 0.222, 0.181],
    )
}

/// The power law `y(v)` through `(v0, y0)` and `(v1, y1)` (all positive, `v0 != v1`):
/// straight in log-log, extended beyond the two points.
pub fn power_law(v: f64, (v0, y0): (f64, f64), (v1, y1): (f64, f64)) -> f64 {
    y0 * (y1 / y0).powf((v / v0).ln() / (v1 / v0).ln())
}

/// Intervals of the damping table (between the curve's smallest and largest `e`).
const INTERVALS: usize = 64;

/// A restitution curve and the Tsuji damping for each `e` on it.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedLaw {
    /// The curve.
    pub curve: RestitutionCurve,
    /// `ln e` at the table's nodes, increasing.
    e: Vec<f64>,
    /// Damping factor at the nodes (decreasing).
    alpha: Vec<f64>,
}

impl SpeedLaw {
    /// The law of `curve`: nodes equally spaced in `ln e` between the curve's smallest and
    /// largest restitution, each node's damping solved by the secant method from its
    /// neighbour's to `1e-13` in `e` (a few dimensionless impacts per node).
    pub fn new(curve: RestitutionCurve) -> Self {
        let (lo, hi) = curve.bounds();
        if hi - lo <= 1e-12 {
            return SpeedLaw {
                e: vec![hi.ln()],
                alpha: vec![damping_for_restitution(hi)],
                curve,
            };
        }
        let mut e = Vec::with_capacity(INTERVALS + 1);
        let mut alpha = Vec::with_capacity(INTERVALS + 1);
        let mut a = damping_for_restitution(hi);
        for j in 0..=INTERVALS {
            let target = hi * (lo / hi).powf(j as f64 / INTERVALS as f64);
            if j > 0 {
                a = secant(target, a);
            }
            e.push(target.ln());
            alpha.push(a);
        }
        e.reverse();
        alpha.reverse();
        SpeedLaw { curve, e, alpha }
    }

    /// Tsuji damping factor of a specimen contact that starts at normal speed `v` (m/s).
    pub fn damping(&self, v: f64) -> f64 {
        self.damping_for(self.curve.at(v))
    }

    /// Tsuji damping factor for restitution `e` (inside the curve's range): cubic
    /// Lagrange interpolation in `ln e` of the table's four nearest nodes.
    pub fn damping_for(&self, e: f64) -> f64 {
        let e = e.ln();
        let n = self.e.len();
        if n == 1 {
            return self.alpha[0];
        }
        let i = self.e.partition_point(|&x| x <= e).clamp(1, n - 1) - 1;
        let j0 = i.saturating_sub(1).min(n - 4);
        let xs = &self.e[j0..j0 + 4];
        let ys = &self.alpha[j0..j0 + 4];
        let mut sum = 0.0;
        for a in 0..4 {
            let mut w = 1.0;
            for b in 0..4 {
                if a != b {
                    w *= (e - xs[b]) / (xs[a] - xs[b]);
                }
            }
            sum += w * ys[a];
        }
        sum
    }
}

/// The damping factor whose impact returns `e`, by the secant method from `a0` (the
/// damping of a nearby `e`); bisection if it does not settle.
fn secant(e: f64, a0: f64) -> f64 {
    let f = |a: f64| restitution_for_damping(a) - e;
    let (mut x0, mut x1) = (a0, a0 * 1.02 + 1e-3);
    let (mut f0, mut f1) = (f(x0), f(x1));
    for _ in 0..30 {
        if f1.abs() < 1e-13 {
            return x1;
        }
        if f1 == f0 {
            break;
        }
        let x2 = (x1 - f1 * (x1 - x0) / (f1 - f0)).max(0.5 * x1);
        (x0, f0) = (x1, f1);
        x1 = x2;
        f1 = f(x1);
    }
    damping_for_restitution(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve() -> RestitutionCurve {
        RestitutionCurve::new(vec![10.0, 40.0, 90.0], vec![0.6, 0.35, 0.25])
    }

    /// The curve passes through its points, is a power law between them (the exponent
    /// of the segment, checked at its geometric middle) and flat beyond its ends.
    #[test]
    fn the_curve_is_a_power_law_between_its_points() {
        let c = curve();
        for (v, e) in c.points() {
            assert!((c.at(v) - e).abs() < 1e-15, "{v}: {}", c.at(v));
        }
        let mid = (10.0f64 * 40.0).sqrt();
        assert!((c.at(mid) - (0.6f64 * 0.35).sqrt()).abs() < 1e-15);
        let p = (0.35f64 / 0.6).ln() / 4f64.ln();
        assert!((c.at(20.0) - 0.6 * 2f64.powf(p)).abs() < 1e-14);
        assert_eq!(c.at(1.0), 0.6);
        assert_eq!(c.at(0.0), 0.6);
        assert_eq!(c.at(500.0), 0.25);
        let one = RestitutionCurve::new(vec![70.0], vec![0.3]);
        assert_eq!(one.at(1.0), 0.3);
        assert_eq!(one.at(700.0), 0.3);
    }

    /// The damping looked up for any `e` of the curve returns that `e` in one
    /// dimensionless Tsuji impact (an independent solve) to 1e-7 (measured: 4e-10 on
    /// `curve()`, 2e-8 on 0.95 to 0.05).
    #[test]
    fn the_table_returns_the_requested_restitution() {
        for c in [
            curve(),
            RestitutionCurve::new(vec![5.0, 100.0], vec![0.95, 0.05]),
            RestitutionCurve::new(vec![5.0, 100.0], vec![1.0, 0.9]),
        ] {
            let law = SpeedLaw::new(c.clone());
            let (lo, hi) = c.bounds();
            let mut worst: f64 = 0.0;
            for k in 0..=60 {
                let e = lo + (hi - lo) * k as f64 / 60.0 * (1.0 - 1e-3 * (k % 7) as f64);
                let back = restitution_for_damping(law.damping_for(e));
                worst = worst.max((back - e).abs());
            }
            assert!(worst < 1e-7, "{c:?}: worst {worst:e}");
        }
        let flat = SpeedLaw::new(RestitutionCurve::new(vec![70.0], vec![0.3]));
        assert_eq!(flat.damping(3.0), damping_for_restitution(0.3));
    }

    /// The example scene's curve is the one the code quotes (docs and validation use it).
    #[test]
    fn the_example_holds_the_measured_curve() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/a5052_restitution_curve.toml"
        );
        let scene = crate::scene::Scene::load(std::path::Path::new(path)).unwrap();
        assert_eq!(
            scene.restitution.shot_specimen_curve,
            Some(a5052_calculix())
        );
    }
}
