//! The cheapest split so far (`Best`, which the binned SAH shares), and the
//! exact sweep SAH that finishes the builder below
//! [`SWEEP_MAX`](super::SWEEP_MAX) objects: every split between sorted
//! centroids on each axis.

use super::*;

/// Cheapest split found so far. Costs are nudged by the imbalance |nl - nr|
/// (1e-6 relative, plus 1e-30 absolute for zero costs), so near-ties go to
/// the more balanced split: identical boxes or points on a line have equal
/// (often zero) costs everywhere, and taking the first would peel off one
/// object per level. Branch-free in the sweep's inner loop.
#[derive(Clone, Copy)]
pub(super) struct Best {
    pub(super) key: f32,
    pub(super) axis: usize,
    pub(super) pos: usize,
}

impl Best {
    pub(super) const NONE: Best = Best { key: f32::INFINITY, axis: 0, pos: 0 };
    /// NaN costs fail the comparison and are never taken.
    pub(super) fn offer(&mut self, cost: f32, imbalance: usize, axis: usize, pos: usize) {
        let imb = imbalance as f32;
        let key = cost * (1.0 + 1e-6 * imb) + 1e-30 * imb;
        if key < self.key {
            *self = Best { key, axis, pos };
        }
    }
}

/// Total order of f32 as u32 (same as `f32::total_cmp`), for integer sorts.
fn sort_key(f: f32) -> u32 {
    let b = f.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// State of an exact sweep-SAH build of <= SWEEP_MAX objects: centroids are
/// sorted once per axis and each split stably partitions the three orders
/// (the O(n log n) scheme of Wald & Havran 2006, in miniature), so no node
/// sorts again. Objects are referred to by local u8 index.
pub(super) struct Sweep<'a> {
    pub(super) prims: &'a [Prim],
    pub(super) bounds: [Bounds; SWEEP_MAX],
    pub(super) order: [[u8; SWEEP_MAX]; 3],
    pub(super) scale: f32,
}

impl<'a> Sweep<'a> {
    pub(super) fn new(prims: &'a [Prim]) -> Self {
        let n = prims.len();
        debug_assert!(n <= SWEEP_MAX);
        let mut bounds = [Bounds::EMPTY; SWEEP_MAX];
        let mut all = Bounds::EMPTY;
        for (b, p) in bounds.iter_mut().zip(prims) {
            *b = p.bounds();
            all = all.union(*b);
        }
        let mut order = [[0u8; SWEEP_MAX]; 3];
        for (a, ord) in order.iter_mut().enumerate() {
            let mut keys = [0u64; SWEEP_MAX];
            for (i, (k, p)) in keys.iter_mut().zip(prims).enumerate() {
                *k = (sort_key(p.c(a)) as u64) << 8 | i as u64;
            }
            keys[..n].sort_unstable();
            for (o, k) in ord.iter_mut().zip(&keys[..n]) {
                *o = *k as u8;
            }
        }
        // One scale for the whole small subtree: its areas relative to its
        // root only underflow for objects ~1e-19 of its size, where any
        // split is as good as another.
        Sweep { prims, bounds, order, scale: area_scale(&all) }
    }

    /// Splits the objects at `order[*][lo..hi]` (n >= 2) at the cheapest
    /// position on any axis; returns the split position, lo < k < hi.
    pub(super) fn split(&mut self, lo: usize, hi: usize) -> usize {
        let n = hi - lo;
        if n == 2 {
            return lo + 1;
        }
        let s = self.scale;
        let b = &self.bounds;
        let ord = &self.order;
        // The three axes advance in lockstep: independent dependency chains.
        let mut right = [[0f32; 3]; SWEEP_MAX];
        let mut acc = [Bounds::EMPTY; 3];
        for i in (lo + 1..hi).rev() {
            for a in 0..3 {
                acc[a] = acc[a].union(b[ord[a][i] as usize]);
                right[i][a] = acc[a].half_area(s) * (hi - i) as f32;
            }
        }
        // NaN costs never win; the default is then a median on axis 0.
        let mut best = Best { pos: lo + n / 2, ..Best::NONE };
        let mut acc = [Bounds::EMPTY; 3];
        for i in lo + 1..hi {
            for a in 0..3 {
                acc[a] = acc[a].union(b[ord[a][i - 1] as usize]);
                let cost = acc[a].half_area(s) * (i - lo) as f32 + right[i][a];
                best.offer(cost, (2 * (i - lo)).abs_diff(n), a, i);
            }
        }
        let Best { axis, pos: k, .. } = best;
        let mut left = [false; SWEEP_MAX];
        for &i in &self.order[axis][lo..k] {
            left[i as usize] = true;
        }
        for (a, ord) in self.order.iter_mut().enumerate() {
            if a == axis {
                continue;
            }
            let mut tmp = [0u8; SWEEP_MAX];
            let (mut l, mut r) = (0, k - lo);
            for &i in &ord[lo..hi] {
                let slot = if left[i as usize] { &mut l } else { &mut r };
                tmp[*slot] = i;
                *slot += 1;
            }
            ord[lo..hi].copy_from_slice(&tmp[..n]);
        }
        k
    }
}
