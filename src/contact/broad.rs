//! Broad phase: a cell list that finds the pairs of spheres whose (inflated) radii
//! overlap, in O(N) expected time, with a deterministic (sorted) output.
//!
//! Each item is a centre and an inflated radius (shot radius plus how far it can move
//! in the coming window). Radii vary a lot (shots at rest next to fast ones), so the cell
//! is twice the 90th-percentile radius, and each pair is found by the item with the
//! larger radius, which searches the 27 cells around it; the largest tenth search a
//! second, coarse grid (cell: twice the largest radius) instead. A grid is a dense array
//! of cells (counting sort) when the items' bounding box holds few enough cells, else a
//! hash map of the occupied ones.

use crate::Vec3;
use rustc_hash::FxHashMap;

type Cell = (i64, i64, i64);

/// Items binned by cell: a dense array of cells when the items' bounding box holds
/// few enough cells (a counting sort, no hashing), else a hash map of occupied cells.
#[derive(Debug, Default, Clone)]
struct Bins {
    cell: f64,
    /// Dense: lowest cell, cells per axis; `starts[c]..starts[c + 1]` into `items`.
    lo: Cell,
    dims: (i64, i64, i64),
    dense: bool,
    starts: Vec<u32>,
    items: Vec<u32>,
    /// Hashed: `(cell, item)` sorted, and each occupied cell's range in it.
    order: Vec<(Cell, u32)>,
    ranges: FxHashMap<Cell, (u32, u32)>,
}

impl Bins {
    #[inline]
    fn key(&self, p: &Vec3) -> Cell {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
            (p.z / self.cell).floor() as i64,
        )
    }

    fn build(&mut self, centres: &[Vec3], cell: f64) {
        self.cell = cell;
        let n = centres.len();
        let (mut lo, mut hi) = (
            (i64::MAX, i64::MAX, i64::MAX),
            (i64::MIN, i64::MIN, i64::MIN),
        );
        for p in centres {
            let k = self.key(p);
            lo = (lo.0.min(k.0), lo.1.min(k.1), lo.2.min(k.2));
            hi = (hi.0.max(k.0), hi.1.max(k.1), hi.2.max(k.2));
        }
        let dims = (hi.0 - lo.0 + 1, hi.1 - lo.1 + 1, hi.2 - lo.2 + 1);
        let total = (dims.0 as f64) * (dims.1 as f64) * (dims.2 as f64);
        self.dense = total <= (8.0 * n as f64).max(65_536.0) && total <= 16_777_216.0;
        if self.dense {
            self.lo = lo;
            self.dims = dims;
            let total = total as usize;
            self.starts.clear();
            self.starts.resize(total + 1, 0);
            let index = |k: Cell| -> usize {
                (((k.0 - lo.0) * dims.1 + (k.1 - lo.1)) * dims.2 + (k.2 - lo.2)) as usize
            };
            for p in centres {
                let c = index(self.key(p));
                self.starts[c + 1] += 1;
            }
            for c in 0..total {
                self.starts[c + 1] += self.starts[c];
            }
            self.items.clear();
            self.items.resize(n, 0);
            let mut fill = self.starts.clone();
            for (i, p) in centres.iter().enumerate() {
                let c = index(self.key(p));
                self.items[fill[c] as usize] = i as u32;
                fill[c] += 1;
            }
        } else {
            self.order.clear();
            let keys: Vec<Cell> = centres.iter().map(|p| self.key(p)).collect();
            self.order
                .extend(keys.into_iter().enumerate().map(|(i, k)| (k, i as u32)));
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
        }
    }

    /// Calls `f(j)` for every item in cell `c`.
    #[inline]
    fn each(&self, c: Cell, f: &mut impl FnMut(usize)) {
        if self.dense {
            let r = (c.0 - self.lo.0, c.1 - self.lo.1, c.2 - self.lo.2);
            if r.0 < 0
                || r.1 < 0
                || r.2 < 0
                || r.0 >= self.dims.0
                || r.1 >= self.dims.1
                || r.2 >= self.dims.2
            {
                return;
            }
            let k = ((r.0 * self.dims.1 + r.1) * self.dims.2 + r.2) as usize;
            for &j in &self.items[self.starts[k] as usize..self.starts[k + 1] as usize] {
                f(j as usize);
            }
        } else if let Some(&(a, b)) = self.ranges.get(&c) {
            for &(_, j) in &self.order[a as usize..b as usize] {
                f(j as usize);
            }
        }
    }
}

/// Reusable cell list.
#[derive(Debug, Default, Clone)]
pub struct CellList {
    fine: Bins,
    coarse: Bins,
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
        // Cells of twice the 90th-percentile radius: every item up to it finds its pairs
        // in the 27 cells around it. The largest tenth (fast or kicked shots) would scan
        // many mostly empty cells: they search a coarse grid instead, whose cell is twice
        // the largest radius, holding every item.
        let r_small = sorted_r[(9 * n) / 10].max(1e-12);
        let cell = 2.0 * r_small;
        let big = |r: f64| r > r_small;
        let r_big = sorted_r.iter().rev().cloned().find(|&r| big(r));
        self.fine.build(centres, cell);
        let scan = |bins: &Bins, i: usize, reach: i64, out: &mut Vec<(u32, u32)>| {
            let p = &centres[i];
            let ri = radii[i];
            let (cx, cy, cz) = bins.key(p);
            for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        bins.each((cx + dx, cy + dy, cz + dz), &mut |j| {
                            let rj = radii[j];
                            // The larger radius finds the pair (ties: the lower index).
                            if rj > ri || (rj == ri && j <= i) {
                                return;
                            }
                            let reach = ri + rj;
                            if (centres[j] - p).norm_squared() < reach * reach {
                                out.push((i.min(j) as u32, i.max(j) as u32));
                            }
                        });
                    }
                }
            }
        };
        for (i, &r) in radii.iter().enumerate() {
            if !big(r) {
                let reach = (2.0 * r / cell).ceil() as i64;
                scan(&self.fine, i, reach, &mut out);
            }
        }
        if let Some(r_big) = r_big {
            self.coarse.build(centres, 2.0 * r_big);
            for (i, &r) in radii.iter().enumerate() {
                if big(r) {
                    scan(&self.coarse, i, 1, &mut out);
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
    fn matches_brute_force_for_mixed_radii_in_both_layouts() {
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
            // Spread over a box too large for a dense grid (the hashed layout): two
            // clumps a metre apart.
            let spread: Vec<Vec3> = centres
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    if k % 2 == 0 {
                        *c
                    } else {
                        c + Vec3::new(1.0, 1.0, 1.0)
                    }
                })
                .collect();
            let mut cells = CellList::default();
            let got = cells.pairs(&spread, &radii);
            assert!(
                !cells.fine.dense,
                "trial {trial}: the grid should be hashed"
            );
            assert_eq!(got, brute(&spread, &radii), "trial {trial}, spread");
        }
    }
}
