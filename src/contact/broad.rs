//! Broad phase: a cell list that finds the pairs of spheres whose (inflated) radii
//! overlap, in O(N) expected time, with a deterministic (sorted) output.
//!
//! Each item is a centre and an inflated radius (shot radius plus how far it can move
//! in the coming window). Radii vary a lot (shots at rest next to fast ones), so the cell
//! size follows the median radius, and each pair is found by the item with the larger
//! radius, which searches the cells within twice its radius.

use crate::Vec3;
use rustc_hash::FxHashMap;

type Cell = (i64, i64, i64);

/// Reusable cell list.
#[derive(Debug, Default, Clone)]
pub struct CellList {
    order: Vec<(Cell, u32)>,
    ranges: FxHashMap<Cell, (u32, u32)>,
}

impl CellList {
    /// All pairs `(i, j)`, `i < j`, with `|x_i - x_j| < r_i + r_j`, sorted.
    /// `centres` and `radii` are indexed alike.
    pub fn pairs(&mut self, centres: &[Vec3], radii: &[f64]) -> Vec<(u32, u32)> {
        let n = centres.len();
        let mut out = Vec::new();
        if n < 2 {
            return out;
        }
        let mut sorted_r: Vec<f64> = radii.to_vec();
        sorted_r.sort_unstable_by(f64::total_cmp);
        let cell = (2.0 * sorted_r[n / 2]).max(1e-12);
        let key = |p: &Vec3| -> Cell {
            (
                (p.x / cell).floor() as i64,
                (p.y / cell).floor() as i64,
                (p.z / cell).floor() as i64,
            )
        };
        self.order.clear();
        self.order
            .extend(centres.iter().enumerate().map(|(i, p)| (key(p), i as u32)));
        self.order.sort_unstable();
        self.ranges.clear();
        let mut start = 0;
        for k in 1..=n {
            if k == n || self.order[k].0 != self.order[start].0 {
                self.ranges
                    .insert(self.order[start].0, (start as u32, k as u32));
                start = k;
            }
        }
        for (i, p) in centres.iter().enumerate() {
            let ri = radii[i];
            let (cx, cy, cz) = key(p);
            let reach = (2.0 * ri / cell).ceil() as i64;
            for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        let Some(&(a, b)) = self.ranges.get(&(cx + dx, cy + dy, cz + dz)) else {
                            continue;
                        };
                        for &(_, j) in &self.order[a as usize..b as usize] {
                            let j = j as usize;
                            let rj = radii[j];
                            // The larger radius finds the pair (ties: the lower index).
                            if rj > ri || (rj == ri && j <= i) {
                                continue;
                            }
                            let reach = ri + rj;
                            if (centres[j] - p).norm_squared() < reach * reach {
                                out.push((i.min(j) as u32, i.max(j) as u32));
                            }
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn brute(centres: &[Vec3], radii: &[f64]) -> Vec<(u32, u32)> {
        let mut v = Vec::new();
        for i in 0..centres.len() {
            for j in i + 1..centres.len() {
                let r = radii[i] + radii[j];
                if (centres[i] - centres[j]).norm_squared() < r * r {
                    v.push((i as u32, j as u32));
                }
            }
        }
        v
    }

    #[test]
    fn matches_brute_force_for_mixed_radii() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for trial in 0..20 {
            let n = 300;
            let centres: Vec<Vec3> = (0..n)
                .map(|_| {
                    Vec3::new(
                        rng.random_range(-0.01..0.01),
                        rng.random_range(-0.01..0.01),
                        rng.random_range(0.0..0.02),
                    )
                })
                .collect();
            // Mostly small radii, a few very large ones (fast shots), some equal ties.
            let radii: Vec<f64> = (0..n)
                .map(|k| match k % 17 {
                    0 => rng.random_range(2e-3..6e-3),
                    1 => 4e-4,
                    _ => rng.random_range(2e-4..8e-4),
                })
                .collect();
            let got = CellList::default().pairs(&centres, &radii);
            assert_eq!(got, brute(&centres, &radii), "trial {trial}");
            assert!(!got.is_empty());
        }
    }
}
