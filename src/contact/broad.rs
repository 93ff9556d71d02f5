//! Broad phase: a cell list that finds the pairs of spheres whose (inflated) radii
//! overlap, in O(N log N) time with a deterministic output order.
//!
//! Each item is a centre and an inflated radius (shot radius plus how far it can move
//! in the coming window). Items are sorted by cell; each item then looks at the 27 cells
//! around its own. Pairs come out sorted, whatever the input order of equal keys.

use crate::Vec3;

type Cell = (i64, i64, i64);

/// Reusable cell list.
#[derive(Debug, Default, Clone)]
pub struct CellList {
    order: Vec<(Cell, u32)>,
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
        let r_max = radii.iter().cloned().fold(0.0, f64::max);
        let cell = (2.0 * r_max).max(1e-12);
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
        for (i, p) in centres.iter().enumerate() {
            let (cx, cy, cz) = key(p);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let c = (cx + dx, cy + dy, cz + dz);
                        let start = self.order.partition_point(|e| e.0 < c);
                        for &(k, j) in &self.order[start..] {
                            if k != c {
                                break;
                            }
                            let j = j as usize;
                            if j <= i {
                                continue;
                            }
                            let reach = radii[i] + radii[j];
                            if (centres[j] - p).norm_squared() < reach * reach {
                                out.push((i as u32, j as u32));
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

    #[test]
    fn matches_brute_force() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let n = 400;
        let centres: Vec<Vec3> = (0..n)
            .map(|_| {
                Vec3::new(
                    rng.random_range(-0.01..0.01),
                    rng.random_range(-0.01..0.01),
                    rng.random_range(0.0..0.02),
                )
            })
            .collect();
        let radii: Vec<f64> = (0..n).map(|_| rng.random_range(2e-4..8e-4)).collect();
        let mut brute = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let r = radii[i] + radii[j];
                if (centres[i] - centres[j]).norm_squared() < r * r {
                    brute.push((i as u32, j as u32));
                }
            }
        }
        let got = CellList::default().pairs(&centres, &radii);
        assert_eq!(got, brute);
        assert!(!got.is_empty());
    }
}
