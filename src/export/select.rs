//! Which impacts go into an FE deck: a window on the specimen (a representative area),
//! a time window, the first N, or a seeded random sample of N. Filters apply in that
//! order; the result keeps time order.

use crate::Vec3;
use crate::contact::specimen::SpecimenShape;
use crate::record::Impact;
use crate::scene::validate::num;
use rand::SeedableRng;
use rand::seq::index::sample;
use rand_chacha::ChaCha8Rng;

/// Selection settings (SI).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Selection {
    /// Contact points inside `[x0, x1] x [y0, y1]`, m (on a cylindrical specimen, on
    /// its unrolled surface: [`SpecimenShape::unrolled`]).
    pub window: Option<[f64; 4]>,
    /// First-contact times inside `[t0, t1]`, s.
    pub time_window: Option<[f64; 2]>,
    /// Keep only first hits (no rebound hits).
    pub first_hits_only: bool,
    /// The first N remaining impacts in time.
    pub first: Option<usize>,
    /// A random sample of N remaining impacts, drawn with `seed`.
    pub sample: Option<usize>,
    /// Seed of the sample.
    pub seed: u64,
    /// The specimen's surface, whose (unrolled) coordinates the window takes.
    pub shape: SpecimenShape,
}

impl Selection {
    /// Applies the selection; the input must be sorted by time.
    pub fn apply(&self, impacts: &[Impact]) -> Vec<Impact> {
        let mut v: Vec<Impact> = impacts
            .iter()
            .filter(|i| {
                self.window.is_none_or(|[x0, y0, x1, y1]| {
                    let (x, y) = self.shape.unrolled(&Vec3::new(i.x_m, i.y_m, i.z_m));
                    x >= x0.min(x1) && x <= x0.max(x1) && y >= y0.min(y1) && y <= y0.max(y1)
                })
            })
            .filter(|i| {
                self.time_window
                    .is_none_or(|[t0, t1]| i.time_s >= t0 && i.time_s <= t1)
            })
            .filter(|i| !self.first_hits_only || i.first_hit == 1)
            .cloned()
            .collect();
        if let Some(n) = self.first {
            v.truncate(n);
        }
        if let Some(n) = self.sample
            && n < v.len()
        {
            let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
            let mut idx = sample(&mut rng, v.len(), n).into_vec();
            idx.sort_unstable();
            v = idx.into_iter().map(|k| v[k].clone()).collect();
        }
        v
    }

    /// One-line description for messages and deck headers.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if let Some([x0, y0, x1, y1]) = self.window {
            let (x, y) = self.shape.unrolled_names();
            parts.push(format!(
                "window {x} {}..{} mm, {y} {}..{} mm",
                num(x0 * 1e3),
                num(x1 * 1e3),
                num(y0 * 1e3),
                num(y1 * 1e3)
            ));
        }
        if let Some([t0, t1]) = self.time_window {
            parts.push(format!("time {}..{} ms", num(t0 * 1e3), num(t1 * 1e3)));
        }
        if self.first_hits_only {
            parts.push("first hits only".into());
        }
        if let Some(n) = self.first {
            parts.push(format!("first {n}"));
        }
        if let Some(n) = self.sample {
            parts.push(format!("random sample of {n} (seed {})", self.seed));
        }
        if parts.is_empty() {
            "all impacts".into()
        } else {
            parts.join(", ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn impacts() -> Vec<Impact> {
        (0..20)
            .map(|k| {
                let x = k as f64 * 1e-3;
                Impact::new(
                    k,
                    k as f64 * 1e-4,
                    &Vec3::new(x, -x, 4e-4),
                    &Vec3::new(0.0, 0.0, -60.0),
                    &Vec3::zeros(),
                    4e-4,
                    2e-6,
                    0,
                    k % 3 != 0,
                )
            })
            .collect()
    }

    #[test]
    fn filters_compose_in_order() {
        let all = impacts();
        let s = Selection {
            window: Some([2.5e-3, -20e-3, 15.5e-3, 0.0]),
            time_window: Some([0.0, 1.25e-3]),
            ..Selection::default()
        };
        let ids: Vec<u32> = s.apply(&all).iter().map(|i| i.shot).collect();
        assert_eq!(ids, vec![3, 4, 5, 6, 7, 8, 9, 10, 11, 12]);
        let s = Selection {
            first_hits_only: true,
            first: Some(3),
            ..Selection::default()
        };
        let ids: Vec<u32> = s.apply(&all).iter().map(|i| i.shot).collect();
        assert_eq!(ids, vec![1, 2, 4]);
    }

    #[test]
    fn sample_is_seeded_sorted_and_without_repeats() {
        let all = impacts();
        let s = Selection {
            sample: Some(5),
            seed: 9,
            ..Selection::default()
        };
        let a: Vec<u32> = s.apply(&all).iter().map(|i| i.shot).collect();
        let b: Vec<u32> = s.apply(&all).iter().map(|i| i.shot).collect();
        assert_eq!(a, b);
        assert_eq!(a.len(), 5);
        assert!(a.windows(2).all(|w| w[0] < w[1]));
        let other: Vec<u32> = Selection {
            seed: 10,
            ..s.clone()
        }
        .apply(&all)
        .iter()
        .map(|i| i.shot)
        .collect();
        assert_ne!(a, other);
        assert_eq!(
            Selection {
                sample: Some(50),
                ..Selection::default()
            }
            .apply(&all)
            .len(),
            20
        );
    }
}
