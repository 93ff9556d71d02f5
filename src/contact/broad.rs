//! Broad phase: finds the pairs of spheres whose (inflated) radii overlap, with a
//! deterministic (sorted) output, by sweep and prune or by a cell list, whichever the
//! items' layout suits.
//!
//! Sparse items strung out along one axis (shots in a nozzle stream, a falling column)
//! are swept along one axis, the one on which their intervals overlap least (estimated
//! from a 64-bin histogram of the centres per axis): sorted by the low end of their
//! interval on it, each item checks the items whose intervals start inside its
//! own, O(N log N) plus the overlaps. A dense grid over such a layout would be mostly
//! empty cells, and a hashed one pays 27 lookups per item. When the intervals would
//! overlap too many others (a bed, a compact cloud) the sweep is not tried, and a sweep
//! that finds more than its budget of interval overlaps is abandoned for the cell list.
//! Calls for items that move little from one call to the next (the window scheduler's
//! shots, [`CellList::pairs_tracked`]) start the sort from the previous call's order and
//! finish it by insertion: the same order and pairs, without a full sort per window.
//! When such a call has the same items as the one before, its search runs with each
//! radius widened by a skin (a DEM code's neighbour-list skin) and keeps what it found;
//! the following calls filter those pairs while every item stays inside its widened ball
//! (its move since plus its new radius within the widened radius), which by the triangle
//! inequality holds every pair a fresh search would find: the same pairs, without a
//! search per call where short windows follow each other in a dense pile.
//!
//! The cell list, in O(N) expected time.
//! Each item is a centre and an inflated radius (shot radius plus how far it can move
//! in the coming window). Radii vary a lot (shots at rest next to fast ones), so the cell
//! is twice the 90th-percentile radius, and each pair is found by the item with the
//! larger radius, which searches the 27 cells around it; the largest tenth search a
//! second, coarse grid (cell: twice the largest radius) instead. A grid is a dense array
//! of cells (counting sort) when the items' bounding box holds few enough cells, else a
//! hash map of the occupied ones. Either way it keeps its items in cell order with their
//! centres and radii alongside, and the search runs through the items in that order: the
//! cells an item visits are read from contiguous memory (in a dense grid a column of
//! cells along `z` is one range), and the items searched one after another share them
//! (a 3,000-shot pile on the fixed-step method: 8 % faster than gathering each
//! neighbour's centre and radius by its index, session 69).

use crate::Vec3;
use rustc_hash::FxHashMap;

type Cell = (i64, i64, i64);

/// Items binned by cell: a dense array of cells when the items' bounding box holds
/// few enough cells (a counting sort, no hashing), else a hash map of occupied cells.
/// Either way the items are kept in cell order with their centres and radii packed
/// alongside (`packed`), so that a search reads the cells it visits from contiguous
/// memory rather than gathering each item's centre and radius from wherever it sits.
#[derive(Debug, Default, Clone)]
struct Bins {
    cell: f64,
    /// Dense: lowest cell, cells per axis; `starts[c]..starts[c + 1]` into `items`
    /// (`z` fastest, so a column of cells along `z` is one range).
    lo: Cell,
    dims: (i64, i64, i64),
    dense: bool,
    starts: Vec<u32>,
    /// The items in cell order, and each one's centre and radius.
    items: Vec<u32>,
    packed: Vec<[f64; 4]>,
    /// Hashed: each occupied cell's range in `items`.
    ranges: FxHashMap<Cell, (u32, u32)>,
    /// Hashed: `(cell, item)`, sorted (scratch).
    order: Vec<(Cell, u32)>,
}

impl Bins {
    #[inline]
    fn key(&self, p: &Vec3) -> Cell {
        (
            crate::floor_i64(p.x / self.cell),
            crate::floor_i64(p.y / self.cell),
            crate::floor_i64(p.z / self.cell),
        )
    }

    fn build(&mut self, centres: &[Vec3], radii: &[f64], cell: f64) {
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
        self.items.clear();
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
            self.items.extend(self.order.iter().map(|&(_, i)| i));
        }
        self.packed.clear();
        self.packed.extend(self.items.iter().map(|&i| {
            let (p, r) = (&centres[i as usize], radii[i as usize]);
            [p.x, p.y, p.z, r]
        }));
    }

    /// Calls `f` with the items (indices, and centres and radii packed alike) of the
    /// cells `(x, y, z)`, `z` in `z_lo..=z_hi`: one slice for the whole column where
    /// the cells are dense, one per occupied cell where they are hashed.
    #[inline]
    fn column(
        &self,
        (x, y): (i64, i64),
        (z_lo, z_hi): (i64, i64),
        f: &mut impl FnMut(&[u32], &[[f64; 4]]),
    ) {
        if self.dense {
            let r = (x - self.lo.0, y - self.lo.1);
            let (za, zb) = (
                (z_lo - self.lo.2).max(0),
                (z_hi - self.lo.2).min(self.dims.2 - 1),
            );
            if r.0 < 0 || r.1 < 0 || r.0 >= self.dims.0 || r.1 >= self.dims.1 || za > zb {
                return;
            }
            let k = ((r.0 * self.dims.1 + r.1) * self.dims.2) as usize;
            let (a, b) = (
                self.starts[k + za as usize] as usize,
                self.starts[k + zb as usize + 1] as usize,
            );
            f(&self.items[a..b], &self.packed[a..b]);
        } else {
            for z in z_lo..=z_hi {
                if let Some(&(a, b)) = self.ranges.get(&(x, y, z)) {
                    let (a, b) = (a as usize, b as usize);
                    f(&self.items[a..b], &self.packed[a..b]);
                }
            }
        }
    }
}

/// The sweep is tried when an item's interval on the sweep axis is expected to hold
/// the starts of at most this many others.
const SWEEP_EXPECTED: f64 = 16.0;
/// Histogram bins per axis for that estimate.
const BINS: usize = 64;
/// A sweep that checks more than this many candidate pairs per item (plus a constant)
/// is abandoned for the cell list: the items bunch up somewhere.
const SWEEP_BUDGET: usize = 24;
/// A tracked call keeps the previous call's sweep axis for this many calls before
/// choosing it from the histogram again (the items move little between calls; a layout
/// that bunches up meanwhile exhausts the sweep's budget, and the next call chooses
/// afresh).
const AXIS_KEPT: u32 = 16;

/// A tracked call's pairs within skin-widened radii, kept for the calls after it
/// ([`CellList::pairs_tracked`]).
#[derive(Debug, Default, Clone)]
struct Skin {
    /// The previous tracked call's ids (ascending): a search is widened when the next
    /// call has the same.
    last_ids: Vec<usize>,
    /// Whether `centres`, `widened` and `pairs` hold a search for `last_ids`.
    held: bool,
    /// The widened search's centres and radii (its items being `last_ids`).
    centres: Vec<Vec3>,
    widened: Vec<f64>,
    /// Its pairs (local indices, sorted).
    pairs: Vec<(u32, u32)>,
    /// The calls that filtered them so far.
    uses: u32,
    /// Widened searches in a row not filtered even once, and the calls still to wait
    /// before the next (`2^misses` after a miss).
    misses: u32,
    wait: u32,
}

impl Skin {
    /// Whether the kept pairs hold every pair of `centres` with `radii` (the same items):
    /// each item's move since the widened search plus its radius stays within its
    /// widened radius, less a slack far above the rounding.
    fn covers(&self, centres: &[Vec3], radii: &[f64]) -> bool {
        self.held
            && self
                .centres
                .iter()
                .zip(&self.widened)
                .zip(centres.iter().zip(radii))
                .all(|((c0, &w), (c, &r))| {
                    let slack = 1e-9 * (w + c0.amax());
                    (c - c0).norm() + r + slack <= w
                })
    }
}

/// At most `2^SKIN_BACKOFF` tracked calls wait between widened searches that nobody
/// filtered.
const SKIN_BACKOFF: u32 = 6;

/// Reusable broad phase (sweep buffers and cell grids).
#[derive(Debug, Default, Clone)]
pub struct CellList {
    fine: Bins,
    coarse: Bins,
    /// Sweep order: the low end of each item's interval on the sweep axis, and the item.
    sweep: Vec<(f64, u32)>,
    /// The last tracked call's sweep ([`CellList::pairs_tracked`]).
    track: Track,
    /// Whether the last call swept (for tests).
    swept: bool,
    /// Whether the last call's sweep order came from the previous one's (for tests).
    reused: bool,
    /// The tracked calls' skin.
    skin: Skin,
    /// Whether the last call filtered the skin's pairs instead of searching
    /// ([`CellList::filtered_last`]: the windows count searches only).
    skinned: bool,
}

/// A tracked call's sweep axis, its items' ids (ascending) and their sweep order (by
/// item), from which the next tracked call starts its own.
#[derive(Debug, Default, Clone)]
struct Track {
    axis: Option<usize>,
    /// Tracked calls since the axis was last chosen from the histogram.
    since_histogram: u32,
    ids: Vec<usize>,
    order: Vec<u32>,
}

/// Order of sweep entries: interval start, then item.
#[inline]
fn sweep_order(a: &(f64, u32), b: &(f64, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// Sorts an almost sorted `v` by insertion; gives up (returning `false`, `v` then a
/// permutation of itself) after `budget` moves.
fn insertion_sort(v: &mut [(f64, u32)], budget: usize) -> bool {
    let mut moves = 0;
    for k in 1..v.len() {
        let x = v[k];
        let mut j = k;
        while j > 0 && sweep_order(&x, &v[j - 1]).is_lt() {
            v[j] = v[j - 1];
            j -= 1;
            moves += 1;
            if moves > budget {
                v[j] = x;
                return false;
            }
        }
        v[j] = x;
    }
    true
}

impl CellList {
    /// All pairs `(i, j)`, `i < j`, with `|x_i - x_j| < r_i + r_j`, sorted.
    /// `centres` and `radii` are indexed alike.
    pub fn pairs(&mut self, centres: &[Vec3], radii: &[f64]) -> Vec<(u32, u32)> {
        self.pairs_of(centres, radii, None)
    }

    /// [`CellList::pairs`] for items with ids `ids` (ascending, indexed alike) that move
    /// little from one call to the next (a window scheduler's shots): a sweep starts
    /// from the previous tracked call's order, sorted again by insertion (the same
    /// order, and so the same pairs, at a fraction of a full sort's cost).
    ///
    /// A call with the same ids as the previous tracked call searches with each radius
    /// widened by `skin` (indexed alike) and keeps those pairs; the calls after it filter
    /// them for as long as they hold every pair (module docs). Either way the result is
    /// exactly [`CellList::pairs`]'.
    pub fn pairs_tracked(
        &mut self,
        centres: &[Vec3],
        radii: &[f64],
        ids: &[usize],
        skin: &[f64],
    ) -> Vec<(u32, u32)> {
        debug_assert!(ids.windows(2).all(|w| w[0] < w[1]));
        debug_assert!(centres.len() == radii.len() && radii.len() == skin.len());
        let same = self.skin.last_ids == ids;
        if same && self.skin.covers(centres, radii) {
            self.skinned = true;
            self.swept = false;
            self.reused = false;
            self.skin.uses += 1;
            self.skin.misses = 0;
            return Self::filtered(&self.skin.pairs, centres, radii);
        }
        self.skinned = false;
        if self.skin.held && self.skin.uses == 0 {
            // Widened for nothing (the shots move too far per call, or others came and
            // went): wait twice as many calls as last time before widening again.
            self.skin.misses = (self.skin.misses + 1).min(SKIN_BACKOFF);
            self.skin.wait = 1 << self.skin.misses;
        }
        self.skin.held = false;
        if !same {
            self.skin.last_ids.clear();
            self.skin.last_ids.extend_from_slice(ids);
        }
        if !same || self.skin.wait > 0 {
            self.skin.wait = self.skin.wait.saturating_sub(1);
            return self.pairs_of(centres, radii, Some(ids));
        }
        let mut widened = std::mem::take(&mut self.skin.widened);
        widened.clear();
        widened.extend(radii.iter().zip(skin).map(|(r, s)| r + s));
        self.skin.pairs = self.pairs_of(centres, &widened, Some(ids));
        self.skin.widened = widened;
        self.skin.centres.clear();
        self.skin.centres.extend_from_slice(centres);
        self.skin.held = true;
        self.skin.uses = 0;
        Self::filtered(&self.skin.pairs, centres, radii)
    }

    /// Whether the last tracked call filtered the skin's pairs rather than searching.
    pub fn filtered_last(&self) -> bool {
        self.skinned
    }

    /// The pairs of `kept` (sorted) within `radii` at `centres`, by the searches' own
    /// test: sorted, as a search returns them.
    fn filtered(kept: &[(u32, u32)], centres: &[Vec3], radii: &[f64]) -> Vec<(u32, u32)> {
        kept.iter()
            .copied()
            .filter(|&(i, j)| {
                let (i, j) = (i as usize, j as usize);
                let reach = radii[i] + radii[j];
                (centres[j] - centres[i]).norm_squared() < reach * reach
            })
            .collect()
    }

    fn pairs_of(
        &mut self,
        centres: &[Vec3],
        radii: &[f64],
        ids: Option<&[usize]>,
    ) -> Vec<(u32, u32)> {
        let n = centres.len();
        let mut out = Vec::new();
        self.swept = false;
        self.reused = false;
        if n < 2 {
            return out;
        }
        if self.sweep_pairs(centres, radii, ids, &mut out) {
            self.swept = true;
            out.sort_unstable();
            return out;
        }
        out.clear();
        self.cell_pairs(centres, radii, &mut out);
        out.sort_unstable();
        out
    }

    /// Sweep and prune along the axis the histogram estimate picks (module docs):
    /// appends every overlapping pair to `out` and returns `true`, or returns `false`
    /// (`out` then holds a part) if the layout does not suit a sweep.
    fn sweep_pairs(
        &mut self,
        centres: &[Vec3],
        radii: &[f64],
        ids: Option<&[usize]>,
        out: &mut Vec<(u32, u32)>,
    ) -> bool {
        let n = centres.len();
        let (mut lo, mut hi) = (centres[0], centres[0]);
        let mut r_sum = 0.0;
        for (c, &r) in centres.iter().zip(radii) {
            lo = lo.inf(c);
            hi = hi.sup(c);
            r_sum += r;
        }
        let extent = hi - lo;
        let kept = match (ids, self.track.axis) {
            (Some(_), Some(axis)) if self.track.since_histogram < AXIS_KEPT => Some(axis),
            _ => None,
        };
        let axis = match kept {
            Some(axis) => axis,
            None => {
                // Per axis, the candidate checks a sweep along it would make, from a
                // histogram of the centres on it: bin `b`'s items each check those
                // starting within their interval, `count_b x 2 r_mean / bin width` of
                // them.
                let diameter = 2.0 * r_sum / n as f64;
                let mut best = (f64::INFINITY, 0);
                for axis in 0..3 {
                    let width = extent[axis] / BINS as f64;
                    if width.is_nan() || width <= 0.0 {
                        continue;
                    }
                    let mut counts = [0u32; BINS];
                    for c in centres {
                        let b = ((c[axis] - lo[axis]) / width) as usize;
                        counts[b.min(BINS - 1)] += 1;
                    }
                    let squares: f64 = counts.iter().map(|&k| f64::from(k) * f64::from(k)).sum();
                    let checks = squares * diameter / width;
                    if checks < best.0 {
                        best = (checks, axis);
                    }
                }
                let (checks, axis) = best;
                let expected = checks / n as f64;
                if expected.is_nan() || expected > SWEEP_EXPECTED {
                    if ids.is_some() {
                        self.track.axis = None;
                    }
                    return false;
                }
                axis
            }
        };
        let order = &mut self.sweep;
        order.clear();
        let key = |i: usize| (centres[i][axis] - radii[i], i as u32);
        if let Some(ids) = ids
            && self.track.axis == Some(axis)
        {
            // The previous order, its items mapped to this call's (both id lists
            // ascend), then the new items; sorted again by insertion.
            let mut seen = vec![false; n];
            let mut new_of_old = vec![u32::MAX; self.track.ids.len()];
            let mut k = 0;
            for (old, id) in self.track.ids.iter().enumerate() {
                while k < n && ids[k] < *id {
                    k += 1;
                }
                if k < n && ids[k] == *id {
                    new_of_old[old] = k as u32;
                    seen[k] = true;
                }
            }
            order.extend(
                self.track
                    .order
                    .iter()
                    .map(|&old| new_of_old[old as usize])
                    .filter(|&i| i != u32::MAX)
                    .map(|i| key(i as usize)),
            );
            order.extend((0..n).filter(|&i| !seen[i]).map(key));
            self.reused = insertion_sort(order, 4 * n + 64);
        }
        if !self.reused {
            order.clear();
            order.extend((0..n).map(key));
            order.sort_unstable_by(sweep_order);
        }
        if let Some(ids) = ids {
            let track = &mut self.track;
            track.axis = Some(axis);
            track.since_histogram = kept.map_or(0, |_| track.since_histogram + 1);
            track.ids.clear();
            track.ids.extend_from_slice(ids);
            track.order.clear();
            track.order.extend(order.iter().map(|&(_, i)| i));
        }
        // Rounding of the interval ends must not lose a pair: a start counts as inside an
        // interval up to a slack far above the rounding and far below any radius.
        let slack = 1e-9 * (extent[axis] + lo[axis].abs() + hi[axis].abs());
        let mut budget = SWEEP_BUDGET * n + 64;
        for (k, &(_, i)) in order.iter().enumerate() {
            let i = i as usize;
            let (ci, ri) = (centres[i], radii[i]);
            let end = ci[axis] + ri + slack;
            for &(start, j) in &order[k + 1..] {
                if start >= end {
                    break;
                }
                if budget == 0 {
                    // Bunched up: the next tracked call chooses from the histogram.
                    self.track.since_histogram = AXIS_KEPT;
                    return false;
                }
                budget -= 1;
                let j = j as usize;
                let reach = ri + radii[j];
                if (centres[j] - ci).norm_squared() < reach * reach {
                    out.push((i.min(j) as u32, i.max(j) as u32));
                }
            }
        }
        true
    }

    /// The cell list (module docs): appends every overlapping pair to `out`.
    fn cell_pairs(&mut self, centres: &[Vec3], radii: &[f64], out: &mut Vec<(u32, u32)>) {
        let n = centres.len();
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
        self.fine.build(centres, radii, cell);
        // Item `i` at `p` with radius `ri` finds its pairs in the columns of cells
        // within `reach` cells around it.
        let scan =
            |bins: &Bins, (i, p, ri): (usize, Vec3, f64), reach: i64, out: &mut Vec<(u32, u32)>| {
                let (cx, cy, cz) = bins.key(&p);
                for dx in -reach..=reach {
                    for dy in -reach..=reach {
                        bins.column(
                            (cx + dx, cy + dy),
                            (cz - reach, cz + reach),
                            &mut |js, pk| {
                                for (&j, q) in js.iter().zip(pk) {
                                    let (j, rj) = (j as usize, q[3]);
                                    // The larger radius finds the pair (ties: the lower index).
                                    if rj > ri || (rj == ri && j <= i) {
                                        continue;
                                    }
                                    let reach = ri + rj;
                                    if (Vec3::new(q[0], q[1], q[2]) - p).norm_squared()
                                        < reach * reach
                                    {
                                        out.push((i.min(j) as u32, i.max(j) as u32));
                                    }
                                }
                            },
                        );
                    }
                }
            };
        // (In cell order: neighbours searched one after another share their cells.)
        let fine = &self.fine;
        for (&i, q) in fine.items.iter().zip(&fine.packed) {
            let r = q[3];
            if !big(r) {
                let reach = (2.0 * r / cell).ceil() as i64;
                scan(
                    fine,
                    (i as usize, Vec3::new(q[0], q[1], q[2]), r),
                    reach,
                    out,
                );
            }
        }
        if let Some(r_big) = r_big {
            self.coarse.build(centres, radii, 2.0 * r_big);
            for (i, &r) in radii.iter().enumerate() {
                if big(r) {
                    scan(&self.coarse, (i, centres[i], r), 1, out);
                }
            }
        }
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

    /// `n` centres uniform in the box `lo..hi`; radii mostly small, every `big`-th very
    /// large (a fast shot's reach), the next one a fixed value (equal-radius ties).
    fn cloud(
        rng: &mut rand_chacha::ChaCha8Rng,
        n: usize,
        lo: Vec3,
        hi: Vec3,
        big: usize,
    ) -> (Vec<Vec3>, Vec<f64>) {
        let centres = (0..n)
            .map(|_| Vec3::from_fn(|a, _| rng.random_range(lo[a]..hi[a])))
            .collect();
        let radii = (0..n)
            .map(|k| match k % big {
                0 => rng.random_range(2e-3..6e-3),
                1 => 4e-4,
                _ => rng.random_range(2e-4..8e-4),
            })
            .collect();
        (centres, radii)
    }

    /// A nozzle stream: 400 shots strung along 0.2 m in a 3 mm column, a few with large
    /// reach (fast shots).
    fn stream(rng: &mut rand_chacha::ChaCha8Rng) -> (Vec<Vec3>, Vec<f64>) {
        cloud(
            rng,
            400,
            Vec3::new(-1.5e-3, -1.5e-3, 0.0),
            Vec3::new(1.5e-3, 1.5e-3, 0.2),
            23,
        )
    }

    /// The public call's pairs, checked against brute force, and whether it swept.
    fn checked(
        cells: &mut CellList,
        centres: &[Vec3],
        radii: &[f64],
        swept: bool,
        what: &str,
    ) -> Vec<(u32, u32)> {
        let got = cells.pairs(centres, radii);
        assert_eq!(got, brute(centres, radii), "{what}");
        assert_eq!(cells.swept, swept, "{what}: swept");
        got
    }

    #[test]
    fn matches_brute_force_for_mixed_radii_in_both_layouts() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for trial in 0..20 {
            let (centres, radii) = cloud(
                &mut rng,
                300,
                Vec3::new(-0.01, -0.01, 0.0),
                Vec3::new(0.01, 0.01, 0.02),
                17,
            );
            let mut cells = CellList::default();
            let got = checked(
                &mut cells,
                &centres,
                &radii,
                false,
                &format!("trial {trial}: a compact cloud"),
            );
            assert!(!got.is_empty());
            // Spread over a box too large for a dense grid (the hashed layout): two
            // clumps a metre apart.
            let far = Vec3::new(1.0, 1.0, 1.0);
            let spread: Vec<Vec3> = (0..centres.len())
                .map(|k| centres[k] + far * (k % 2) as f64)
                .collect();
            let mut cells = CellList::default();
            let mut got = Vec::new();
            cells.cell_pairs(&spread, &radii, &mut got);
            got.sort_unstable();
            assert!(
                !cells.fine.dense,
                "trial {trial}: the grid should be hashed"
            );
            assert_eq!(got, brute(&spread, &radii), "trial {trial}, spread");
            // The public call sweeps this layout (two clumps far apart along a diagonal).
            checked(
                &mut cells,
                &spread,
                &radii,
                true,
                &format!("trial {trial}: two far clumps"),
            );
        }
    }

    #[test]
    fn a_stream_is_swept_and_a_bunched_layout_falls_back_to_cells() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for trial in 0..20 {
            // A nozzle stream, interval ends landing on each other's starts.
            let (mut centres, radii) = stream(&mut rng);
            // Exact touching along the axis: item 2's interval starts where item 3's ends.
            centres[2] = Vec3::new(0.0, 0.0, 0.1);
            centres[3] = Vec3::new(0.0, 0.0, 0.1 - radii[2] - radii[3]);
            let mut cells = CellList::default();
            let got = checked(
                &mut cells,
                &centres,
                &radii,
                true,
                &format!("trial {trial}: a stream"),
            );
            assert!(!got.is_empty());
            // Most of them bunched in a millimetre at one end, a few spread far along the
            // axis: the bounding box looks sparse, the sweep exceeds its budget.
            let bunched: Vec<Vec3> = centres
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    if k % 40 == 0 {
                        *c
                    } else {
                        Vec3::new(c.x * 0.3, c.y * 0.3, c.z * 5e-3)
                    }
                })
                .collect();
            checked(
                &mut cells,
                &bunched,
                &radii,
                false,
                &format!("trial {trial}: a bunched layout"),
            );
        }
    }

    #[test]
    fn tracked_calls_reuse_the_previous_order_and_find_the_same_pairs() {
        // A stream moving on between calls, shots leaving at one end and entering at the
        // other: each tracked call starts from the previous order (sorted again by
        // insertion) and finds exactly the brute-force pairs. A call whose items jumped
        // far (the order reversed) gives up the insertion sort and still finds them.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let (mut centres, radii) = stream(&mut rng);
        let mut ids: Vec<usize> = (0..400).collect();
        let mut next = 400;
        let zeros = vec![0.0; 400];
        let mut cells = CellList::default();
        for call in 0..12 {
            let got = cells.pairs_tracked(
                &centres,
                &radii[..centres.len()],
                &ids,
                &zeros[..centres.len()],
            );
            assert_eq!(got, brute(&centres, &radii[..centres.len()]), "call {call}");
            assert!(cells.swept, "call {call}: swept");
            assert_eq!(cells.reused, call > 0, "call {call}: order reused");
            // Move on by up to a diameter, drop the three oldest, add three new ones.
            for c in centres.iter_mut() {
                c.z += rng.random_range(-2e-3..2e-3);
            }
            centres.drain(..3);
            ids.drain(..3);
            for _ in 0..3 {
                centres.push(Vec3::new(0.0, 0.0, rng.random_range(0.0..0.2)));
                ids.push(next);
                next += 1;
            }
        }
        for c in centres.iter_mut() {
            c.z = 0.2 - c.z;
        }
        let got = cells.pairs_tracked(
            &centres,
            &radii[..centres.len()],
            &ids,
            &zeros[..centres.len()],
        );
        assert_eq!(got, brute(&centres, &radii[..centres.len()]), "reversed");
        assert!(cells.swept && !cells.reused, "reversed: a full sort");
    }

    #[test]
    fn a_dense_cloud_reuses_its_skin_and_finds_the_same_pairs() {
        // A compact cloud of shots (0.2 mm radius, reach up to 5 um) drifting by up to a
        // micrometre per call in random directions, radii changing every call, as a
        // dense pile's short windows. Each call must find exactly the brute-force pairs,
        // whether it searched or filtered the skin's; most filter, some search again (a
        // shot left its widened ball), and a call with other ids always searches. Then
        // the shots move a diameter per call, as a stream's: no widened search is ever
        // filtered, and they back off to one in 64 calls.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
        let n = 600;
        let (mut centres, _) = cloud(
            &mut rng,
            n,
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(6e-3, 6e-3, 3e-3),
            1_000_000,
        );
        let mut ids: Vec<usize> = (0..n).collect();
        let skin = vec![2e-5; n];
        let mut cells = CellList::default();
        let (mut skinned, mut searched) = (0, 0);
        for call in 0..400 {
            let radii: Vec<f64> = (0..centres.len())
                .map(|_| 2e-4 + rng.random_range(0.0..5e-6))
                .collect();
            let got = cells.pairs_tracked(&centres, &radii, &ids, &skin[..centres.len()]);
            assert_eq!(got, brute(&centres, &radii), "call {call}");
            if cells.skinned {
                skinned += 1;
            } else {
                searched += 1;
            }
            if call == 200 {
                // One shot leaves: the next call has other ids and searches.
                centres.remove(7);
                ids.remove(7);
                let got = cells.pairs_tracked(&centres, &radii[1..], &ids, &skin[1..]);
                assert_eq!(got, brute(&centres, &radii[1..]), "after the change");
                assert!(!cells.skinned, "a call with other ids searches");
            }
            for c in centres.iter_mut() {
                *c += Vec3::from_fn(|_, _| rng.random_range(-1e-6..1e-6));
            }
            // Now and then one shot is kicked half a diameter: into new pairs.
            if call % 20 == 10 {
                let k = rng.random_range(0..centres.len());
                centres[k] += Vec3::from_fn(|_, _| rng.random_range(-2e-4..2e-4));
            }
        }
        assert!(skinned > 300, "skinned {skinned} of 400");
        assert!(searched > 20, "searched {searched} of 400");
        let mut widened = 0;
        for call in 0..400 {
            let radii = vec![2e-4; centres.len()];
            let held = cells.skin.held;
            let got = cells.pairs_tracked(&centres, &radii, &ids, &skin[..centres.len()]);
            assert_eq!(got, brute(&centres, &radii), "fast call {call}");
            if !held && cells.skin.held {
                widened += 1;
            }
            for c in centres.iter_mut() {
                *c += Vec3::from_fn(|_, _| rng.random_range(-4e-4..4e-4));
            }
        }
        assert!(!cells.skinned);
        // Widened after waits of 2, 4, ..., 64 calls, then once every 65.
        assert!(
            (7..=12).contains(&widened),
            "widened {widened} times in 400 fast calls"
        );
    }
}
