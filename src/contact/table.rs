//! Binary Hertz-Tsuji impacts in closed form: one dimensionless solution per restitution,
//! tabulated once and scaled to each contact.
//!
//! Two shots in ballistic flight feel the same gravity, so their relative position `r`
//! moves only under the contact force, along `n = r / |r|`: a planar central-force
//! problem. With `rho = |r| = d - delta` (`d` the touching distance), the angular momentum
//! `d w` (`w` the tangential speed at the touch) is conserved, and
//! `delta'' = -F(delta, delta') / m* - (d w)^2 / rho^3`. Scaling as Tsuji et al. do (see
//! [`crate::contact::hertz`]): `delta = L xi`, `t = T tau`, `T^(5/2) = m* / (K u^(1/2))`,
//! `L = u T` (`u` the normal closing speed at the touch) turns it into
//!
//! `xi'' = -max(0, xi^(3/2) + alpha xi^(1/4) xi') - q (1 - eps xi)^-3`,
//! `xi(0) = 0`, `xi'(0) = 1`, with `eps = L / d` and `q = (w / u)^2 eps`,
//!
//! and the normal turns by `theta = (w / u) eps Phi`, `Phi' = (1 - eps xi)^-2`. A shot on
//! the flat specimen is the same equation with `eps = 0` and `q = -g T / u` (gravity
//! presses it into the plane; the motion along the plane is free). The contact is thus
//! one solution of two parameters `(q, eps)` per damping factor `alpha`.
//!
//! [`ContactTable`] holds that solution on a grid of `x = q / (1 + q)` and `eps`, up to the
//! kink (where the unclamped force reaches zero; after it the motion is free and closed
//! form): the kink's time `tau_k` and `(xi, xi', Phi)` at [`SAMPLES`] equal fractions of
//! it, the last one the kink itself. Nodes are solved when first needed (Dormand-Prince
//! at a relative error of 1e-11, kink located on the dense output), so a scene pays only
//! for the part of the plane its contacts visit; a lookup interpolates with cubic
//! Lagrange polynomials in both coordinates. The interpolated values match a direct
//! solution to 2e-7 over the grid (tested below; the largest differences are in grazing
//! contacts, whose overlap is a small part of the motion): a pair's velocities after the
//! contact agree with the integrator's at tolerance 1e-11 to 1e-7 of the impact speed
//! (tested in `events::binary`), far inside the integrator's own error at the
//! tolerances where the table is used ([`FROM_TOLERANCE`]).

use std::sync::OnceLock;

use crate::integrate::dopri::{DenseStep, Dopri5, step_factor};

/// States kept along a contact: at fractions `j / SAMPLES` of the time to the kink,
/// `j = 1..=SAMPLES` (the last is the kink).
pub const SAMPLES: usize = 6;

/// Values per node: `tau_k`, then `(xi, xi', Phi)` per sample.
const VALUES: usize = 1 + 3 * SAMPLES;

/// Grid in `x = asinh(q / Q_SCALE)`: `X0 + i HX`, `i < NX` (`q` from -0.025 to 12). Fine
/// near `q = 0`, where the solution varies fastest (its fourth derivative in `q` is
/// about 1.5e4 there), and of equal relative steps in `q` beyond `Q_SCALE`.
const Q_SCALE: f64 = 0.03;
const X0: f64 = -0.75;
const HX: f64 = 0.05;
const NX: usize = 147;
/// Grid in `eps`: `j HE`, `j < NE`.
const HE: f64 = 0.0125;
const NE: usize = 13;

/// The event scheduler's lean path takes contacts from the table rather than
/// integrating them at integrator tolerances from this one up (the matched setting of
/// the LIGGGHTS benchmark is 1e-4): the table's error (below 1e-7 of the impact speed)
/// is then far below the integrator's own. At tighter tolerances, the default 1e-6
/// among them, every contact is integrated.
pub const FROM_TOLERANCE: f64 = 1e-5;

/// Relative (and absolute, the values being of order one) error of a node's solution.
const NODE_TOLERANCE: f64 = 1e-11;

/// A contact's dimensionless course (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Course {
    /// Dimensionless time of the kink, `tau_k`.
    pub tau_kink: f64,
    /// `(xi, xi', Phi)` at `tau = tau_k j / SAMPLES`, `j = 1..=SAMPLES`.
    pub at: [[f64; 3]; SAMPLES],
}

/// The tabulated impacts of one damping factor (see the module docs).
#[derive(Debug)]
pub struct ContactTable {
    alpha: f64,
    nodes: Vec<OnceLock<Option<[f64; VALUES]>>>,
}

impl ContactTable {
    /// An empty table for the Tsuji damping factor `alpha` (`HertzLaw::damping`).
    pub fn new(alpha: f64) -> Self {
        ContactTable {
            alpha,
            nodes: (0..NX * NE).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The damping factor this table is for.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The course of a contact of parameters `q` and `eps`, interpolated; `None` outside
    /// the grid (`q` from about -0.025 to 9.9, `eps` below 0.1375) or where a node has no
    /// solution.
    pub fn course(&self, q: f64, eps: f64) -> Option<Course> {
        if !(q.is_finite() && eps >= 0.0) {
            return None;
        }
        let (bx, wx) = stencil(((q / Q_SCALE).asinh() - X0) / HX, NX)?;
        let (be, we) = stencil(eps / HE, NE)?;
        let mut v = [0.0; VALUES];
        for (a, &wa) in wx.iter().enumerate() {
            if wa == 0.0 {
                continue;
            }
            for (b, &wb) in we.iter().enumerate() {
                if wb == 0.0 {
                    continue;
                }
                let node = self.node(bx + a, be + b)?;
                let w = wa * wb;
                for (vi, ni) in v.iter_mut().zip(node) {
                    *vi += w * ni;
                }
            }
        }
        let mut at = [[0.0; 3]; SAMPLES];
        for (j, s) in at.iter_mut().enumerate() {
            s.copy_from_slice(&v[1 + 3 * j..4 + 3 * j]);
        }
        Some(Course { tau_kink: v[0], at })
    }

    /// Node `(i, j)`, solved on first use.
    fn node(&self, i: usize, j: usize) -> Option<&[f64; VALUES]> {
        self.nodes[i * NE + j]
            .get_or_init(|| {
                let x = X0 + i as f64 * HX;
                solve(self.alpha, Q_SCALE * x.sinh(), j as f64 * HE)
            })
            .as_ref()
    }
}

/// The first node and the four cubic Lagrange weights for grid coordinate `f` (in node
/// units) on a grid of `n` nodes: the stencil is centred on `f`'s interval, or starts at
/// node 0 in the first interval. `None` outside.
fn stencil(f: f64, n: usize) -> Option<(usize, [f64; 4])> {
    if f.is_nan() || f < 0.0 {
        return None;
    }
    let i = f.floor() as usize;
    let base = i.saturating_sub(1);
    if base + 3 >= n {
        return None;
    }
    let u = f - base as f64;
    let w = [
        -(u - 1.0) * (u - 2.0) * (u - 3.0) / 6.0,
        u * (u - 2.0) * (u - 3.0) / 2.0,
        -u * (u - 1.0) * (u - 3.0) / 2.0,
        u * (u - 1.0) * (u - 2.0) / 6.0,
    ];
    // On a node the other weights are zero exactly (their nodes are then never solved).
    let w = if u == u.round() {
        let mut e = [0.0; 4];
        e[u as usize] = 1.0;
        e
    } else {
        w
    };
    Some((base, w))
}

/// The dimensionless margin to the kink, `xi + alpha xi' / xi^(1/4)` (the unclamped force
/// over `xi^(5/4)`; `xi` itself once apart), as `HertzLaw::unloading_margin`.
fn margin(alpha: f64, y: &[f64]) -> f64 {
    if y[0] <= 0.0 {
        y[0]
    } else {
        y[0] + alpha * y[1] / y[0].sqrt().sqrt()
    }
}

/// Solves one node: `(tau_k, (xi, xi', Phi) at the samples)`, or `None` if the contact
/// does not come to its kink within 50 time units (it cannot, for the grid's range).
fn solve(alpha: f64, q: f64, eps: f64) -> Option<[f64; VALUES]> {
    let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| {
        let xi = y[0];
        let force = if xi > 0.0 {
            let sq = xi.sqrt();
            (xi * sq + alpha * sq.sqrt() * y[1]).max(0.0)
        } else {
            0.0
        };
        let shrink = 1.0 / (1.0 - eps * xi);
        dy[0] = y[1];
        dy[1] = -force - q * shrink * shrink * shrink;
        dy[2] = shrink * shrink;
    };
    // On the stack, so the stage loops unroll (same results as the `Vec` workspace): the
    // pack stream's 611 nodes took 3 % of its instructions with the `Vec`, 1.6 % now.
    let mut w = Dopri5::<[f64; 3]>::fixed();
    let (mut y, mut y_new, mut err) = ([0.0, 1.0, 0.0], [0.0; 3], [0.0; 3]);
    let mut steps: Vec<DenseStep> = Vec::with_capacity(256);
    let (mut t, mut h) = (0.0, 1e-6);
    let mut loaded = false;
    let tau_k = loop {
        if t > 50.0 || steps.len() > 100_000 {
            return None;
        }
        w.step(&mut f, t, &y, h, &mut y_new, &mut err);
        let e = (0..3).fold(0.0f64, |m, k| {
            m.max(err[k].abs() / (NODE_TOLERANCE * (1.0 + y[k].abs())))
        });
        if e.is_nan() || e > 1.0 {
            h *= if e.is_finite() {
                step_factor(e, 0.1, f64::INFINITY)
            } else {
                0.1
            };
            continue;
        }
        let step = w.dense(t, &y, &y_new, h);
        let g1 = margin(alpha, &y_new);
        if loaded && g1 < 0.0 {
            // The kink is inside this step: bisect its dense output.
            let mut probe = [0.0; 3];
            let (mut lo, mut hi) = (t, t + h);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                step.at(mid, &mut probe);
                if margin(alpha, &probe) < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            steps.push(step);
            break 0.5 * (lo + hi);
        }
        loaded |= y_new[0] > 0.0;
        steps.push(step);
        t += h;
        y = y_new;
        w.accept_fsal();
        h *= step_factor(e.max(1e-10), 0.0, 4.0);
    };
    let mut out = [0.0; VALUES];
    out[0] = tau_k;
    let mut k = 0;
    for j in 1..=SAMPLES {
        let tau = tau_k * j as f64 / SAMPLES as f64;
        while k + 1 < steps.len() && steps[k].end() < tau {
            k += 1;
        }
        steps[k].at(tau, &mut out[1 + 3 * (j - 1)..4 + 3 * (j - 1)]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::hertz::{damping_for_restitution, restitution_for_damping};

    /// Normal speed after the kink's free release, for `eps = 0` and `q = 0`: the
    /// rebound speed, which the damping was calibrated to.
    #[test]
    fn head_on_rebounds_with_the_calibrated_restitution() {
        for e in [0.5, 0.7, 0.9] {
            let alpha = damping_for_restitution(e);
            let c = ContactTable::new(alpha).course(0.0, 0.0).unwrap();
            let [xi, rate, _] = c.at[SAMPLES - 1];
            // After the kink no force acts: the overlap closes at constant speed.
            assert!(xi > 0.0 && rate < 0.0);
            let rebound = -rate;
            assert!(
                (rebound - e).abs() < 1e-9,
                "e {e}: {rebound} (direct {})",
                restitution_for_damping(alpha)
            );
        }
    }

    /// Interpolated courses against direct solutions off the nodes.
    #[test]
    fn interpolation_matches_direct_solutions() {
        let alpha = damping_for_restitution(0.9);
        let table = ContactTable::new(alpha);
        // Worst relative differences: the kink's time and the turn `Phi` (against
        // `tau_k`), the overlap (against its peak) and its rate (against 1).
        let (mut time, mut state) = (0.0f64, 0.0f64);
        for &q in &[-0.0173, -0.003, 0.00071, 0.0421, 0.337, 1.93, 7.7, 9.6] {
            for &eps in &[0.0, 0.0031, 0.0187, 0.0466, 0.091, 0.117] {
                let c = table.course(q, eps).unwrap();
                let d = solve(alpha, q, eps).unwrap();
                let peak = (0..SAMPLES).fold(0.0f64, |m, j| m.max(d[1 + 3 * j]));
                time = time.max((c.tau_kink - d[0]).abs() / d[0]);
                for j in 0..SAMPLES {
                    let x = &d[1 + 3 * j..4 + 3 * j];
                    state = state
                        .max((c.at[j][0] - x[0]).abs() / peak)
                        .max((c.at[j][1] - x[1]).abs());
                    time = time.max((c.at[j][2] - x[2]).abs() / d[0]);
                }
            }
        }
        // Measured: 1.5e-7 and 1.5e-7, both at the largest `q` (a grazing contact, whose
        // overlap and its rate are a small part of the motion).
        assert!(
            time < 2e-7 && state < 2e-7,
            "time {time:e}, state {state:e}"
        );
    }

    #[test]
    fn outside_the_grid_is_refused() {
        let table = ContactTable::new(0.1);
        assert!(table.course(-0.05, 0.0).is_none());
        assert!(table.course(25.0, 0.01).is_none());
        assert!(table.course(0.1, 0.2).is_none());
        assert!(table.course(f64::NAN, 0.0).is_none());
    }
}
