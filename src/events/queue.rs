//! The event queue: a calendar queue (time buckets; the current one a binary heap).
//!
//! Every event of a run falls in `[0, end]`, so the buckets tile that span and nothing
//! wraps around. An event goes to the bucket of its time (an event in the past, to the
//! current bucket); `pop` empties buckets in order. Bucket indices are monotone in time,
//! so the pop order is exactly that of one binary heap over all events (ties included:
//! the items' own order decides), but a pop touches one small heap instead of
//! descending a large one (the event scheduler's queue holds about ten stale predictions
//! per shot; as one heap, popping it was 15 % of the pack stream's run time, mostly
//! cache misses).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A min-queue of items ordered by `Ord`, keyed for bucketing by a time in `[0, end]`.
///
/// Only the current bucket is a heap; a later bucket is a plain list that becomes the
/// heap when it is reached (heapified in linear time). A push into the future is then
/// one append, where a heap push would sift through storage that is cold by the time
/// its bucket comes up (measured: the 200,000-shot pack stream spent 10.7 % of its run
/// in heap pushes).
#[derive(Debug)]
pub struct Calendar<T: Ord> {
    /// Later buckets, unordered; `buckets[current]` is empty (its items are in `heap`).
    buckets: Vec<Vec<Reverse<T>>>,
    /// The current bucket's items, and items pushed with times before its end.
    heap: BinaryHeap<Reverse<T>>,
    /// Bucket width, s.
    width: f64,
    /// The bucket `heap` holds.
    current: usize,
    len: usize,
}

impl<T: Ord> Calendar<T> {
    /// A queue for times in `[0, end]` with `buckets` buckets (at least one).
    pub fn new(end: f64, buckets: usize) -> Self {
        let nb = buckets.max(1);
        let width = if end > 0.0 { end / nb as f64 } else { 1.0 };
        Calendar {
            buckets: (0..nb).map(|_| Vec::new()).collect(),
            heap: BinaryHeap::new(),
            width,
            current: 0,
            len: 0,
        }
    }

    /// Items queued.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no item is queued.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Queues `item` at time `t` (times past the end go to the last bucket).
    pub fn push(&mut self, t: f64, item: T) {
        let b = if t.is_nan() {
            self.buckets.len() - 1
        } else {
            ((t / self.width).max(0.0) as usize).min(self.buckets.len() - 1)
        };
        if b <= self.current {
            self.heap.push(Reverse(item));
        } else {
            self.buckets[b].push(Reverse(item));
        }
        self.len += 1;
    }

    /// The smallest item.
    pub fn pop(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        while self.heap.is_empty() {
            // Reach the next bucket: its list becomes the heap (a bucket left behind is
            // never used again, so memory follows the queued events, as with one heap).
            self.current += 1;
            self.heap = BinaryHeap::from(std::mem::take(&mut self.buckets[self.current]));
        }
        self.len -= 1;
        self.heap.pop().map(|Reverse(x)| x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Item(f64, u32);
    impl Eq for Item {}
    impl Ord for Item {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&o.0).then(self.1.cmp(&o.1))
        }
    }
    impl PartialOrd for Item {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }

    /// Interleaved pushes (future, past and tied times) and pops come out exactly as
    /// from one binary heap.
    #[test]
    fn pops_in_the_order_of_one_heap() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for buckets in [1, 3, 64, 4096] {
            let end = 1e-4;
            let mut cal = Calendar::new(end, buckets);
            let mut heap = BinaryHeap::new();
            let mut now = 0.0f64;
            let mut popped = 0;
            for step in 0..20_000u32 {
                if rng.random_bool(0.55) {
                    let t = match rng.random_range(0..10) {
                        0 => now - rng.random_range(0.0..1e-6), // in the past
                        1 => now,                               // a tie with "now"
                        2 => end,
                        _ => (now + rng.random_range(0.0..2e-5)).min(end),
                    };
                    let it = Item(t, step % 5);
                    cal.push(t, it);
                    heap.push(Reverse(it));
                } else {
                    let a = cal.pop();
                    let b = heap.pop().map(|Reverse(x)| x);
                    assert_eq!(a, b, "{buckets} buckets, step {step}");
                    if let Some(x) = a {
                        now = now.max(x.0);
                        popped += 1;
                    }
                }
                assert_eq!(cal.len(), heap.len());
            }
            while let Some(Reverse(x)) = heap.pop() {
                assert_eq!(cal.pop(), Some(x));
            }
            assert!(cal.is_empty() && cal.pop().is_none());
            assert!(popped > 5_000);
        }
    }
}
