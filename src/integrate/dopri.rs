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

/// Reusable stage storage for a state of fixed length.
#[derive(Debug, Clone)]
pub struct Dopri5 {
    k: [Vec<f64>; 7],
    stage: Vec<f64>,
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
            f(t, y, &mut self.k[0]);
            self.first_stage_valid = true;
            evals += 1;
        }
        for s in 1..7 {
            for (i, (st, yi)) in self.stage.iter_mut().zip(y).enumerate() {
                let mut acc = 0.0;
                for (j, a) in A[s].iter().enumerate().take(s) {
                    acc += a * self.k[j][i];
                }
                *st = yi + h * acc;
            }
            let (done, rest) = self.k.split_at_mut(s);
            let _ = done;
            f(t + C[s] * h, &self.stage, &mut rest[0]);
            evals += 1;
        }
        // Stage 7 is evaluated at the fifth-order solution itself (FSAL).
        y_new.copy_from_slice(&self.stage);
        for (i, ei) in err.iter_mut().enumerate() {
            let mut e = 0.0;
            for (j, w) in E.iter().enumerate() {
                e += w * self.k[j][i];
            }
            *ei = h * e;
        }
        evals
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
    fn integrates_polynomial_of_degree_four_exactly() {
        let mut w = Dopri5::new(1);
        let mut f = |t: f64, _y: &[f64], d: &mut [f64]| d[0] = 5.0 * t.powi(4);
        let (mut y1, mut e) = ([0.0], [0.0]);
        w.step(&mut f, 0.0, &[0.0], 1.3, &mut y1, &mut e);
        assert!((y1[0] - 1.3f64.powi(5)).abs() < 1e-12);
    }
}
