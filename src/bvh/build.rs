//! Top-down builders (thesis Table 4: SAH, MID, EQ), one leaf per object.
//!
//! Nodes are written straight into the final layout: a subtree of `n` leaves
//! owns `2n - 1` nodes, so once a node is split into `nl` and `n - nl`
//! objects, the ranges of both child subtrees are known and they are built
//! in parallel (`rayon::join`) into disjoint slices. No temporary tree, no
//! flattening pass.
//!
//! Robustness: every split puts at least one object on each side (any
//! heuristic that would not falls back to an equal-count split), so the
//! recursion ends for all inputs, NaN included. Cost comparisons use
//! `<` and `total_cmp`, which never panic on NaN; a NaN cost simply loses.

use glam::{Vec3A, Vec4};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

use super::{BvhNode, Split, LEAF_BIT, NO_PARENT};
use crate::scene::Aabb;

/// Bins of the binned SAH (Wald 2007); 32 keeps its cost within ~1% of a
/// full sweep on the nodes it is used for.
const BINS: usize = 32;
/// Nodes this small get an exact sweep SAH over sorted centroids: binning
/// costs O(bins) per node, which dominates near the leaves.
const SWEEP_MAX: usize = 32;
/// Keeps the index lane of [`Prim`] a normal float (exponent >= 128).
const INDEX_TAG: u32 = 0x4000_0000;
/// Subtrees smaller than this are built on the calling thread.
const PAR_MIN: usize = 2048;
/// Nodes at least this large bin their objects in parallel chunks.
const PAR_BIN_MIN: usize = 1 << 15;

/// Working copy of an object's box; `lo.w` holds the object index so that
/// partitioning moves one 32-byte value. The SIMD math runs on all four lanes,
/// so the index is stored with bit 30 set: raw small integers are denormal
/// floats, and every add/mul on a denormal costs a ~100-cycle microcode assist
/// (it made the first version 10x slower).
#[derive(Clone, Copy)]
struct Prim {
    lo: Vec4,
    hi: Vec4,
}

impl Prim {
    fn min(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }
    fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }
    fn new(b: &Aabb, object: u32) -> Prim {
        Prim { lo: b.min.extend(f32::from_bits(object | INDEX_TAG)), hi: b.max.extend(0.0) }
    }
    fn object(&self) -> u32 {
        self.lo.w.to_bits() & !INDEX_TAG
    }
    /// Halves first so that ±f32::MAX boxes do not overflow.
    fn centroid(&self) -> Vec3A {
        self.min() * 0.5 + self.max() * 0.5
    }
    fn c(&self, axis: usize) -> f32 {
        self.lo[axis] * 0.5 + self.hi[axis] * 0.5
    }
}

/// Box accumulator on SIMD vectors.
#[derive(Clone, Copy)]
struct Bounds {
    min: Vec3A,
    max: Vec3A,
}

impl Bounds {
    const EMPTY: Bounds = Bounds { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };
    fn grow(&mut self, min: Vec3A, max: Vec3A) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }
    fn grow_prim(&mut self, p: &Prim) {
        self.grow(p.min(), p.max());
    }
    fn union(mut self, o: Bounds) -> Bounds {
        self.grow(o.min, o.max);
        self
    }
    fn extent(&self) -> Vec3A {
        (self.max - self.min).max(Vec3A::ZERO)
    }
    /// Half surface area with extents multiplied by `s` (the node's
    /// 1/extent), so f32 neither overflows at ±1e30 nor underflows deep down.
    fn half_area(&self, s: f32) -> f32 {
        let e = (self.max * s - self.min * s).max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

fn centroid_bounds(prims: &[Prim]) -> Bounds {
    let f = |b: Bounds, p: &Prim| {
        let c = p.centroid();
        Bounds { min: b.min.min(c), max: b.max.max(c) }
    };
    if prims.len() >= PAR_BIN_MIN {
        prims.par_chunks(4096).map(|ch| ch.iter().fold(Bounds::EMPTY, f)).reduce(|| Bounds::EMPTY, Bounds::union)
    } else {
        prims.iter().fold(Bounds::EMPTY, f)
    }
}

/// Scale for the area terms of a node with these bounds.
fn area_scale(b: &Bounds) -> f32 {
    let s = 1.0 / b.extent().max_element();
    if s.is_finite() && s > 0.0 {
        s
    } else {
        1.0 // zero extent (all areas are 0 anyway) or overflowed extent
    }
}

pub(super) fn build(boxes: &[Aabb], split: Split) -> (Vec<BvhNode>, Vec<u32>) {
    let n = boxes.len();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    assert!(n <= (LEAF_BIT / 2) as usize, "BVH holds at most 2^30 objects");
    let mut prims: Vec<Prim> = boxes
        .par_iter()
        .enumerate()
        .with_min_len(4096)
        .map(|(i, b)| Prim::new(b, i as u32))
        .collect();
    let mut nodes = vec![BvhNode { min: [0.0; 3], child: 0, max: [0.0; 3], parent: 0 }; 2 * n - 1];
    let leaf_of = Builder { split, leaf_of: (0..n).map(|_| AtomicU32::new(u32::MAX)).collect() };
    let (root, rest) = nodes.split_first_mut().expect("n >= 1");
    *root = if n == 1 {
        leaf_of.leaf(&prims[0], 0, NO_PARENT)
    } else {
        let cb = centroid_bounds(&prims);
        let b = leaf_of.subtree(&mut prims, cb, rest, 1, 0);
        node(&b, 1, NO_PARENT)
    };
    let leaf_of_object = leaf_of.leaf_of.into_iter().map(AtomicU32::into_inner).collect();
    (nodes, leaf_of_object)
}

fn node(b: &Bounds, child: u32, parent: u32) -> BvhNode {
    BvhNode { min: b.min.to_array(), child, max: b.max.to_array(), parent }
}

struct Builder {
    split: Split,
    /// Written once per object from whichever thread makes its leaf.
    leaf_of: Vec<AtomicU32>,
}

impl Builder {
    fn leaf(&self, p: &Prim, index: u32, parent: u32) -> BvhNode {
        let o = p.object();
        self.leaf_of[o as usize].store(index, Ordering::Relaxed);
        // The object's own box, bit for bit (validate() checks equality).
        BvhNode { min: p.lo.truncate().to_array(), child: LEAF_BIT | o, max: p.hi.truncate().to_array(), parent }
    }

    /// Builds the descendants of node `me` (which holds `prims`, n >= 2) into
    /// `out` (2n - 2 nodes, global index `base` = the children's pair) and
    /// returns the bounds of `prims`. Depth-first pair allocation: the left
    /// child's subtree follows the pair, then the right child's.
    fn subtree(&self, prims: &mut [Prim], cb: Bounds, out: &mut [BvhNode], base: u32, me: u32) -> Bounds {
        let n = prims.len();
        debug_assert!(n >= 2 && out.len() == 2 * n - 2);
        let (nl, child_cb) = self.split(prims, &cb);
        debug_assert!(nl >= 1 && nl < n);
        let (lp, rp) = prims.split_at_mut(nl);
        let (pair, desc) = out.split_at_mut(2);
        let (ld, rd) = desc.split_at_mut(2 * nl - 2);
        let (lcb, rcb) = child_cb.map_or((None, None), |(l, r)| (Some(l), Some(r)));
        let (lbase, rbase) = (base + 2, base + 2 * nl as u32);
        let mut left = move || self.child(lp, lcb, ld, lbase, base, me);
        let mut right = move || self.child(rp, rcb, rd, rbase, base + 1, me);
        let ((lb, ln), (rb, rn)) = if n >= PAR_MIN { rayon::join(left, right) } else { (left(), right()) };
        pair[0] = ln;
        pair[1] = rn;
        lb.union(rb)
    }

    /// Node `me` (child of `parent`) holding `prims`; returns its bounds and node.
    fn child(&self, prims: &mut [Prim], cb: Option<Bounds>, out: &mut [BvhNode], base: u32, me: u32, parent: u32) -> (Bounds, BvhNode) {
        if let [p] = prims {
            let b = Bounds { min: p.min(), max: p.max() };
            return (b, self.leaf(p, me, parent));
        }
        let cb = cb.unwrap_or_else(|| centroid_bounds(prims));
        let b = self.subtree(prims, cb, out, base, me);
        (b, node(&b, base, parent))
    }

    /// Reorders `prims` and returns the left count (1..n) and, when known for
    /// free, the children's centroid bounds.
    fn split(&self, prims: &mut [Prim], cb: &Bounds) -> (usize, Option<(Bounds, Bounds)>) {
        let n = prims.len();
        if n == 2 {
            return (1, None);
        }
        let found = match self.split {
            Split::Sah if n <= SWEEP_MAX => sweep_sah(prims).map(|nl| (nl, None)),
            Split::Sah => binned_sah(prims, cb),
            Split::Mid => middle(prims, cb),
            Split::Eq => None,
        };
        found.filter(|&(nl, _)| nl > 0 && nl < n).unwrap_or_else(|| (equal_counts(prims, cb), None))
    }
}

/// Median on the longest centroid axis; when all centroids coincide any
/// halving is as good as another and the order is left as is.
fn equal_counts(prims: &mut [Prim], cb: &Bounds) -> usize {
    let mid = prims.len() / 2;
    let e = cb.max - cb.min;
    // `e.max_element() > 0` is false for NaN and zero extents alike.
    if e.max_element() > 0.0 {
        let axis = e.max_position();
        prims.select_nth_unstable_by(mid, |a, b| a.c(axis).total_cmp(&b.c(axis)));
    }
    mid
}

/// Hoare partition; evaluates `left` exactly once per element, which lets
/// the predicate accumulate per-side data.
fn partition(prims: &mut [Prim], mut left: impl FnMut(&Prim) -> bool) -> usize {
    // prims[..i] go left, prims[j..] go right, [i, j) is unexamined.
    let (mut i, mut j) = (0, prims.len());
    loop {
        while i < j && left(&prims[i]) {
            i += 1;
        }
        if i == j {
            return i;
        }
        // prims[i] goes right; look for a left one from the end.
        j -= 1;
        while i < j && !left(&prims[j]) {
            j -= 1;
        }
        if i == j {
            return i;
        }
        prims.swap(i, j);
        i += 1;
    }
}

/// Partition that also returns both sides' centroid bounds.
fn partition_cb(prims: &mut [Prim], left: impl Fn(Vec3A) -> bool) -> (usize, Option<(Bounds, Bounds)>) {
    let (mut lb, mut rb) = (Bounds::EMPTY, Bounds::EMPTY);
    let nl = partition(prims, |p| {
        let c = p.centroid();
        let l = left(c);
        let b = if l { &mut lb } else { &mut rb };
        b.grow(c, c);
        l
    });
    (nl, Some((lb, rb)))
}

/// MID: spatial middle of the centroid bounds on the longest axis.
fn middle(prims: &mut [Prim], cb: &Bounds) -> Option<(usize, Option<(Bounds, Bounds)>)> {
    let e = cb.max - cb.min;
    if !(e.max_element() > 0.0) {
        return None;
    }
    let axis = e.max_position();
    let mid = cb.min[axis] * 0.5 + cb.max[axis] * 0.5;
    Some(partition_cb(prims, |c| c[axis] < mid))
}

#[derive(Clone, Copy)]
struct Bin {
    b: Bounds,
    n: u32,
}

type Bins = [[Bin; BINS]; 3];
const EMPTY_BINS: Bins = [[Bin { b: Bounds::EMPTY, n: 0 }; BINS]; 3];

/// Maps centroids to bins on all three axes; a zero scale (flat axis)
/// sends everything to bin 0. NaN maps to 0 too (`as` saturates).
#[derive(Clone, Copy)]
struct Binner {
    min: Vec3A,
    scale: Vec3A,
}

impl Binner {
    fn index(&self, c: Vec3A) -> glam::UVec3 {
        ((c - self.min) * self.scale).as_uvec3().min(glam::UVec3::splat(BINS as u32 - 1))
    }
    fn bin(&self, prims: &[Prim]) -> Bins {
        let mut bins = EMPTY_BINS;
        for p in prims {
            let k = self.index(p.centroid());
            let (min, max) = (p.min(), p.max());
            for a in 0..3 {
                let bin = &mut bins[a][k[a] as usize];
                bin.b.grow(min, max);
                bin.n += 1;
            }
        }
        bins
    }
}

fn merge_bins(mut a: Bins, b: Bins) -> Bins {
    for (x, y) in a.iter_mut().flatten().zip(b.iter().flatten()) {
        x.b = x.b.union(y.b);
        x.n += y.n;
    }
    a
}

/// Binned SAH over all three axes (cost = A_L·N_L + A_R·N_R; one object per
/// leaf, so no leaf-cost termination). Returns None when no plane separates
/// the objects (coincident centroids, NaN).
fn binned_sah(prims: &mut [Prim], cb: &Bounds) -> Option<(usize, Option<(Bounds, Bounds)>)> {
    let e = cb.max - cb.min;
    // Slightly under BINS so the largest centroid still lands in the last bin.
    let scale = Vec3A::select(e.cmpgt(Vec3A::ZERO), Vec3A::splat(BINS as f32 * 0.9999) / e, Vec3A::ZERO);
    let scale = Vec3A::select(scale.is_finite_mask(), scale, Vec3A::ZERO);
    if scale.cmpeq(Vec3A::ZERO).all() {
        return None;
    }
    let binner = Binner { min: cb.min, scale };
    let bins = if prims.len() >= PAR_BIN_MIN {
        prims.par_chunks(8192).map(|ch| binner.bin(ch)).reduce(|| EMPTY_BINS, merge_bins)
    } else {
        binner.bin(prims)
    };
    let node = bins[0].iter().fold(Bounds::EMPTY, |b, x| b.union(x.b));
    let s = area_scale(&node);
    let mut best = (f32::INFINITY, 0usize, 0usize); // cost, axis, first right bin
    for (a, bins) in bins.iter().enumerate() {
        if scale[a] == 0.0 {
            continue;
        }
        let mut right = [0f32; BINS];
        let (mut acc, mut cnt) = (Bounds::EMPTY, 0u32);
        for i in (1..BINS).rev() {
            acc = acc.union(bins[i].b);
            cnt += bins[i].n;
            right[i] = if cnt > 0 { acc.half_area(s) * cnt as f32 } else { f32::NAN };
        }
        let (mut acc, mut cnt) = (Bounds::EMPTY, 0u32);
        for i in 1..BINS {
            acc = acc.union(bins[i - 1].b);
            cnt += bins[i - 1].n;
            // NaN (empty right side) and empty left sides never win.
            let cost = acc.half_area(s) * cnt as f32 + right[i];
            if cnt > 0 && cost < best.0 {
                best = (cost, a, i);
            }
        }
    }
    if !best.0.is_finite() {
        return None;
    }
    let (_, axis, split) = best;
    Some(partition_cb(prims, |c| {
        (((c[axis] - binner.min[axis]) * binner.scale[axis]) as u32).min(BINS as u32 - 1) < split as u32
    }))
}

/// Exact SAH for small nodes: sort by centroid on each axis and sweep every
/// split position. Both sides are non-empty by construction.
fn sweep_sah(prims: &mut [Prim]) -> Option<usize> {
    let n = prims.len();
    let node = prims.iter().fold(Bounds::EMPTY, |mut b, p| {
        b.grow_prim(p);
        b
    });
    let s = area_scale(&node);
    let mut right = [0f32; SWEEP_MAX];
    let mut best = (f32::INFINITY, usize::MAX, 0usize);
    for axis in 0..3 {
        prims.sort_unstable_by(|a, b| a.c(axis).total_cmp(&b.c(axis)));
        let mut acc = Bounds::EMPTY;
        for i in (1..n).rev() {
            acc.grow_prim(&prims[i]);
            right[i] = acc.half_area(s) * (n - i) as f32;
        }
        let mut acc = Bounds::EMPTY;
        for i in 1..n {
            acc.grow_prim(&prims[i - 1]);
            let cost = acc.half_area(s) * i as f32 + right[i];
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let (_, axis, i) = best;
    if axis == usize::MAX {
        return None;
    }
    if axis != 2 {
        prims.sort_unstable_by(|a, b| a.c(axis).total_cmp(&b.c(axis)));
    }
    Some(i)
}
