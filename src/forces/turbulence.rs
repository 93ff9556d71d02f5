//! Turbulent dispersion (beyond the paper): the discrete random-walk eddy model of
//! Gosman & Ioannides (1983). In the jet's mixing layer and developed region a shot sees
//! the mean air velocity plus a fluctuation `u'`, drawn when it meets an eddy and held for
//! the eddy's lifetime, and feels it through drag. The paper's mean-flow model has no
//! such fluctuation, and with its constants its lateral force moves a shot by well under
//! 0.1 mm (model-notes): small, slow shots follow the fluctuations more closely (Stokes
//! number ~ D^2 |u|), which is the dispersion the paper's measured trends point to.
//!
//! * `u' = I |u_mean| xi`, `xi` three independent standard normals truncated to
//!   `|xi_k| <= 3` (so force bounds hold), `I` = `jet.turbulence_intensity` (free round
//!   jets: about 0.15-0.25 in the mixing layer);
//! * eddy size `L_e = 0.4 b`, `b` the local jet radius (mixing layer: `(5d + s)/10`,
//!   developed jet: `s/5`, Eqs 15-16's edges), lifetime `t_e = L_e / (I |u_mean|)`;
//!   the eddy-crossing time is not modelled (the shots lag the air by far less than an
//!   eddy over its lifetime at these intensities);
//! * the draws come from a generator seeded by (scene seed, shot id, eddy number), so a
//!   run is reproducible whatever the islands, windows and threads.
//!
//! No fluctuation in the bore, the potential core and still air.

use crate::Vec3;
use crate::flow::{JetCoords, Region};
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};

/// The eddy model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turbulence {
    /// Intensity `I`, a fraction of the local mean speed.
    pub intensity: f64,
    /// Eddy size as a fraction of the local jet radius (0.4).
    pub scale: f64,
    /// Nozzle bore `d`, m.
    pub bore: f64,
    /// Scene seed.
    pub seed: u64,
}

/// Largest |xi_k| drawn.
pub const TRUNCATION: f64 = 3.0;

impl Turbulence {
    /// Whether `region` is turbulent.
    #[inline]
    pub fn turbulent(region: Region) -> bool {
        matches!(region, Region::Mixing | Region::Lip | Region::Developed)
    }

    /// A new eddy for shot `shot` (its `number`-th) at jet coordinates `c` in `region`
    /// with local mean speed `u`: `(u', lifetime)`. `None` outside turbulent regions or in
    /// still air.
    pub fn eddy(
        &self,
        shot: u32,
        number: u32,
        c: &JetCoords,
        region: Region,
        u: f64,
    ) -> Option<(Vec3, f64)> {
        if !Self::turbulent(region) || u <= 0.0 || self.intensity <= 0.0 {
            return None;
        }
        let d = self.bore;
        let b = match region {
            Region::Developed => c.s / 5.0,
            _ => (5.0 * d + c.s) / 10.0,
        };
        let sigma = self.intensity * u;
        let lifetime = (self.scale * b / sigma).max(1e-7);
        let key = self
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(((shot as u64) << 32) | number as u64);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(key);
        let mut draw = || loop {
            let x: f64 = StandardNormal.sample(&mut rng);
            if x.abs() <= TRUNCATION {
                return x;
            }
            let _: u32 = rng.random();
        };
        let xi = Vec3::new(draw(), draw(), draw());
        Some((xi * sigma, lifetime))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eddies_are_reproducible_and_have_the_requested_intensity() {
        let t = Turbulence {
            intensity: 0.2,
            scale: 0.4,
            bore: 6e-3,
            seed: 1,
        };
        let c = JetCoords {
            s: 0.02,
            r: 0.004,
            offset: Vec3::x() * 0.004,
        };
        let a = t.eddy(3, 7, &c, Region::Mixing, 300.0).unwrap();
        assert_eq!(a, t.eddy(3, 7, &c, Region::Mixing, 300.0).unwrap());
        assert_ne!(a.0, t.eddy(3, 8, &c, Region::Mixing, 300.0).unwrap().0);
        assert!(t.eddy(3, 7, &c, Region::Core, 300.0).is_none());
        // Lifetime 0.4 b / (I u), b = (5d + s)/10 = 5 mm.
        assert!((a.1 - 0.4 * 5e-3 / 60.0).abs() < 1e-15);
        // Over many eddies each component has rms ~ I u (truncation at 3 sigma: 0.987).
        let n = 20_000;
        let ms: f64 = (0..n)
            .map(|k| t.eddy(1, k, &c, Region::Mixing, 300.0).unwrap().0.x.powi(2))
            .sum::<f64>()
            / n as f64;
        let rms = ms.sqrt() / 60.0;
        assert!((rms - 0.987).abs() < 0.02, "{rms}");
    }
}
