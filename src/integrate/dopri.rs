//! Dormand-Prince 5(4) Runge-Kutta step on a flat `f64` state (Dormand & Prince 1980;
//! Hairer, Norsett & Wanner, Solving ODEs I, Table 5.2). Fifth-order solution, embedded
//! fourth-order error estimate, first-same-as-last. The workspace is allocated once and
//! reused, so a step allocates nothing.

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// Fifth-order weights minus fourth-order weights.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Dense-output weights (Hairer's `contd5`; `D[1]` is zero).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// The step-size controller's factor for a step of error norm `e` (1 at the
/// tolerance): `0.9 e^(-1/5)` clamped to `[min, max]`; `max` for `e = 0`, `min` for an
/// infinite or NaN `e`. The fifth root comes from a bit-level first guess and four
/// Newton steps (relative error below 1e-9): `powf` was 2 % of the pack stream's
/// instructions, called once or twice per step.
pub fn step_factor(e: f64, min: f64, max: f64) -> f64 {
    if e.is_nan() || e == f64::INFINITY {
        return min;
    }
    // 0.9 e^(-1/5) >= max <=> e <= (0.9 / max)^5, and the same for min.
    let r = 0.9 / max;
    if e <= r * r * r * r * r {
        return max;
    }
    let r = 0.9 / min;
    if e >= r * r * r * r * r {
        return min;
    }
    0.9 * inv_fifth_root(e)
}

/// `x^(-1/5)` for a normal `x > 0`: `bits(y) ~ 1.2 bits(1) - 0.2 bits(x)` (the exponent
/// field read as a logarithm), then Newton on `x y^5 = 1`, which converges from below
/// and above alike (`y <- y (6 - x y^5) / 5`).
fn inv_fifth_root(x: f64) -> f64 {
    const ONE: f64 = 4_607_182_418_800_017_408.0; // 1.0f64.to_bits()
    let mut y = f64::from_bits((1.2 * ONE - 0.2 * x.to_bits() as f64) as u64);
    for _ in 0..4 {
        let y2 = y * y;
        y *= (6.0 - x * y2 * y2 * y) * 0.2;
    }
    y
}

/// What a step of length `h` can miss of a force that turns from smooth to zero
/// inside it at slope `F'` (a contact's kink, when the step is not cut there): the
/// fifth-order solution's quadrature of the ramp `(s - theta)_+` against its exact
/// integral, at worst over the kink's place `theta` in the step, is
/// `KINK_MISS[0] h^2` for the velocity and `KINK_MISS[1] h^3` for the position (times
/// `F' / m`). Measured by the test below: 0.022465 and 0.013156.
pub const KINK_MISS: [f64; 2] = [0.0225, 0.0132];

/// The same for the forces `s^(1/4)` and `s^(3/2)` that start a Hertz contact (`s`
/// from the touch), the touch anywhere inside the step or before its start (see
/// [`start_quadrature`]): at worst `TOUCH_MISS[0] h^(5/4)` and `TOUCH_MISS[1] h^(5/2)`
/// of the velocity (times the force's coefficient over the mass). Measured by the test
/// below: 0.19545 and 0.0055993, both with the touch inside the step.
pub const TOUCH_MISS: [f64; 2] = [0.196, 0.0056];

/// How a step's fifth-order solution integrates the forces `s^(1/4)` and `s^(3/2)`
/// that start a Hertz contact (`s` measured from a touch `r` step lengths before the
/// step's start; steps of length 1): for each, the velocity's quadrature
/// `sum_i b_i (r + c_i)^p` and the position's `sum_j (sum_i b_i a_ij) (r + c_j)^p`. The
/// contact law compares them with the exact integrals to correct the steps that follow
/// a touch, where the force is not smooth.
pub fn start_quadrature(r: f64) -> [(f64, f64); 2] {
    // sum_i b_i a_ij: the position's weights of the stages.
    const BB: [f64; 6] = {
        let b = &A[6];
        let mut bb = [0.0; 6];
        let mut j = 0;
        while j < 6 {
            let mut i = j + 1;
            while i < 6 {
                bb[j] += b[i] * A[i][j];
                i += 1;
            }
            j += 1;
        }
        bb
    };
    let b = &A[6];
    let mut q = [(0.0, 0.0); 2];
    for j in 0..6 {
        let s = r + C[j];
        let sq = s.sqrt();
        for (k, sp) in [sq.sqrt(), s * sq].into_iter().enumerate() {
            q[k].0 += b[j] * sp;
            q[k].1 += BB[j] * sp;
        }
    }
    q
}

/// One accepted step `[t0, t0 + h]` with its dense output: the state at any time inside.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DenseStep {
    /// Start of the step, s.
    pub t0: f64,
    /// Step size, s.
    pub h: f64,
    rc: Vec<f64>,
}

impl DenseStep {
    /// End of the step, s.
    pub fn end(&self) -> f64 {
        self.t0 + self.h
    }

    /// Length of the state.
    pub fn len(&self) -> usize {
        self.rc.len() / 5
    }

    /// Whether the state is empty.
    pub fn is_empty(&self) -> bool {
        self.rc.is_empty()
    }

    /// The state at `t` in `[t0, t0 + h]` (the step's end exactly at `t0 + h`).
    pub fn at(&self, t: f64, y: &mut [f64]) {
        let n = y.len();
        debug_assert_eq!(self.rc.len(), 5 * n);
        if t >= self.end() {
            for (i, yi) in y.iter_mut().enumerate() {
                *yi = self.rc[i] + self.rc[n + i];
            }
            return;
        }
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        let rc = &self.rc;
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = rc[i]
                + th * (rc[n + i]
                    + th1 * (rc[2 * n + i] + th * (rc[3 * n + i] + th1 * rc[4 * n + i])));
        }
    }

    /// How far the three components `k..k + 3` of the dense output depart over
    /// `[ta, tb]` (inside the step) from their chord there, the straight line through
    /// their values at `ta` and `tb` taken at the same fraction of the time. The output
    /// is `rc0 + th rc1 + th (1 - th) rc2 + th^2 (1 - th) rc3 + th^2 (1 - th)^2 rc4`,
    /// whose second derivative in `th` is at most `2 |rc2| + 4 |rc3| + 2 |rc4|` over
    /// the step; a curve departs from its chord over `[th_a, th_b]` by at most
    /// `(th_b - th_a)^2 / 8` times that.
    pub fn bend(&self, ta: f64, tb: f64, k: usize) -> f64 {
        let n = self.len();
        let span = ((tb - ta) / self.h).clamp(0.0, 1.0);
        let rc = &self.rc;
        let curv2: f64 = (k..k + 3)
            .map(|i| {
                let c = 2.0 * rc[2 * n + i].abs()
                    + 4.0 * rc[3 * n + i].abs()
                    + 2.0 * rc[4 * n + i].abs();
                c * c
            })
            .sum();
        0.125 * span * span * curv2.sqrt()
    }
}

/// Reusable stage storage for a state of fixed length: `Vec`s sized at run time (the
/// island's states), or arrays on the stack (`Dopri5<[f64; N]>`, the lean path's 6-,
/// 9- and 12-value states, where the stage loops unroll). Both run the same code in the
/// same order, so their results are identical.
#[derive(Debug, Clone)]
pub struct Dopri5<K = Vec<f64>> {
    k: [K; 7],
    stage: K,
    /// Whether `k[0]` holds `f(t, y)` for the current start point.
    pub first_stage_valid: bool,
}

impl Dopri5 {
    /// Workspace for states of length `n`.
    pub fn new(n: usize) -> Self {
        Dopri5 {
            k: std::array::from_fn(|_| vec![0.0; n]),
            stage: vec![0.0; n],
            first_stage_valid: false,
        }
    }

    /// Resizes for a state of length `n` and invalidates the first stage.
    pub fn resize(&mut self, n: usize) {
        for k in &mut self.k {
            k.resize(n, 0.0);
        }
        self.stage.resize(n, 0.0);
        self.first_stage_valid = false;
    }
}

impl<const N: usize> Dopri5<[f64; N]> {
    /// Workspace on the stack for states of length `N`.
    pub fn fixed() -> Self {
        Dopri5 {
            k: [[0.0; N]; 7],
            stage: [0.0; N],
            first_stage_valid: false,
        }
    }
}

impl<K: AsRef<[f64]> + AsMut<[f64]>> Dopri5<K> {
    /// One trial step of size `h` from `(t, y)`: writes the fifth-order solution to
    /// `y_new` and the error estimate (fifth minus fourth order) to `err`. Returns the
    /// number of right-hand-side evaluations made (6, or 7 when the first stage was stale).
    pub fn step<F>(
        &mut self,
        f: &mut F,
        t: f64,
        y: &[f64],
        h: f64,
        y_new: &mut [f64],
        err: &mut [f64],
    ) -> u32
    where
        F: FnMut(f64, &[f64], &mut [f64]),
    {
        let mut evals = 0;
        if !self.first_stage_valid {
            f(t, y, self.k[0].as_mut());
            self.first_stage_valid = true;
            evals += 1;
        }
        // The workspace's length: a constant for arrays, so their loops unroll.
        let n = self.stage.as_ref().len();
        debug_assert_eq!(
            y.len(),
            n,
            "BUG: a state of another length than the workspace"
        );
        let y = &y[..n];
        // Stage sums unrolled per stage over slices of one length (no bounds checks in
        // the loops); the additions run in the scalar form's order: identical results.
        macro_rules! stage {
            ($s:literal: $($j:literal),+) => {{
                {
                    let k = &self.k;
                    let ks: [&[f64]; $s] = [$(&k[$j].as_ref()[..n]),+];
                    let st = &mut self.stage.as_mut()[..n];
                    let a = &A[$s];
                    for i in 0..n {
                        let acc = 0.0 $(+ a[$j] * ks[$j][i])+;
                        st[i] = y[i] + h * acc;
                    }
                }
                let (_, rest) = self.k.split_at_mut($s);
                f(t + C[$s] * h, self.stage.as_ref(), rest[0].as_mut());
                evals += 1;
            }};
        }
        stage!(1: 0);
        stage!(2: 0, 1);
        stage!(3: 0, 1, 2);
        stage!(4: 0, 1, 2, 3);
        stage!(5: 0, 1, 2, 3, 4);
        stage!(6: 0, 1, 2, 3, 4, 5);
        y_new.copy_from_slice(self.stage.as_ref());
        let k: [&[f64]; 7] = std::array::from_fn(|j| &self.k[j].as_ref()[..n]);
        for (i, ei) in err[..n].iter_mut().enumerate() {
            let e = 0.0
                + E[0] * k[0][i]
                + E[1] * k[1][i]
                + E[2] * k[2][i]
                + E[3] * k[3][i]
                + E[4] * k[4][i]
                + E[5] * k[5][i]
                + E[6] * k[6][i];
            *ei = h * e;
        }
        evals
    }

    /// Dense output of the step just taken from `y0` to `y1` (size `h`; call before
    /// [`Dopri5::accept_fsal`]): the fourth-order continuous extension of Dormand &
    /// Prince (Hairer, Norsett & Wanner, Solving ODEs I, II.6), whose error is of the
    /// order of the step's own.
    pub fn dense(&self, t0: f64, y0: &[f64], y1: &[f64], h: f64) -> DenseStep {
        let mut out = DenseStep::default();
        self.dense_into(t0, y0, y1, h, &mut out);
        out
    }

    /// [`Dopri5::dense`] into `out`, reusing its storage (event location: nothing is
    /// allocated per located event).
    pub fn dense_into(&self, t0: f64, y0: &[f64], y1: &[f64], h: f64, out: &mut DenseStep) {
        let n = y0.len();
        out.t0 = t0;
        out.h = h;
        let rc = &mut out.rc;
        rc.clear();
        rc.resize(5 * n, 0.0);
        let k: [&[f64]; 7] = std::array::from_fn(|j| self.k[j].as_ref());
        for i in 0..n {
            let r2 = y1[i] - y0[i];
            let r3 = h * k[0][i] - r2;
            rc[i] = y0[i];
            rc[n + i] = r2;
            rc[2 * n + i] = r3;
            rc[3 * n + i] = r2 - h * k[6][i] - r3;
            rc[4 * n + i] = h
                * (D[0] * k[0][i]
                    + D[2] * k[2][i]
                    + D[3] * k[3][i]
                    + D[4] * k[4][i]
                    + D[5] * k[5][i]
                    + D[6] * k[6][i]);
        }
    }

    /// After accepting a step: the last stage becomes the next step's first stage.
    pub fn accept_fsal(&mut self) {
        self.k.swap(0, 6);
        self.first_stage_valid = true;
    }

    /// Invalidates the stored first stage (the right-hand side changed discontinuously).
    pub fn invalidate(&mut self) {
        self.first_stage_valid = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_factor_is_the_fifth_root_clamped() {
        // Against powf over the range where it is not clamped, and at the clamps.
        let mut worst = 0.0f64;
        for k in 0..=4000 {
            let e = 10f64.powf(-4.0 + 8.0 * k as f64 / 4000.0);
            let want = (0.9 * e.powf(-0.2)).clamp(0.2, 5.0);
            let got = step_factor(e, 0.2, 5.0);
            worst = worst.max((got / want - 1.0).abs());
        }
        assert!(worst < 1e-9, "worst relative error {worst:.2e}");
        assert_eq!(step_factor(0.0, 0.2, 5.0), 5.0);
        assert_eq!(step_factor(f64::INFINITY, 0.2, 5.0), 0.2);
        assert_eq!(step_factor(f64::NAN, 0.25, 5.0), 0.25);
        assert_eq!(step_factor(1e300, 0.1, f64::INFINITY), 0.1);
        let e = 3.7e-30;
        assert!((step_factor(e, 0.1, f64::INFINITY) / (0.9 * e.powf(-0.2)) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn fifth_order_on_exponential_and_error_estimate_is_small() {
        // y' = -y, y(0) = 1: one step of 0.1 is accurate to ~h^6.
        let mut w = Dopri5::new(1);
        let mut f = |_t: f64, y: &[f64], d: &mut [f64]| d[0] = -y[0];
        let (mut y1, mut e) = ([0.0], [0.0]);
        w.step(&mut f, 0.0, &[1.0], 0.1, &mut y1, &mut e);
        assert!((y1[0] - (-0.1f64).exp()).abs() < 1e-8);
        assert!(e[0].abs() < 1e-6);
    }

    #[test]
    fn dense_output_is_fourth_order_inside_the_step() {
        // y' = -y: the interpolant's error at mid-step falls as h^5 (local, 4th order).
        let mut f = |_t: f64, y: &[f64], d: &mut [f64]| d[0] = -y[0];
        let mut err = |h: f64| {
            let mut w = Dopri5::new(1);
            let (mut y1, mut e) = ([0.0], [0.0]);
            w.step(&mut f, 0.0, &[1.0], h, &mut y1, &mut e);
            let d = w.dense(0.0, &[1.0], &y1, h);
            let mut y = [0.0];
            d.at(0.5 * h, &mut y);
            let mut end = [0.0];
            d.at(h, &mut end);
            assert_eq!(end, y1, "the dense output ends on the step's own end");
            (y[0] - (-0.5 * h).exp()).abs()
        };
        let (e1, e2) = (err(0.2), err(0.1));
        assert!(e1 < 1e-6, "{e1}");
        let order = (e1 / e2).log2();
        assert!(order > 4.5, "observed order {order}");
    }

    #[test]
    fn the_output_departs_from_its_chord_by_at_most_its_bend() {
        // A shot turning on a circle (x'' = -w^2 x in the plane, drifting along z) over a
        // quarter turn in one step: on each part of the step, every sampled point of the
        // output (positions and velocities) lies within the bend of the chord's point at
        // the same time, and the bend is not much larger than the largest departure.
        let w2 = 4.0;
        let mut f = |_t: f64, y: &[f64], d: &mut [f64]| {
            d[..3].copy_from_slice(&y[3..6]);
            d[3] = -w2 * y[0];
            d[4] = -w2 * y[1];
            d[5] = 0.0;
        };
        let y0 = [1.0, 0.0, 0.5, 0.0, 2.0, 0.3];
        let h = std::f64::consts::FRAC_PI_4;
        let mut w = Dopri5::new(6);
        let (mut y1, mut e) = ([0.0; 6], [0.0; 6]);
        w.step(&mut f, 0.0, &y0, h, &mut y1, &mut e);
        let d = w.dense(0.0, &y0, &y1, h);
        let at = |t: f64| {
            let mut y = [0.0; 6];
            d.at(t, &mut y);
            y
        };
        for (a, b) in [(0.0, 1.0), (0.0, 0.1), (0.3, 0.5), (0.9, 1.0), (0.5, 0.5)] {
            let (ta, tb) = (a * h, b * h);
            let (ya, yb) = (at(ta), at(tb));
            for k in [0, 3] {
                let bend = d.bend(ta, tb, k);
                let mut far: f64 = 0.0;
                for j in 0..=200 {
                    let s = j as f64 / 200.0;
                    let y = at(ta + (tb - ta) * s);
                    let off: f64 = (k..k + 3)
                        .map(|i| (y[i] - (ya[i] + (yb[i] - ya[i]) * s)).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    assert!(
                        off <= bend + 1e-15,
                        "part {a}-{b}, component {k}: {off} beyond {bend}"
                    );
                    far = far.max(off);
                }
                // Measured: 2.1-2.3 times the largest departure (the bound takes the
                // largest curvature over the whole step).
                assert!(
                    bend <= 3.0 * far + 1e-15,
                    "part {a}-{b}, component {k}: {bend} against {far}"
                );
            }
        }
    }

    /// Exact integral minus the fifth-order quadrature of `(s - theta)_+^p` over a step
    /// of length 1 (`theta` may be negative: a start before the step), for the velocity
    /// (weights `b`) and the position (weights `sum_i b_i a_ij`, against
    /// `int (1 - s) f ds`).
    fn misses(theta: f64, p: f64) -> (f64, f64) {
        let f = |s: f64| (s - theta).max(0.0).powf(p);
        let lo = theta.max(0.0);
        let (p1, p2) = (p + 1.0, p + 2.0);
        let iv = ((1.0 - theta).powf(p1) - (lo - theta).powf(p1)) / p1;
        // int_lo^1 (1 - s) (s - theta)^p ds, with 1 - s = (1 - theta) - (s - theta).
        let ix = (1.0 - theta) * iv - ((1.0 - theta).powf(p2) - (lo - theta).powf(p2)) / p2;
        let (mut qv, mut qx) = (0.0, 0.0);
        // The seventh stage has weight 0.
        for j in 0..6 {
            let bb: f64 = (j + 1..6).map(|i| A[6][i] * A[i][j]).sum();
            qv += A[6][j] * f(C[j]);
            qx += bb * f(C[j]);
        }
        (iv - qv, ix - qx)
    }

    #[test]
    fn the_miss_constants_bound_the_quadrature_of_kinks_and_touches() {
        let scan = |p: f64, lo: f64| {
            let (mut v, mut x) = (0.0f64, 0.0f64);
            for k in 0..=20_000 {
                let (dv, dx) = misses(lo + (1.0 - lo) * k as f64 / 20_000.0, p);
                (v, x) = (v.max(dv.abs()), x.max(dx.abs()));
            }
            (v, x)
        };
        let (kv, kx) = scan(1.0, 0.0);
        for (c, m) in [(KINK_MISS[0], kv), (KINK_MISS[1], kx)] {
            assert!(m <= c && m > 0.98 * c, "kink: {m} against {c}");
        }
        // A touch up to two steps before the step's start, or inside it.
        for (c, p) in [(TOUCH_MISS[0], 0.25), (TOUCH_MISS[1], 1.5)] {
            let (m, _) = scan(p, -2.0);
            assert!(m <= c && m > 0.98 * c, "touch s^{p}: {m} against {c}");
        }
        // The quadrature of the touch before the step agrees with `start_quadrature`.
        let q = start_quadrature(0.3);
        let (dv, _) = misses(-0.3, 0.25);
        let exact = (1.3f64.powf(1.25) - 0.3f64.powf(1.25)) / 1.25;
        assert!((exact - q[0].0 - dv).abs() < 1e-14);
    }

    #[test]
    fn a_step_over_a_kink_misses_no_more_than_the_kink_bound() {
        // x'' = max(0, t_k - t): a force that falls linearly to zero at t_k and stays
        // zero (a contact's kink), stepped once without a cut: the step's
        // velocity and position against the exact ones, for kinks all over the step.
        for k in 1..40 {
            let tk = k as f64 / 40.0;
            let mut f = |t: f64, y: &[f64], d: &mut [f64]| {
                d[0] = y[1];
                d[1] = (tk - t).max(0.0);
            };
            let mut w = Dopri5::new(2);
            let (mut y1, mut e) = ([0.0; 2], [0.0; 2]);
            w.step(&mut f, 0.0, &[0.0, 0.0], 1.0, &mut y1, &mut e);
            let (v, x) = (tk * tk / 2.0, tk * tk / 2.0 - tk * tk * tk / 6.0);
            assert!(
                (y1[1] - v).abs() <= KINK_MISS[0],
                "kink at {tk}: v {}",
                y1[1] - v
            );
            assert!(
                (y1[0] - x).abs() <= KINK_MISS[1],
                "kink at {tk}: x {}",
                y1[0] - x
            );
        }
    }

    #[test]
    fn integrates_polynomial_of_degree_four_exactly() {
        let mut w = Dopri5::new(1);
        let mut f = |t: f64, _y: &[f64], d: &mut [f64]| d[0] = 5.0 * t.powi(4);
        let (mut y1, mut e) = ([0.0], [0.0]);
        w.step(&mut f, 0.0, &[0.0], 1.3, &mut y1, &mut e);
        assert!((y1[0] - 1.3f64.powi(5)).abs() < 1e-12);
    }
}
