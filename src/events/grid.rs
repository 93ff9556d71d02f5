//! A persistent uniform cell grid for the event scheduler: each shot sits in one cell
//! (linked lists in flat arrays, O(1) moves), cells at least one contact distance wide so
//! that shots that can touch are always in neighbouring cells. Coordinates outside the
//! grid's box are clamped into its outer cells, which therefore reach to infinity: the
//! grid is always correct, only slower for shots far outside the box.

use crate::Vec3;

const NONE: u32 = u32::MAX;

/// Cell coordinates.
pub type Cell = [usize; 3];

/// The grid.
#[derive(Debug, Clone)]
pub struct Grid {
    lo: Vec3,
    cell: f64,
    dims: Cell,
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Each shot's cell (meaningful while it is in the grid).
    pub at: Vec<Cell>,
    inside: Vec<bool>,
}

impl Grid {
    /// A grid of cells of at least `cell` metres over the box `[lo, hi]`, for `n` shots,
    /// with at most about `max_cells` cells (cells grow to respect it).
    pub fn new(lo: Vec3, hi: Vec3, cell: f64, n: usize, max_cells: usize) -> Self {
        let ext = hi - lo;
        let mut cell = cell;
        let dims = loop {
            let d = [0, 1, 2].map(|k| ((ext[k] / cell).floor() as usize).max(1));
            if d[0] * d[1] * d[2] <= max_cells {
                break d;
            }
            cell *= 1.25;
        };
        Grid {
            lo,
            cell,
            dims,
            head: vec![NONE; dims[0] * dims[1] * dims[2]],
            next: vec![NONE; n],
            prev: vec![NONE; n],
            at: vec![[0; 3]; n],
            inside: vec![false; n],
        }
    }

    /// Cell edge, m.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Cells per axis.
    pub fn dims(&self) -> Cell {
        self.dims
    }

    /// The (clamped) cell of a point.
    pub fn cell_of(&self, p: &Vec3) -> Cell {
        [0, 1, 2].map(|k| {
            let f = crate::floor_i64((p[k] - self.lo[k]) / self.cell);
            if f <= 0 {
                0
            } else {
                (f as usize).min(self.dims[k] - 1)
            }
        })
    }

    #[inline]
    fn index(&self, c: &Cell) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Puts shot `i` into cell `c` (removing it from its old cell first).
    pub fn place(&mut self, i: usize, c: Cell) {
        if self.inside[i] {
            if self.at[i] == c {
                return;
            }
            self.remove(i);
        }
        let h = self.index(&c);
        let first = self.head[h];
        self.next[i] = first;
        self.prev[i] = NONE;
        if first != NONE {
            self.prev[first as usize] = i as u32;
        }
        self.head[h] = i as u32;
        self.at[i] = c;
        self.inside[i] = true;
    }

    /// Takes shot `i` out of the grid.
    pub fn remove(&mut self, i: usize) {
        if !self.inside[i] {
            return;
        }
        let (p, n) = (self.prev[i], self.next[i]);
        if p != NONE {
            self.next[p as usize] = n;
        } else {
            let h = self.index(&self.at[i]);
            self.head[h] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
        self.inside[i] = false;
    }

    /// Calls `f` for every shot in the cells `lo..=hi` (per axis, clamped).
    pub fn for_each_in(&self, lo: [i64; 3], hi: [i64; 3], mut f: impl FnMut(usize)) {
        let clamp = |v: i64, k: usize| v.clamp(0, self.dims[k] as i64 - 1) as usize;
        let (a, b) = (
            [0, 1, 2].map(|k| clamp(lo[k], k)),
            [0, 1, 2].map(|k| clamp(hi[k], k)),
        );
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    let mut i = self.head[self.index(&[x, y, z])];
                    while i != NONE {
                        f(i as usize);
                        i = self.next[i as usize];
                    }
                }
            }
        }
    }

    /// Calls `f` for every shot in the 27 cells around `c`.
    pub fn for_each_near(&self, c: Cell, f: impl FnMut(usize)) {
        let c = c.map(|v| v as i64);
        self.for_each_in(
            [c[0] - 1, c[1] - 1, c[2] - 1],
            [c[0] + 1, c[1] + 1, c[2] + 1],
            f,
        );
    }

    /// Calls `f` for every shot in cells that overlap the ball `(p, r)`'s bounding box.
    pub fn for_each_within(&self, p: &Vec3, r: f64, f: impl FnMut(usize)) {
        let k = |v: f64, a: usize| crate::floor_i64((v - self.lo[a]) / self.cell);
        self.for_each_in(
            [0, 1, 2].map(|a| k(p[a] - r, a)),
            [0, 1, 2].map(|a| k(p[a] + r, a)),
            f,
        );
    }

    /// Lower and upper coordinate of cell `c` along `axis`; `None` for an outer face
    /// (outer cells reach to infinity).
    pub fn faces(&self, c: &Cell, axis: usize) -> (Option<f64>, Option<f64>) {
        let lo = self.lo[axis] + c[axis] as f64 * self.cell;
        (
            (c[axis] > 0).then_some(lo),
            (c[axis] + 1 < self.dims[axis]).then_some(lo + self.cell),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn place_move_remove_and_query() {
        let mut g = Grid::new(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0), 0.1, 4, 1_000_000);
        assert_eq!(g.dims(), [10, 10, 10]);
        let pts = [
            Vec3::new(0.05, 0.05, 0.05),
            Vec3::new(0.15, 0.05, 0.05),
            Vec3::new(0.95, 0.95, 0.95),
            Vec3::new(5.0, -3.0, 0.5),
        ];
        for (i, p) in pts.iter().enumerate() {
            g.place(i, g.cell_of(p));
        }
        assert_eq!(g.at[3], [9, 0, 5]);
        let mut seen = Vec::new();
        g.for_each_near(g.at[0], |i| seen.push(i));
        seen.sort();
        assert_eq!(seen, vec![0, 1]);
        g.place(1, [5, 5, 5]);
        let mut seen = Vec::new();
        g.for_each_near(g.at[0], |i| seen.push(i));
        assert_eq!(seen, vec![0]);
        g.remove(0);
        let mut seen = Vec::new();
        g.for_each_within(&Vec3::new(0.5, 0.5, 0.5), 2.0, |i| seen.push(i));
        seen.sort();
        assert_eq!(seen, vec![1, 2, 3]);
        assert_eq!(g.faces(&[0, 0, 0], 0), (None, Some(0.1)));
        assert_eq!(g.faces(&[9, 0, 0], 0).1, None);
    }

    #[test]
    fn cells_grow_to_respect_the_budget() {
        let g = Grid::new(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0), 0.001, 1, 1000);
        let d = g.dims();
        assert!(d[0] * d[1] * d[2] <= 1000);
        assert!(g.cell_size() >= 0.1);
    }
}
