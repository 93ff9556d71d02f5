//! Hertz normal contact with Tsuji damping (paper Eqs 19-24 as corrected in model-notes).
//!
//! `F_n = K delta^(3/2) + alpha sqrt(m* K) delta^(1/4) d(delta)/dt`, clamped at zero (no
//! adhesion), with the textbook stiffness `K = (4/3) E* sqrt(R*)`,
//! `1/E* = (1-nu_1^2)/E_1 + (1-nu_2^2)/E_2`. Tsuji et al. (1992) showed that with this
//! dashpot the restitution coefficient depends only on `alpha`: scaling
//! `delta = L xi`, `t = T tau` with `T^(5/2) = m*/(K v^(1/2))`, `L = v T` turns the impact
//! into `xi'' = -max(0, xi^(3/2) + alpha xi^(1/4) xi')`, `xi(0) = 0`, `xi'(0) = 1`,
//! whose rebound speed is `e(alpha)`. [`damping_for_restitution`] solves that
//! dimensionless problem for the `alpha` that gives a requested `e` exactly.

use crate::integrate::dopri::Dopri5;

/// Normal contact law of one material pair: effective modulus and calibrated damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzLaw {
    /// Effective modulus `E*`, Pa.
    pub effective_modulus: f64,
    /// Requested restitution coefficient `e` in (0, 1].
    pub restitution: f64,
    /// Tsuji damping factor `alpha` that yields `restitution` (0 for `e = 1`).
    pub damping: f64,
}

impl HertzLaw {
    /// Law for two materials `(E_1, nu_1)`, `(E_2, nu_2)` (Pa) and restitution `e`.
    pub fn new(e1: f64, nu1: f64, e2: f64, nu2: f64, restitution: f64) -> Self {
        HertzLaw {
            effective_modulus: effective_modulus(e1, nu1, e2, nu2),
            restitution,
            damping: damping_for_restitution(restitution),
        }
    }

    /// Hertz stiffness `K = (4/3) E* sqrt(R*)`, N/m^(3/2), for effective radius `r_eff` (m).
    #[inline]
    pub fn stiffness(&self, r_eff: f64) -> f64 {
        4.0 / 3.0 * self.effective_modulus * r_eff.sqrt()
    }

    /// Normal force (N, >= 0, repulsive) at `overlap` (m, > 0) growing at `overlap_rate`
    /// (m/s) between bodies of effective mass `m_eff` (kg) and stiffness `k` (N/m^1.5).
    #[inline]
    pub fn force(&self, k: f64, m_eff: f64, overlap: f64, overlap_rate: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        let sq = overlap.sqrt();
        let spring = k * overlap * sq;
        let dashpot = self.damping * (m_eff * k).sqrt() * sq.sqrt() * overlap_rate;
        (spring + dashpot).max(0.0)
    }
}

impl HertzLaw {
    /// How far a contact at `overlap` (m) changing at `overlap_rate` (m/s) is from the
    /// instant its force would turn negative (where the clamp at zero puts a kink into
    /// the motion): `delta^(3/2) + alpha sqrt(m*/K) delta^(1/4) d(delta)/dt`, the
    /// unclamped force over `K`, as a length (`g / sqrt(delta)`, about the overlap while
    /// loading, and smooth through its root, so the secant search that locates it
    /// converges fast). Positive while the contact pushes; the integrator ends a step
    /// where it crosses zero, so no step straddles the kink. Once the bodies are apart
    /// it is the (negative) gap: a step that carries a pushing contact past both its kink
    /// and its parting still sees the crossing (it returned 0 there until session 6, and
    /// such steps went unlocated: a rebound error of 2e-4 at tolerance 1e-5).
    #[inline]
    pub fn unloading_margin(&self, k: f64, m_eff: f64, overlap: f64, overlap_rate: f64) -> f64 {
        if overlap <= 0.0 {
            return overlap;
        }
        overlap + self.damping * (m_eff / k).sqrt() * overlap_rate / overlap.sqrt().sqrt()
    }
}

/// `E* = 1 / ((1-nu_1^2)/E_1 + (1-nu_2^2)/E_2)`, Pa.
pub fn effective_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Peak overlap (m) of an undamped Hertz impact at normal speed `v` (m/s):
/// `delta_max = (5 m* v^2 / (4 K))^(2/5)`.
pub fn peak_overlap(m_eff: f64, k: f64, v: f64) -> f64 {
    (5.0 * m_eff * v * v / (4.0 * k)).powf(0.4)
}

/// Duration (s) of an undamped Hertz impact at normal speed `v` (m/s):
/// `t_c = 2.94328 delta_max / v` (the constant is `0.8 B(2/5, 1/2)`).
pub fn contact_time(m_eff: f64, k: f64, v: f64) -> f64 {
    HERTZ_TIME_CONSTANT * peak_overlap(m_eff, k, v) / v
}

/// `2 * integral_0^1 (1 - x^(5/2))^(-1/2) dx = 0.8 B(2/5, 1/2)`.
pub const HERTZ_TIME_CONSTANT: f64 = 2.943_275_184_324_7;

/// Rebound speed ratio of the dimensionless Tsuji impact for damping factor `alpha`.
pub fn restitution_for_damping(alpha: f64) -> f64 {
    if alpha <= 0.0 {
        return 1.0;
    }
    let mut f = |_t: f64, y: &[f64], d: &mut [f64]| {
        d[0] = y[1];
        d[1] = if y[0] > 0.0 {
            let sq = y[0].sqrt();
            -(y[0] * sq + alpha * sq.sqrt() * y[1]).max(0.0)
        } else {
            0.0
        };
    };
    let mut w = Dopri5::new(2);
    let (mut y, mut y_new, mut err) = ([0.0, 1.0], [0.0; 2], [0.0; 2]);
    let (mut t, mut h) = (0.0, 1e-6);
    let tol = 1e-12;
    for _ in 0..1_000_000 {
        w.step(&mut f, t, &y, h, &mut y_new, &mut err);
        let e = err[0].abs().max(err[1].abs()) / tol;
        if e > 1.0 {
            h *= (0.9 * e.powf(-0.2)).max(0.1);
            continue;
        }
        if y_new[0] <= 0.0 {
            // Left the contact during this step. After the force has vanished the
            // motion is uniform, so the speed at the end of a short final step is the
            // rebound speed; shrink until the step lands within 1e-13 of the surface.
            if y_new[0] > -1e-13 {
                return -y_new[1];
            }
            h *= 0.5;
            continue;
        }
        t += h;
        y = y_new;
        w.accept_fsal();
        h *= (0.9 * e.max(1e-10).powf(-0.2)).min(4.0);
    }
    unreachable!("BUG: dimensionless Hertz impact did not end")
}

/// Tsuji damping factor `alpha` for which one collision returns restitution `e` in (0, 1].
pub fn damping_for_restitution(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while restitution_for_damping(hi) > e {
        lo = hi;
        hi *= 2.0;
        if hi > 1e6 {
            break;
        }
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if restitution_for_damping(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-12 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effective_modulus_of_equal_steels() {
        let e = effective_modulus(210e9, 0.3, 210e9, 0.3);
        assert!((e - 210e9 / (2.0 * 0.91)).abs() / e < 1e-12);
    }

    #[test]
    fn calibration_round_trips() {
        for &e in &[0.05, 0.3, 0.7, 0.9, 0.99] {
            let a = damping_for_restitution(e);
            assert!((restitution_for_damping(a) - e).abs() < 1e-9, "e={e} a={a}");
        }
        assert_eq!(damping_for_restitution(1.0), 0.0);
    }

    #[test]
    fn undamped_dimensionless_impact_is_elastic() {
        assert!((restitution_for_damping(1e-12) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn force_is_spring_derivative_of_hertz_potential() {
        // U = (2/5) K delta^(5/2) => F = K delta^(3/2); check by central differences.
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 1.0);
        let k = law.stiffness(0.4e-3);
        let u = |d: f64| 0.4 * k * d.powf(2.5);
        let d = 10e-6;
        let fd = (u(d + 1e-10) - u(d - 1e-10)) / 2e-10;
        assert!((law.force(k, 1e-6, d, 0.0) - fd).abs() / fd < 1e-6);
    }

    #[test]
    fn force_never_attracts() {
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.3);
        let k = law.stiffness(0.4e-3);
        assert_eq!(law.force(k, 1e-6, 1e-9, -100.0), 0.0);
        assert_eq!(law.force(k, 1e-6, -1e-9, 1.0), 0.0);
    }
}
