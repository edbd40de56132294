//! Object-level BVH: one leaf per object, the hierarchy HROC walks on the GPU
//! (bottom-up group extraction, top-down ray casting; HROC paper §4, thesis
//! §3). Built with SAH, middle or equal-count splits (Lee's thesis, Table 4).
//!
//! Layout (mirrored by the shaders): a flat array of 32-byte [`BvhNode`]s,
//! root at 0. The two children of an interior node are adjacent
//! (`child`, `child + 1`) and every pair starts at an odd index, so a node's
//! sibling is `n + 1` or `n - 1` without a memory access — group extraction
//! marks the sibling of every node on the way up. Pairs are allocated in
//! depth-first order (a subtree's nodes are one contiguous range), and every
//! child has a larger index than its parent.
//!
//! NaN boxes: the scene rejects them before a BVH is built. If one slips
//! through, `build` still terminates without panicking and gives every object
//! exactly one leaf, but node boxes may not contain it, and [`Bvh::validate`]
//! rejects the tree (a NaN box never equals itself).

mod build;
mod huge_pages;

use glam::{Vec3, Vec4};
use std::fmt;
use std::str::FromStr;

use crate::frustum::aabb_in_frustum;
use crate::Aabb;

/// Leaf marker in [`BvhNode::child`]; the low 31 bits are the object index.
pub const LEAF_BIT: u32 = 0x8000_0000;
/// The root's [`BvhNode::parent`].
pub const NO_PARENT: u32 = u32::MAX;
/// [`Bvh::leaf_of_object`] of an object outside the tree ([`Bvh::build_subset`]).
pub const NO_LEAF: u32 = u32::MAX;

/// One node, 32 bytes, `std430`-compatible: `vec3<f32> min; u32 child;
/// vec3<f32> max; u32 parent`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BvhNode {
    /// Box minimum corner.
    pub min: [f32; 3],
    /// `LEAF_BIT | object` for a leaf, else the left child (right = child + 1).
    pub child: u32,
    /// Box maximum corner.
    pub max: [f32; 3],
    /// Parent node, [`NO_PARENT`] for the root.
    pub parent: u32,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    /// The node's box.
    pub fn aabb(&self) -> Aabb {
        Aabb::new(Vec3::from(self.min), Vec3::from(self.max))
    }
    /// True when [`BvhNode::child`] holds [`LEAF_BIT`] (an object, not a child pair).
    pub fn is_leaf(&self) -> bool {
        self.child & LEAF_BIT != 0
    }
}

/// Split strategy of the top-down builder (Lee's thesis, Table 4: SAH, MID, EQ).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Split {
    /// Binned surface-area heuristic (the default of Lee's thesis).
    #[default]
    Sah,
    /// Spatial middle of the centroid bounds on the longest axis.
    Mid,
    /// Equal object counts (median on the longest axis).
    Eq,
}

impl Split {
    /// Every split strategy, in the order of Lee's thesis, Table 4.
    pub const ALL: [Split; 3] = [Split::Sah, Split::Mid, Split::Eq];
    /// Short lower-case name (`sah`, `mid`, `eq`), as parsed by `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            Split::Sah => "sah",
            Split::Mid => "mid",
            Split::Eq => "eq",
        }
    }
}

impl fmt::Display for Split {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Split {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Split::ALL.into_iter().find(|x| x.name().eq_ignore_ascii_case(s)).ok_or_else(|| format!("unknown split '{s}' (expected sah, mid or eq)"))
    }
}

/// Binary object BVH in the GPU layout described in the module docs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// Nodes in the GPU layout: root at 0, child pairs adjacent from odd indices.
    pub nodes: Vec<BvhNode>,
    /// Leaf node of each object (the start of HROC's bottom-up walk).
    pub leaf_of_object: Vec<u32>,
    /// Wall-clock build time, milliseconds.
    pub build_ms: f64,
}

/// Surface area in f64: f32 overflows for boxes near ±1e19 and beyond.
pub(crate) fn area64(min: [f32; 3], max: [f32; 3]) -> f64 {
    let e = |i: usize| (max[i] as f64 - min[i] as f64).max(0.0);
    if (0..3).any(|i| min[i] > max[i]) {
        return 0.0;
    }
    let (x, y, z) = (e(0), e(1), e(2));
    2.0 * (x * y + y * z + z * x)
}

impl Bvh {
    /// Builds a BVH over `boxes` with one leaf per object (index = position in
    /// `boxes`): 0 objects → no nodes, 1 → a leaf root, N → 2N - 1 nodes.
    pub fn build(boxes: &[Aabb], split: Split) -> Bvh {
        let t = std::time::Instant::now();
        let (nodes, leaf_of_object) = build::build(boxes, split);
        Bvh { nodes, leaf_of_object, build_ms: t.elapsed().as_secs_f64() * 1e3 }
    }

    /// Builds a BVH over the objects `objects` only (indices into `boxes`,
    /// each at most once): leaves hold those indices, and every other
    /// object's [`Bvh::leaf_of_object`] is [`NO_LEAF`]. The culler builds
    /// its tree over the static objects this way (HROC §6's hybrid).
    pub fn build_subset(boxes: &[Aabb], objects: &[u32], split: Split) -> Bvh {
        let t = std::time::Instant::now();
        let sub: Vec<Aabb> = objects.iter().map(|&o| boxes[o as usize]).collect();
        let (mut nodes, sub_leaf) = build::build(&sub, split);
        for n in nodes.iter_mut().filter(|n| n.is_leaf()) {
            n.child = LEAF_BIT | objects[(n.child & !LEAF_BIT) as usize];
        }
        let mut leaf_of_object = vec![NO_LEAF; boxes.len()];
        for (&o, &leaf) in objects.iter().zip(&sub_leaf) {
            leaf_of_object[o as usize] = leaf;
        }
        Bvh { nodes, leaf_of_object, build_ms: t.elapsed().as_secs_f64() * 1e3 }
    }

    /// Refits every node's box to `boxes` (one per object, the new world
    /// boxes) keeping the tree: leaves take their object's box, interior
    /// nodes the union of their children. O(N). A refit tree stays valid but
    /// its SAH cost grows as objects move away from where the tree was built
    /// ([`Bvh::sah_cost`]).
    pub fn refit(&mut self, boxes: &[Aabb]) {
        self.refit_with(|o| Some(boxes[o as usize]));
    }

    /// [`Bvh::refit`] where `leaf_box(object)` gives each leaf's new box, or
    /// `None` to keep the leaf's box as it is (a frozen leaf).
    pub fn refit_with(&mut self, leaf_box: impl Fn(u32) -> Option<Aabb>) {
        // Children follow their parents (module docs): one backward pass.
        for n in (0..self.nodes.len()).rev() {
            let node = self.nodes[n];
            let b = if node.is_leaf() {
                match leaf_box(node.child & !LEAF_BIT) {
                    Some(b) => b,
                    None => continue,
                }
            } else {
                self.nodes[node.child as usize].aabb().union(self.nodes[node.child as usize + 1].aabb())
            };
            let nd = &mut self.nodes[n];
            (nd.min, nd.max) = (b.min.to_array(), b.max.to_array());
        }
    }

    /// Number of nodes (2N - 1 for N objects).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }
    /// True for a tree with no nodes (no objects).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
    /// True when node `n` is a leaf.
    pub fn is_leaf(&self, n: u32) -> bool {
        self.nodes[n as usize].is_leaf()
    }
    /// Object index of node `n`, or `None` for an interior node.
    pub fn object(&self, n: u32) -> Option<u32> {
        let c = self.nodes[n as usize].child;
        (c & LEAF_BIT != 0).then_some(c & !LEAF_BIT)
    }
    /// Left and right child of node `n`, or `None` for a leaf.
    pub fn children(&self, n: u32) -> Option<[u32; 2]> {
        let c = self.nodes[n as usize].child;
        (c & LEAF_BIT == 0).then_some([c, c + 1])
    }
    /// Pairs start at odd indices, so the sibling needs no lookup.
    pub fn sibling(&self, n: u32) -> Option<u32> {
        match n {
            0 => None,
            _ if n as usize >= self.nodes.len() => None,
            _ if n % 2 == 1 => Some(n + 1),
            _ => Some(n - 1),
        }
    }
    /// Parent of node `n`, or `None` for the root.
    pub fn parent(&self, n: u32) -> Option<u32> {
        let p = self.nodes[n as usize].parent;
        (p != NO_PARENT).then_some(p)
    }
    /// Box of node `n`.
    pub fn aabb(&self, n: u32) -> Aabb {
        self.nodes[n as usize].aabb()
    }

    /// Maximum leaf depth (root = 0; 0 for an empty tree). Children always
    /// follow their parent, so one forward pass suffices.
    pub fn depth(&self) -> u32 {
        let mut d = vec![0u32; self.nodes.len()];
        let mut max = 0;
        for (i, n) in self.nodes.iter().enumerate() {
            if !n.is_leaf() {
                let c = n.child as usize;
                d[c] = d[i] + 1;
                d[c + 1] = d[i] + 1;
                max = max.max(d[i] + 1);
            }
        }
        max
    }

    /// SAH cost (Lee's thesis §3; MacDonald & Booth 1990): the sum over all nodes of
    /// area(node) / area(root). 0 for an empty tree, and 0 when the root has
    /// no area (every node then has none either: 0/0 counts as 0).
    pub fn sah_cost(&self) -> f64 {
        let Some(root) = self.nodes.first() else { return 0.0 };
        let ra = area64(root.min, root.max);
        if ra == 0.0 || !ra.is_finite() {
            return 0.0;
        }
        self.nodes.iter().map(|n| area64(n.min, n.max)).sum::<f64>() / ra
    }

    /// Objects whose box overlaps `b` (closed intervals), sorted.
    pub fn query_aabb(&self, b: &Aabb) -> Vec<u32> {
        self.query(|n| {
            let (min, max) = (Vec3::from(n.min), Vec3::from(n.max));
            min.cmple(b.max).all() && b.min.cmple(max).all()
        })
    }

    /// Objects whose box passes [`aabb_in_frustum`], sorted. The test is
    /// monotone under box containment, so pruning at interior nodes loses
    /// nothing the brute-force loop would find.
    pub fn query_frustum(&self, planes: &[Vec4; 6]) -> Vec<u32> {
        self.query(|n| aabb_in_frustum(planes, Vec3::from(n.min), Vec3::from(n.max)))
    }

    /// Depth-first walk visiting subtrees whose node passes `hit`.
    fn query(&self, hit: impl Fn(&BvhNode) -> bool) -> Vec<u32> {
        let mut out = Vec::new();
        if self.nodes.is_empty() {
            return out;
        }
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            let n = &self.nodes[i as usize];
            if !hit(n) {
                continue;
            }
            if n.is_leaf() {
                out.push(n.child & !LEAF_BIT);
            } else {
                stack.push(n.child + 1);
                stack.push(n.child);
            }
        }
        out.sort_unstable();
        out
    }

    /// Checks every structural invariant the GPU passes rely on. Works on
    /// arbitrary (possibly corrupt) node arrays without panicking.
    pub fn validate(&self, boxes: &[Aabb]) -> Result<(), String> {
        let nodes = &self.nodes;
        let n_obj = boxes.len();
        let expect = if n_obj == 0 { 0 } else { 2 * n_obj - 1 };
        if nodes.len() != expect {
            return Err(format!("{} nodes for {n_obj} objects, expected {expect}", nodes.len()));
        }
        if self.leaf_of_object.len() != n_obj {
            return Err(format!("leaf_of_object has {} entries for {n_obj} objects", self.leaf_of_object.len()));
        }
        if nodes.is_empty() {
            return Ok(());
        }
        if nodes.len() > (LEAF_BIT as usize) {
            return Err("too many nodes for 31-bit indices".into());
        }
        if nodes[0].parent != NO_PARENT {
            return Err(format!("root parent is {}, expected NO_PARENT", nodes[0].parent));
        }
        let finite = |n: &BvhNode| n.min.iter().chain(&n.max).all(|c| !c.is_nan());
        // Walk from the root: every node reached exactly once and all nodes
        // reached means a tree (no cycles, no sharing, nothing detached).
        let mut seen = vec![false; nodes.len()];
        let mut obj_leaf = vec![u32::MAX; n_obj];
        let mut stack = vec![0u32];
        seen[0] = true;
        let mut reached = 1usize;
        while let Some(i) = stack.pop() {
            let n = &nodes[i as usize];
            if !finite(n) {
                return Err(format!("node {i}: NaN in box {:?}..{:?}", n.min, n.max));
            }
            if n.is_leaf() {
                let o = (n.child & !LEAF_BIT) as usize;
                if o >= n_obj {
                    return Err(format!("leaf {i}: object {o} out of range"));
                }
                if obj_leaf[o] != u32::MAX {
                    return Err(format!("object {o} in leaves {} and {i}", obj_leaf[o]));
                }
                obj_leaf[o] = i;
                let b = &boxes[o];
                if n.aabb() != *b {
                    return Err(format!("leaf {i}: box {:?}..{:?} differs from object {o}'s {:?}", n.min, n.max, b));
                }
                continue;
            }
            let c = n.child;
            if c % 2 != 1 || c as usize + 1 >= nodes.len() {
                return Err(format!("node {i}: child pair at {c} (must be odd and in range)"));
            }
            let outer = n.aabb();
            for k in [c, c + 1] {
                let ch = &nodes[k as usize];
                if ch.parent != i {
                    return Err(format!("node {k}: parent {} but node {i} claims it", ch.parent));
                }
                if seen[k as usize] {
                    return Err(format!("node {k} reached twice (cycle or shared child)"));
                }
                seen[k as usize] = true;
                reached += 1;
                if !outer.contains(&ch.aabb()) {
                    return Err(format!("node {i}: box {:?}..{:?} does not contain child {k}'s {:?}..{:?}", n.min, n.max, ch.min, ch.max));
                }
                stack.push(k);
            }
        }
        if reached != nodes.len() {
            return Err(format!("{} of {} nodes unreachable from the root", nodes.len() - reached, nodes.len()));
        }
        for (o, (&want, &got)) in obj_leaf.iter().zip(&self.leaf_of_object).enumerate() {
            if want == u32::MAX {
                return Err(format!("object {o} has no leaf"));
            }
            if want != got {
                return Err(format!("leaf_of_object[{o}] = {got}, but its leaf is {want}"));
            }
        }
        Ok(())
    }
}
