//! Triangles in a view's frustum, counted on the CPU over the culler's
//! BVH: what `vfc` would draw this frame, for `auto`'s cost model.
//!
//! Each node knows its subtree's triangles; a walk from the root adds a
//! node whole when its box is inside the frustum, skips it when outside,
//! and opens it otherwise, up to a budget of nodes, past which a node that
//! meets the frustum counts whole (an estimate a little high, never a
//! culling decision). Objects outside the tree (`DYNAMIC`, or added since
//! the last build) count as inside. The subtree sums are refreshed when the
//! tree is rebuilt; objects added or removed in between shift the estimate.

use glam::{Vec3, Vec4};

use crate::bvh::{Bvh, LEAF_BIT};
use crate::frustum::aabb_in_frustum;
use crate::layout::DrawCommand;

/// Nodes a count opens at most: 48 µs a frame at 256k objects on a core
/// of the 2-core machine BENCHMARKS.md describes (4096 took 0.35 ms there,
/// a sixth of an H200's frame). The estimate is then high by a share the cost model
/// learns (what a frame drew over the estimate).
pub const BUDGET: usize = 256;

/// Subtree triangle sums of one tree.
#[derive(Default)]
pub struct FrustumLoad {
    /// The tree's generation and node count they were summed for.
    key: Option<(u64, usize)>,
    node_triangles: Vec<f64>,
    /// Triangles of every object.
    pub all: f64,
    /// Triangles of the objects outside the tree.
    outside: f64,
}

impl FrustumLoad {
    /// Sums the subtrees again when `tree` (of `generation`) is not the
    /// one summed.
    pub fn refresh(&mut self, tree: &Bvh, generation: u64, commands: &[DrawCommand]) {
        let key = Some((generation, tree.nodes.len()));
        if self.key == key {
            return;
        }
        self.key = key;
        let tris = |object: usize| commands.get(object).map_or(0.0, |c| (c.index_count / 3) as f64);
        let nodes = &tree.nodes;
        let mut sums = vec![0.0; nodes.len()];
        // Post-order: a node after both children.
        let mut stack: Vec<(usize, bool)> = if nodes.is_empty() { Vec::new() } else { vec![(0, false)] };
        while let Some((i, opened)) = stack.pop() {
            let child = nodes[i].child;
            if child & LEAF_BIT != 0 {
                sums[i] = tris((child & !LEAF_BIT) as usize);
            } else if opened {
                sums[i] = sums[child as usize] + sums[child as usize + 1];
            } else {
                stack.extend([(i, true), (child as usize, false), (child as usize + 1, false)]);
            }
        }
        self.all = commands.iter().map(|c| (c.index_count / 3) as f64).sum();
        self.outside = (self.all - sums.first().copied().unwrap_or(0.0)).max(0.0);
        self.node_triangles = sums;
    }

    /// Triangles of the objects whose boxes meet the frustum `planes`
    /// (estimated past [`BUDGET`] nodes, as the module says).
    pub fn count(&self, tree: &Bvh, planes: &[Vec4; 6]) -> f64 {
        self.count_within(tree, planes, BUDGET)
    }

    /// [`FrustumLoad::count`] opening at most `budget` nodes.
    fn count_within(&self, tree: &Bvh, planes: &[Vec4; 6], budget: usize) -> f64 {
        let nodes = &tree.nodes;
        if nodes.is_empty() || self.node_triangles.len() != nodes.len() {
            return self.all;
        }
        let mut total = self.outside;
        let mut stack = vec![0usize];
        let mut opened = 0;
        while let Some(i) = stack.pop() {
            let n = &nodes[i];
            let (min, max) = (Vec3::from(n.min), Vec3::from(n.max));
            if !aabb_in_frustum(planes, min, max) {
                continue;
            }
            if n.child & LEAF_BIT != 0 || opened >= budget || inside(planes, min, max) {
                total += self.node_triangles[i];
            } else {
                opened += 1;
                stack.extend([n.child as usize, n.child as usize + 1]);
            }
        }
        total
    }
}

/// True when the box lies wholly inside every plane.
fn inside(planes: &[Vec4; 6], min: Vec3, max: Vec3) -> bool {
    planes.iter().all(|p| {
        let n = p.truncate();
        let v = Vec3::select(n.cmpge(Vec3::ZERO), min, max); // the "negative vertex"
        n.dot(v) + p.w >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frustum::frustum_planes;
    use crate::Aabb;

    #[test]
    fn it_counts_what_frustum_culling_keeps() {
        // A 20 x 20 grid of unit boxes on the ground, objects of 1..=400 triangles.
        let boxes: Vec<Aabb> = (0..400)
            .map(|i| Aabb::new(Vec3::new((i % 20) as f32 * 2.0, 0.0, (i / 20) as f32 * 2.0), Vec3::new((i % 20) as f32 * 2.0 + 1.0, 1.0, (i / 20) as f32 * 2.0 + 1.0)))
            .collect();
        let commands: Vec<DrawCommand> = (0..400).map(|i| DrawCommand { index_count: 3 * (i + 1), instance_count: 1, ..Default::default() }).collect();
        let tree = Bvh::build(&boxes, crate::bvh::Split::Sah);
        let mut load = FrustumLoad::default();
        load.refresh(&tree, 0, &commands);
        assert_eq!(load.all, (1..=400).sum::<u32>() as f64);
        for (eye, at) in [
            (Vec3::new(-5.0, 3.0, -5.0), Vec3::new(20.0, 0.0, 20.0)),
            (Vec3::new(20.0, 10.0, 20.0), Vec3::new(20.0, 0.0, 0.0)),
            (Vec3::new(0.0, 5.0, 60.0), Vec3::new(0.0, 5.0, 100.0)),
        ] {
            let vp = glam::Mat4::perspective_rh(1.0, 1.5, 0.1, 100.0) * glam::Mat4::look_at_rh(eye, at, Vec3::Y);
            let planes = frustum_planes(&vp);
            let exact: f64 = boxes.iter().zip(&commands).filter(|(b, _)| aabb_in_frustum(&planes, b.min, b.max)).map(|(_, c)| (c.index_count / 3) as f64).sum();
            // Exact with budget enough; past the budget, high, never low.
            assert_eq!(load.count_within(&tree, &planes, usize::MAX), exact, "eye {eye}");
            let estimate = load.count_within(&tree, &planes, 16);
            assert!(estimate >= exact && estimate <= load.all, "eye {eye}: {estimate} for {exact}");
        }
    }
}
