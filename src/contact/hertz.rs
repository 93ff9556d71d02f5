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

use crate::integrate::dopri::{Dopri5, TOUCH_MISS};

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

    /// The same law with Tsuji damping factor `damping` (a contact whose restitution
    /// depends on its impact speed, [`crate::contact::restitution`]).
    #[inline]
    pub fn with_damping(&self, damping: f64) -> Self {
        HertzLaw {
            restitution: f64::NAN,
            damping,
            ..*self
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
        self.force_unclamped(k, m_eff, overlap, overlap_rate)
            .max(0.0)
    }

    /// [`HertzLaw::force`] without the clamp at zero (negative past the kink, still zero
    /// once apart): for a step that starts with the contact pushing and is cut at its
    /// kink, so that its stages see a smooth force.
    #[inline]
    pub fn force_unclamped(&self, k: f64, m_eff: f64, overlap: f64, overlap_rate: f64) -> f64 {
        self.force_unclamped_with(k, (m_eff * k).sqrt(), overlap, overlap_rate)
    }

    /// [`HertzLaw::force`] with `root_mk = sqrt(m_eff k)` given: the same number, for a
    /// caller that keeps it for a pair of bodies.
    #[inline]
    pub fn force_with(&self, k: f64, root_mk: f64, overlap: f64, overlap_rate: f64) -> f64 {
        self.force_unclamped_with(k, root_mk, overlap, overlap_rate)
            .max(0.0)
    }

    /// [`HertzLaw::force_unclamped`] with `root_mk = sqrt(m_eff k)` given.
    #[inline]
    pub fn force_unclamped_with(
        &self,
        k: f64,
        root_mk: f64,
        overlap: f64,
        overlap_rate: f64,
    ) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        let sq = overlap.sqrt();
        let spring = k * overlap * sq;
        let dashpot = self.damping * root_mk * sq.sqrt() * overlap_rate;
        spring + dashpot
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

impl HertzLaw {
    /// A bound on the rate (N/s) at which the force falls through its kink, for a
    /// contact now at `overlap` (m) changing at `overlap_rate` (m/s): what a step that
    /// runs over the kink without stopping there misses (`dopri::KINK_MISS`) scales
    /// with it.
    ///
    /// At the kink the unclamped force is zero, `K delta^(3/2) = -c delta^(1/4) delta'`
    /// (`c = alpha sqrt(m* K)`), so its slope `(3/2) K delta^(1/2) delta' + c ((1/4)
    /// delta^(-3/4) delta'^2 + delta^(1/4) delta'')` is `(5/4) K delta^(1/2) |delta'|`
    /// plus `c delta^(1/4) delta''`, where `delta''` comes from the other forces only
    /// (the contact's own is zero there; left out: a bed's weights and the air change it
    /// little over a step). The kink's state is bounded by the contact's energy now,
    /// `E = m* delta'^2 / 2 + (2/5) K delta^(5/2)`, which the dashpot only lowers:
    /// `delta delta'^2 = delta (2 / m*) (E - (2/5) K delta^(5/2))` is largest at
    /// `delta^(5/2) = E / (7/5 K)`, where it is `(10/7) delta E / m*`.
    pub fn kink_slope(k: f64, m_eff: f64, overlap: f64, overlap_rate: f64) -> f64 {
        let d = overlap.max(0.0);
        let energy = 0.5 * m_eff * overlap_rate * overlap_rate + 0.4 * k * d * d * d.sqrt();
        let d_star = (energy / (1.4 * k)).powf(0.4);
        1.25 * k * (10.0 / 7.0 * d_star * energy / m_eff).sqrt()
    }

    /// The longest step (s) that a touch at closing speed `v0` (m/s) may fall in, or
    /// start less than a step before, while the step misses at most `dv` (m/s) of the
    /// relative velocity from the force's start `c1 s^(1/4) + c2 s^(3/2)`
    /// ([`HertzLaw::onset_terms`]): by `dopri::TOUCH_MISS`, at most
    /// `(a u + b u^2) / m*` with `u = h^(5/4)`, `a = T_1 |c1|`, `b = T_2 |c2|`, whose
    /// root `u = 2 m* dv / (a + sqrt(a^2 + 4 b m* dv))` gives the step.
    pub fn touch_span(&self, k: f64, m_eff: f64, v0: f64, dv: f64) -> f64 {
        let (c1, c2) = self.onset_terms(k, m_eff, v0.max(0.0));
        let (a, b) = (TOUCH_MISS[0] * c1.abs(), TOUCH_MISS[1] * c2.abs());
        let w = dv * m_eff;
        let den = a + (a * a + 4.0 * b * w).sqrt();
        if den <= 0.0 {
            return f64::INFINITY;
        }
        (2.0 * w / den).powf(0.8)
    }
}

impl HertzLaw {
    /// What a Dormand-Prince step of `h` (s) that starts `a` (s) after the touch of an
    /// impact at normal speed `v0` (m/s) misses of the contact force, as the pair of
    /// integrals `(position, velocity)`: `(int (t1 - s) F ds, int F ds)` over the step
    /// (ending at `t1`) minus the step's quadratures of them (N s^2, N s). Added to the
    /// step's result (divided by the masses, along the normal), they make the step exact
    /// up to the force's smoother part.
    ///
    /// At a touch the force has no Taylor series in time: its start is
    /// `F = c1 s^(1/4) + c2 s^(3/2) + ...` with `c1 = alpha sqrt(m* K) v0^(5/4)` (the
    /// dashpot) and `c2 = K v0^(3/2) (1 - 8 alpha^2 / 9)` (the spring, less the
    /// dashpot's own slowing: Tsuji's `xi = tau - (16 alpha / 45) tau^(9/4) + ...`).
    /// A step from the touch integrates `s^(1/4)` 4 % short and its error estimate sees
    /// 0.06 % of that; the next step, four times longer, is 0.02 % short. Without this a
    /// step from the touch must be about 1 % of a contact step long to be accurate.
    pub fn onset_correction(&self, k: f64, m_eff: f64, v0: f64, a: f64, h: f64) -> (f64, f64) {
        if v0 <= 0.0 || h <= 0.0 {
            return (0.0, 0.0);
        }
        start_correction(self.onset_terms(k, m_eff, v0), a, h)
    }

    /// The coefficients `(c1, c2)` of the force's start `F = c1 s^(1/4) + c2 s^(3/2)`
    /// at an impact of normal speed `v0` (see [`HertzLaw::onset_correction`]).
    pub fn onset_terms(&self, k: f64, m_eff: f64, v0: f64) -> (f64, f64) {
        let al = self.damping;
        (
            al * (m_eff * k).sqrt() * v0 * v0.sqrt().sqrt(),
            k * v0 * v0.sqrt() * (1.0 - 8.0 / 9.0 * al * al),
        )
    }
}

/// What a Dormand-Prince step of `h` (s), starting `a` (s) after a touch, misses of a
/// force `c1 s^(1/4) + c2 s^(3/2)` (`s` the time since the touch): `(position,
/// velocity)` integrals, exact minus the step's quadrature (see
/// [`HertzLaw::onset_correction`]; the sliding friction of a touch starts the same way).
pub fn start_correction((c1, c2): (f64, f64), a: f64, h: f64) -> (f64, f64) {
    if h <= 0.0 {
        return (0.0, 0.0);
    }
    let r = a.max(0.0) / h;
    let quad = crate::integrate::dopri::start_quadrature(r);
    // s^(p+1) and s^(p+2) at both ends of [r, r + 1], for p = 1/4 and 3/2.
    let powers = |s: f64| {
        let sq = s.sqrt();
        let p1 = [s * sq.sqrt(), s * s * sq];
        [p1, [p1[0] * s, p1[1] * s]]
    };
    let (r1, lo, hi) = (r + 1.0, powers(r), powers(r + 1.0));
    let hq = h.sqrt();
    let scale = [h * hq.sqrt(), h * h * hq];
    let (mut dx, mut dv) = (0.0, 0.0);
    for (q, (c, p)) in [(c1, 0.25), (c2, 1.5)].into_iter().enumerate() {
        let (p1, p2) = (p + 1.0, p + 2.0);
        // Exact integrals over [r, r + 1] of s^p and of (r + 1 - s) s^p.
        let iv = (hi[0][q] - lo[0][q]) / p1;
        let ix = r1 * iv - (hi[1][q] - lo[1][q]) / p2;
        let (qv, qx) = quad[q];
        dv += c * scale[q] * (iv - qv);
        dx += c * scale[q] * h * (ix - qx);
    }
    (dx, dv)
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

/// The normal speed (m/s) of the impact whose [`contact_time`] is `tc` (s).
pub fn impact_speed(m_eff: f64, k: f64, tc: f64) -> f64 {
    // t_c = HERTZ_TIME_CONSTANT (5 m* / (4 K))^(2/5) v^(-1/5).
    (HERTZ_TIME_CONSTANT * (1.25 * m_eff / k).powf(0.4) / tc).powi(5)
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
    let mut w = Dopri5::<[f64; 2]>::fixed();
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

    /// The dimensionless Tsuji impact (`K = m* = v0 = 1`, restitution 0.7) from the touch
    /// to `t`, converged: in the quartic time `u = (t' / t)^(1/4)`, where its start is
    /// smooth, in 4,000 steps.
    fn converged_start(law: &HertzLaw, t: f64) -> [f64; 2] {
        let mut g = |u: f64, y: &[f64], d: &mut [f64]| {
            let f = law.force(1.0, 1.0, y[0], y[1]);
            let s = 4.0 * t * u * u * u;
            d[0] = s * y[1];
            d[1] = -s * f;
        };
        let mut w = Dopri5::new(2);
        let (mut y, mut y1, mut e) = ([0.0, 1.0], [0.0; 2], [0.0; 2]);
        let n = 4000;
        for i in 0..n {
            w.step(
                &mut g,
                i as f64 / n as f64,
                &y,
                1.0 / n as f64,
                &mut y1,
                &mut e,
            );
            y = y1;
            w.accept_fsal();
        }
        y
    }

    /// One Dormand-Prince step from `(a, y)` of `h` on the dimensionless impact, with
    /// and without the onset correction: the errors (position, velocity) of each against
    /// the converged course.
    fn step_errors(law: &HertzLaw, a: f64, h: f64) -> ([f64; 2], [f64; 2]) {
        let y0 = if a > 0.0 {
            converged_start(law, a)
        } else {
            [0.0, 1.0]
        };
        let exact = converged_start(law, a + h);
        let mut f = |_t: f64, y: &[f64], d: &mut [f64]| {
            d[0] = y[1];
            d[1] = -law.force(1.0, 1.0, y[0], y[1]);
        };
        let mut w = Dopri5::new(2);
        let (mut y1, mut e) = ([0.0; 2], [0.0; 2]);
        w.step(&mut f, a, &y0, h, &mut y1, &mut e);
        // The force pushes against the overlap's growth.
        let (dx, dv) = law.onset_correction(1.0, 1.0, 1.0, a, h);
        let plain = [(y1[0] - exact[0]).abs(), (y1[1] - exact[1]).abs()];
        let fixed = [(y1[0] - dx - exact[0]).abs(), (y1[1] - dv - exact[1]).abs()];
        (plain, fixed)
    }

    #[test]
    fn a_step_from_the_touch_is_corrected_for_the_forces_start() {
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.7);
        let tc = contact_time(1.0, 1.0, 1.0);
        // The first step from the touch (2 % of the contact): the velocity's error falls
        // from 3.0e-4 to 3.1e-6 of the impact speed, the position's from 2.0e-5 to 9.4e-8
        // of the impact speed times the time unit (measured).
        let (plain, fixed) = step_errors(&law, 0.0, 0.02 * tc);
        assert!(plain[1] > 1e-4, "{plain:?}");
        assert!(fixed[1] < plain[1] / 50.0, "{fixed:?} {plain:?}");
        assert!(fixed[0] < plain[0] / 50.0, "{fixed:?} {plain:?}");
        // The next, four times longer, from where the first ended: 6.4e-6 -> 8.0e-7 and
        // 2.4e-6 -> 2.1e-7.
        let (plain, fixed) = step_errors(&law, 0.02 * tc, 0.08 * tc);
        assert!(fixed[1] < plain[1] / 5.0, "{fixed:?} {plain:?}");
        assert!(fixed[0] < plain[0] / 5.0, "{fixed:?} {plain:?}");
        // Far from the touch the force is smooth and the correction vanishes.
        let (dx, dv) = law.onset_correction(1.0, 1.0, 1.0, 0.5 * tc, 0.01 * tc);
        assert!(dx.abs() < 1e-12 && dv.abs() < 1e-12, "{dx} {dv}");
    }

    #[test]
    fn a_step_over_a_touch_within_its_span_misses_less_than_asked() {
        // The dimensionless impact (`K = m* = v0 = 1`); the touch inside the step, at
        // its start, or a little before it: one plain step against the converged course.
        for e in [0.3, 0.7, 0.9, 1.0] {
            let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, e);
            let mut f = |_t: f64, y: &[f64], d: &mut [f64]| {
                d[0] = y[1];
                d[1] = -law.force(1.0, 1.0, y[0], y[1]);
            };
            for dv in [1e-4, 1e-6] {
                let h = law.touch_span(1.0, 1.0, 1.0, dv);
                let mut worst: f64 = 0.0;
                for theta in [-0.5, -0.1, 0.0, 0.3, 0.7, 0.95] {
                    // theta < 0: the touch `-theta h` into the step; else before it.
                    let (y0, end) = if theta < 0.0 {
                        ([theta * h, 1.0], (1.0 + theta) * h)
                    } else {
                        let y0 = if theta > 0.0 {
                            converged_start(&law, theta * h)
                        } else {
                            [0.0, 1.0]
                        };
                        (y0, (1.0 + theta) * h)
                    };
                    let exact = converged_start(&law, end);
                    let mut w = Dopri5::new(2);
                    let (mut y1, mut err) = ([0.0; 2], [0.0; 2]);
                    w.step(&mut f, 0.0, &y0, h, &mut y1, &mut err);
                    worst = worst.max((y1[1] - exact[1]).abs());
                }
                // Measured: 0.15-0.5 of what was asked.
                assert!(worst <= dv, "e {e}, dv {dv}: missed {worst} in {h}");
                assert!(
                    worst > 0.05 * dv,
                    "e {e}, dv {dv}: {worst}, the span is too short"
                );
            }
        }
    }

    #[test]
    fn the_kink_slope_bounds_the_force_where_it_turns() {
        // The dimensionless impact, stepped finely in its quartic time, then on in plain
        // time until the unclamped force turns negative; its slope there against the
        // bound from the states before.
        for e in [0.3, 0.7, 0.9] {
            let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, e);
            let tc = contact_time(1.0, 1.0, 1.0);
            let mut f = |_t: f64, y: &[f64], d: &mut [f64]| {
                d[0] = y[1];
                d[1] = -law.force_unclamped(1.0, 1.0, y[0], y[1]);
            };
            let h = 1e-4 * tc;
            let mut y = converged_start(&law, 0.05 * tc);
            let mut states = vec![y];
            let mut w = Dopri5::new(2);
            let (mut y1, mut err) = ([0.0; 2], [0.0; 2]);
            let force = |y: &[f64; 2]| law.force_unclamped(1.0, 1.0, y[0], y[1]);
            let slope = loop {
                w.step(&mut f, 0.0, &y, h, &mut y1, &mut err);
                if force(&y1) < 0.0 {
                    break (force(&y) - force(&y1)) / h;
                }
                y = y1;
                states.push(y);
            };
            let bounds: Vec<f64> = states
                .iter()
                .map(|s| HertzLaw::kink_slope(1.0, 1.0, s[0], s[1]))
                .collect();
            let least = bounds.iter().cloned().fold(f64::INFINITY, f64::min);
            assert!(
                least >= slope,
                "e {e}: bound {least} below the slope {slope}"
            );
            // Not far above it at the kink itself (the energy left there): measured 1.23,
            // 1.48 and 2.33 times the slope for the three restitutions.
            let last = bounds[bounds.len() - 1];
            assert!(last <= 3.0 * slope, "e {e}: bound {last} against {slope}");
        }
    }

    #[test]
    fn the_start_quadratures_are_the_tableaus() {
        // Against the generic power, from the touch and later.
        for r in [0.0, 0.25, 3.0] {
            let q = crate::integrate::dopri::start_quadrature(r);
            for (k, p) in [0.25, 1.5].into_iter().enumerate() {
                let mut w = Dopri5::new(2);
                // One step of y'' = (r + t)^p from rest: velocity and position are the
                // velocity's and the position's quadratures.
                let mut f = |t: f64, y: &[f64], d: &mut [f64]| {
                    d[0] = y[1];
                    d[1] = (r + t).powf(p);
                };
                let mut y1 = [0.0; 2];
                let mut e2 = [0.0; 2];
                w.step(&mut f, 0.0, &[0.0, 0.0], 1.0, &mut y1, &mut e2);
                assert!((q[k].0 - y1[1]).abs() < 1e-14, "{r} {p}: {:?} {y1:?}", q[k]);
                assert!((q[k].1 - y1[0]).abs() < 1e-14, "{r} {p}: {:?} {y1:?}", q[k]);
            }
        }
    }

    #[test]
    fn force_never_attracts() {
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.3);
        let k = law.stiffness(0.4e-3);
        assert_eq!(law.force(k, 1e-6, 1e-9, -100.0), 0.0);
        assert_eq!(law.force(k, 1e-6, -1e-9, 1.0), 0.0);
    }
}
