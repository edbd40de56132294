//! Top-down builders (Lee's thesis, Table 4: SAH, MID, EQ), one leaf per object.
//!
//! SAH: binned SAH over all three axes (32 bins, 16 below 256 objects) down
//! to 32 objects, then an exact sweep SAH. On 120k random boxes this gives a
//! lower SAH cost than obvhs 0.4's fastest and medium presets (PLOC +
//! reinsertion), built faster than medium (`examples/bvh_build.rs`). MID and
//! EQ are the alternatives of Lee's thesis: centroid-bounds middle, and median on
//! the longest axis.
//!
//! Nodes are written straight into the final layout: a subtree of `n` leaves
//! owns `2n - 1` nodes, so once a node is split into `nl` and `n - nl`
//! objects, the ranges of both child subtrees are known and they are built
//! in parallel (`rayon::join`) into disjoint slices. No temporary tree, no
//! flattening pass.
//!
//! Robustness: every split puts at least one object on each side (a
//! heuristic that would not falls back to an equal-count split), so the
//! recursion ends for all inputs, NaN included. Cost comparisons use `<` and
//! sorts use total orders, so NaN never panics; a NaN cost simply loses.

use glam::{Vec3A, Vec4};
#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// `rayon::join` with the `parallel` feature, else one after the other.
fn join<A: Send, B: Send>(a: impl FnOnce() -> A + Send, b: impl FnOnce() -> B + Send) -> (A, B) {
    #[cfg(feature = "parallel")]
    return rayon::join(a, b);
    #[cfg(not(feature = "parallel"))]
    return (a(), b());
}
use std::sync::atomic::{AtomicU32, Ordering};

use super::{huge_pages, BvhNode, Split, LEAF_BIT, NO_PARENT};
use crate::Aabb;

/// Bins of the binned SAH (Wald 2007) on large nodes.
const BINS: usize = 32;
/// Nodes below this many objects use BINS / 2 bins: each node pays
/// O(bins) to evaluate them, and near the leaves that dominates.
const FULL_BINS_MIN: usize = 256;
/// SAH subtrees this small are built by an exact sweep over presorted
/// centroids: exact splits where most of the tree's nodes are, without the
/// per-node cost of bins.
const SWEEP_MAX: usize = 32;
/// From this depth on only equal-count splits are made. That bounds the
/// recursion (and the GPU's traversal stacks) for adversarial inputs such as
/// exponentially spaced objects, where MID or SAH may peel off one object
/// per level: depth < 64 + 32 for any input of up to 2^30 objects.
const HEURISTIC_DEPTH: u32 = 64;
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
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
struct Prim {
    lo: Vec4,
    hi: Vec4,
}

impl Prim {
    fn new(b: &Aabb, object: u32) -> Prim {
        Prim { lo: b.min.extend(f32::from_bits(object | INDEX_TAG)), hi: b.max.extend(0.0) }
    }
    fn min(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }
    fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }
    fn bounds(&self) -> Bounds {
        Bounds { min: self.min(), max: self.max() }
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
    fn point(c: Vec3A) -> Bounds {
        Bounds { min: c, max: c }
    }
    fn union(self, o: Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
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

/// Scale for the area terms of a node with these bounds.
fn area_scale(b: &Bounds) -> f32 {
    let s = 1.0 / b.extent().max_element();
    if s.is_finite() && s > 0.0 {
        s
    } else {
        1.0 // zero extent (all areas are 0 anyway) or overflowed extent
    }
}

fn centroid_bounds(prims: &[Prim]) -> Bounds {
    let f = |b: Bounds, p: &Prim| b.union(Bounds::point(p.centroid()));
    if prims.len() >= PAR_BIN_MIN {
        {
            #[cfg(feature = "parallel")]
            let b = prims.par_chunks(4096).map(|ch| ch.iter().fold(Bounds::EMPTY, f)).reduce(|| Bounds::EMPTY, Bounds::union);
            #[cfg(not(feature = "parallel"))]
            let b = prims.iter().fold(Bounds::EMPTY, f);
            b
        }
    } else {
        prims.iter().fold(Bounds::EMPTY, f)
    }
}

pub(super) fn build(boxes: &[Aabb], split: Split) -> (Vec<BvhNode>, Vec<u32>) {
    let n = boxes.len();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    assert!(n <= (LEAF_BIT / 2) as usize, "BVH holds at most 2^30 objects");
    // Every buffer is allocated zeroed on huge pages and first touched by
    // the workers that fill it.
    let mut prims = huge_pages::zeroed_vec::<Prim>(n);
    #[cfg(feature = "parallel")]
    prims.par_iter_mut().zip(boxes).enumerate().with_min_len(4096).for_each(|(i, (p, b))| *p = Prim::new(b, i as u32));
    #[cfg(not(feature = "parallel"))]
    prims.iter_mut().zip(boxes).enumerate().for_each(|(i, (p, b))| *p = Prim::new(b, i as u32));
    // Out-of-place partitions ping-pong between `prims` and `scratch`.
    let mut scratch = huge_pages::zeroed_vec::<Prim>(if split == Split::Eq { 0 } else { n });
    let mut nodes = huge_pages::zeroed_vec::<BvhNode>(2 * n - 1);
    // Every object gets exactly one leaf, so the zeros are all overwritten.
    let builder = Builder { split, leaf_of: huge_pages::zeroed_vec(n) };
    let (root, rest) = nodes.split_first_mut().expect("n >= 1");
    let at = Place { me: 0, parent: NO_PARENT, base: 1, depth: 0 };
    builder.child(Work { prims: &mut prims, scratch: &mut scratch }, None, root, rest, at);
    let leaf_of_object = builder.leaf_of.into_iter().map(AtomicU32::into_inner).collect();
    (nodes, leaf_of_object)
}

fn node(b: &Bounds, child: u32, parent: u32) -> BvhNode {
    BvhNode { min: b.min.to_array(), child, max: b.max.to_array(), parent }
}

/// A node's objects and an equally long scratch area (empty for EQ, which
/// partitions in place).
struct Work<'a> {
    prims: &'a mut [Prim],
    scratch: &'a mut [Prim],
}

impl<'a> Work<'a> {
    /// Splits at `nl`; `moved` says the objects now live in `scratch`.
    fn split_at(self, nl: usize, moved: bool) -> (Work<'a>, Work<'a>) {
        let (prims, scratch) = if moved { (self.scratch, self.prims) } else { (self.prims, self.scratch) };
        let (lp, rp) = prims.split_at_mut(nl);
        let (ls, rs) = scratch.split_at_mut(nl.min(scratch.len()));
        (Work { prims: lp, scratch: ls }, Work { prims: rp, scratch: rs })
    }
}

/// A chosen split: left count, whether the objects moved to scratch, and
/// the children's centroid bounds when they came for free.
struct Cut {
    nl: usize,
    moved: bool,
    cbs: Option<(Bounds, Bounds)>,
}

/// Where a node goes: its own index, its parent's, the global index of its
/// children's pair (its subtree's first descendant), and its depth.
#[derive(Clone, Copy)]
struct Place {
    me: u32,
    parent: u32,
    base: u32,
    depth: u32,
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

    /// Builds the node at `at` holding `w.prims`: writes it to `slot` and its
    /// descendants to `out` (2n - 2 nodes, the first at `at.base`), and
    /// returns its bounds. Pairs are allocated depth first: the children's
    /// pair, then the left subtree, then the right.
    ///
    /// Nodes are stored in place, never returned: a returned node is written
    /// in pieces and reloaded whole, and the failed store forwarding cost
    /// ~25% of the sweep builder's time.
    fn child(&self, w: Work, cb: Option<Bounds>, slot: &mut BvhNode, out: &mut [BvhNode], at: Place) -> Bounds {
        let n = w.prims.len();
        if n == 1 {
            let p = &w.prims[0];
            *slot = self.leaf(p, at.me, at.parent);
            return p.bounds();
        }
        let b = if self.split == Split::Sah && n <= SWEEP_MAX && at.depth < HEURISTIC_DEPTH {
            self.sweep_subtree(w.prims, out, at.base, at.me)
        } else {
            let cb = cb.unwrap_or_else(|| centroid_bounds(w.prims));
            self.subtree(w, cb, out, at)
        };
        *slot = node(&b, at.base, at.parent);
        b
    }

    fn subtree(&self, mut w: Work, cb: Bounds, out: &mut [BvhNode], at: Place) -> Bounds {
        let n = w.prims.len();
        debug_assert!(n >= 2 && out.len() == 2 * n - 2);
        let cut = self.split(&mut w, &cb, at.depth);
        let nl = cut.nl;
        debug_assert!(nl >= 1 && nl < n);
        let (lw, rw) = w.split_at(nl, cut.moved);
        let ([ls, rs], desc) = out.split_first_chunk_mut::<2>().expect("n >= 2");
        let (ld, rd) = desc.split_at_mut(2 * nl - 2);
        let (lcb, rcb) = cut.cbs.map_or((None, None), |(l, r)| (Some(l), Some(r)));
        let depth = at.depth + 1;
        let lat = Place { me: at.base, parent: at.me, base: at.base + 2, depth };
        let rat = Place { me: at.base + 1, parent: at.me, base: at.base + 2 * nl as u32, depth };
        let left = move || self.child(lw, lcb, ls, ld, lat);
        let right = move || self.child(rw, rcb, rs, rd, rat);
        let (lb, rb) = if n >= PAR_MIN { join(left, right) } else { (left(), right()) };
        lb.union(rb)
    }

    fn split(&self, w: &mut Work, cb: &Bounds, depth: u32) -> Cut {
        let n = w.prims.len();
        if n == 2 {
            return Cut { nl: 1, moved: false, cbs: None };
        }
        let found = match self.split {
            _ if depth >= HEURISTIC_DEPTH => None,
            Split::Sah => binned_sah(w, cb),
            Split::Mid => middle(w, cb),
            Split::Eq => None,
        };
        match found {
            Some(cut) if cut.nl > 0 && cut.nl < n => cut,
            // Both heuristics only cut where bins/centroids say both sides
            // are non-empty, so this is for inputs like NaN.
            Some(Cut { moved, .. }) => {
                let prims = if moved { &mut *w.scratch } else { &mut *w.prims };
                Cut { nl: equal_counts(prims, cb), moved, cbs: None }
            }
            None => Cut { nl: equal_counts(w.prims, cb), moved: false, cbs: None },
        }
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

/// Branch-free out-of-place partition of `w.prims` into `w.scratch`: lefts
/// from the front, rights from the back. Every object is stored to both
/// ends and one cursor advances, which costs two stores instead of a ~50%
/// mispredicted branch (random boxes split unpredictably). Also returns the
/// centroid bounds of both sides.
fn partition(w: &mut Work, left: impl Fn(Vec3A) -> bool) -> Cut {
    let n = w.prims.len();
    let dst = &mut w.scratch[..n];
    let (mut l, mut r) = (0usize, n);
    for p in w.prims.iter() {
        let go = left(p.centroid());
        // l < r holds until the last object, where l == r - 1.
        dst[l] = *p;
        dst[r - 1] = *p;
        l += go as usize;
        r -= !go as usize;
    }
    // A second pass over the (cached) result is cheaper than tracking both
    // sides' bounds with selects in the loop above.
    let (lp, rp) = dst.split_at(l);
    Cut { nl: l, moved: true, cbs: Some((centroid_bounds(lp), centroid_bounds(rp))) }
}

/// MID: spatial middle of the centroid bounds on the longest axis.
fn middle(w: &mut Work, cb: &Bounds) -> Option<Cut> {
    let e = cb.max - cb.min;
    let widest = e.max_element();
    if widest.is_nan() || widest <= 0.0 {
        return None;
    }
    let axis = e.max_position();
    let mid = cb.min[axis] * 0.5 + cb.max[axis] * 0.5;
    Some(partition(w, |c| c[axis] < mid))
}

#[derive(Clone, Copy)]
struct Bin {
    b: Bounds,
    n: u32,
}

type Bins = [[Bin; BINS]; 3];
const EMPTY_BINS: Bins = [[Bin { b: Bounds::EMPTY, n: 0 }; BINS]; 3];

/// Maps centroids to `count` bins on all three axes; a zero scale (flat
/// axis) sends everything to bin 0, and so does NaN.
#[derive(Clone, Copy)]
struct Binner {
    min: Vec3A,
    scale: Vec3A,
    last: Vec3A,
}

impl Binner {
    /// Bin per axis (lane 3 is meaningless). Clamped in float first, so the
    /// conversion is a plain truncation; `max` returns its second operand
    /// for NaN, so NaN lands in bin 0.
    fn index(&self, c: Vec3A) -> [u32; 4] {
        truncate(((c - self.min) * self.scale).max(Vec3A::ZERO).min(self.last))
    }
    fn bin(&self, prims: &[Prim]) -> Bins {
        let mut bins = EMPTY_BINS;
        for p in prims {
            let k = self.index(p.centroid());
            let b = p.bounds();
            for (a, bins) in bins.iter_mut().enumerate() {
                let bin = &mut bins[k[a] as usize];
                bin.b = bin.b.union(b);
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

/// Binned SAH over all three axes (cost = A_L·N_L + A_R·N_R: one object per
/// leaf, so no leaf-cost termination). Returns None when no plane separates
/// the objects (coincident centroids, NaN).
fn binned_sah(w: &mut Work, cb: &Bounds) -> Option<Cut> {
    let n = w.prims.len();
    let count = if n >= FULL_BINS_MIN { BINS } else { BINS / 2 };
    let e = cb.max - cb.min;
    // The largest centroid maps to `count` and is clamped into the last bin.
    let scale = Vec3A::select(e.cmpgt(Vec3A::ZERO), Vec3A::splat(count as f32) / e, Vec3A::ZERO);
    let scale = Vec3A::select(scale.is_finite_mask(), scale, Vec3A::ZERO);
    if scale.cmpeq(Vec3A::ZERO).all() {
        return None;
    }
    let binner = Binner { min: cb.min, scale, last: Vec3A::splat(count as f32 - 1.0) };
    let bins = if n >= PAR_BIN_MIN {
        {
            #[cfg(feature = "parallel")]
            let b = w.prims.par_chunks(8192).map(|ch| binner.bin(ch)).reduce(|| EMPTY_BINS, merge_bins);
            #[cfg(not(feature = "parallel"))]
            let b = w.prims.chunks(8192).map(|ch| binner.bin(ch)).fold(EMPTY_BINS, merge_bins);
            b
        }
    } else {
        binner.bin(w.prims)
    };
    let node = bins[0][..count].iter().fold(Bounds::EMPTY, |b, x| b.union(x.b));
    let s = area_scale(&node);
    let mut best = Best::NONE; // pos: first bin of the right side
    for (a, bins) in bins.iter().enumerate() {
        if scale[a] == 0.0 {
            continue;
        }
        let bins = &bins[..count];
        let mut right = [f32::NAN; BINS];
        let (mut acc, mut cnt) = (Bounds::EMPTY, 0u32);
        for i in (1..count).rev() {
            acc = acc.union(bins[i].b);
            cnt += bins[i].n;
            if cnt > 0 {
                right[i] = acc.half_area(s) * cnt as f32;
            }
        }
        let (mut acc, mut cnt) = (Bounds::EMPTY, 0u32);
        for i in 1..count {
            acc = acc.union(bins[i - 1].b);
            cnt += bins[i - 1].n;
            // NaN (empty right side) and empty left sides never win.
            let cost = acc.half_area(s) * cnt as f32 + right[i];
            if cnt > 0 {
                best.offer(cost, (2 * cnt as usize).abs_diff(n), a, i);
            }
        }
    }
    if !best.key.is_finite() {
        return None;
    }
    let Best { axis, pos: split, .. } = best;
    // The same arithmetic as the binning, so the sides match the bin counts.
    Some(partition(w, |c| binner.index(c)[axis] < split as u32))
}

/// Truncates non-negative in-range floats to integers, four lanes at once
/// (`as u32` per lane compiles to scalar conversions with saturation fix-ups).
#[cfg(target_arch = "x86_64")]
fn truncate(v: Vec3A) -> [u32; 4] {
    // SAFETY: SSE2 is part of the x86_64 baseline, so the instruction exists.
    bytemuck::cast(unsafe { std::arch::x86_64::_mm_cvttps_epi32(v.into()) })
}

#[cfg(not(target_arch = "x86_64"))]
fn truncate(v: Vec3A) -> [u32; 4] {
    [v.x as u32, v.y as u32, v.z as u32, 0]
}

mod sweep;
use sweep::{Best, Sweep};

impl Builder {
    /// SAH subtree of <= SWEEP_MAX objects; same contract as `subtree`.
    fn sweep_subtree(&self, prims: &[Prim], out: &mut [BvhNode], base: u32, me: u32) -> Bounds {
        let mut sw = Sweep::new(prims);
        self.sweep_node(&mut sw, 0, prims.len(), out, base, me)
    }

    fn sweep_node(&self, sw: &mut Sweep, lo: usize, hi: usize, out: &mut [BvhNode], base: u32, me: u32) -> Bounds {
        let k = sw.split(lo, hi);
        let nl = k - lo;
        let ([ls, rs], desc) = out.split_first_chunk_mut::<2>().expect("n >= 2");
        let (ld, rd) = desc.split_at_mut(2 * nl - 2);
        let lb = self.sweep_child(sw, lo, k, ls, ld, base + 2, base, me);
        let rb = self.sweep_child(sw, k, hi, rs, rd, base + 2 * nl as u32, base + 1, me);
        lb.union(rb)
    }

    #[allow(clippy::too_many_arguments)]
    fn sweep_child(&self, sw: &mut Sweep, lo: usize, hi: usize, slot: &mut BvhNode, out: &mut [BvhNode], base: u32, me: u32, parent: u32) -> Bounds {
        if hi - lo == 1 {
            let i = sw.order[0][lo] as usize;
            *slot = self.leaf(&sw.prims[i], me, parent);
            return sw.bounds[i];
        }
        let b = self.sweep_node(sw, lo, hi, out, base, me);
        *slot = node(&b, base, parent);
        b
    }
}
