//! `oq`: "simple OC" of Kovalčík & Sochor 2005 — traverse the BVH front to back from the
//! root (children ordered by the distance of their box to the eye), query
//! each node's padded box before drawing, one query in flight (stop and
//! wait). Visible: draw the object (leaf) or descend; invisible: skip the
//! subtree. Boxes that cross the near plane or hold the eye are visible
//! without a query.

use super::{front_to_back, Class, NodeView, QueryRenderer};
use crate::bvh::Bvh;
use crate::cull::facts::Facts;
use crate::cull::{CullMethod, Frame, MethodContext};
use crate::cull::{Method, Stage, Stat};
use crate::error::Result;
use crate::gpu::Gpu;

/// `oq`'s facts.
pub(crate) const FACTS: Facts = Facts { name: "oq", description: "hierarchical stop-and-wait occlusion queries, front to back (004's simple OC)", ..Facts::QUERIES };

/// What the traversal asks of its host.
pub enum Visit {
    /// Is node `n` visible? (a query)
    Test(u32),
    /// Draw object `o`.
    Draw(u32),
}

/// The front-to-back traversal, independent of the GPU: `visit` answers
/// tests (its result is ignored for draws). Returns the nodes tested.
pub fn traverse(bvh: &Bvh, view: &NodeView, mut visit: impl FnMut(Visit) -> Result<bool>) -> Result<u64> {
    let mut tested = 0;
    if bvh.is_empty() {
        return Ok(0);
    }
    let mut stack = vec![0u32];
    while let Some(n) = stack.pop() {
        let visible = match view.classify(bvh.aabb(n)) {
            Class::Outside => false,
            Class::Near => true,
            Class::Testable => {
                tested += 1;
                visit(Visit::Test(n))?
            }
        };
        if !visible {
            continue;
        }
        match bvh.children(n) {
            Some(c) => {
                let [near, far] = front_to_back(bvh, view.eye, c);
                stack.push(far);
                stack.push(near);
            }
            None => {
                visit(Visit::Draw(bvh.object(n).unwrap_or(0)))?;
            }
        }
    }
    Ok(tested)
}

/// The `oq` method: stop-and-wait occlusion queries on a front-to-back BVH walk.
pub struct Oq {
    bvh: Bvh,
    q: QueryRenderer,
}

impl Oq {
    /// A BVH copy and the shared query renderer.
    pub fn new(cx: &MethodContext) -> Result<Self> {
        Ok(Oq { bvh: cx.bvh.clone(), q: QueryRenderer::new(cx)? })
    }
}

impl CullMethod for Oq {
    fn method(&self) -> Method {
        Method::Oq
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage(Stage::QueriesAndDraws);
        self.q.begin_frame();
        let view = NodeView::from_frame(f);
        let q = &mut self.q;
        traverse(&self.bvh, &view, |v| match v {
            Visit::Test(n) => {
                q.query(f, &[n]);
                Ok(q.collect(f)?[0] > 0)
            }
            Visit::Draw(o) => {
                q.draw_object(f, o);
                Ok(true)
            }
        })?;
        self.q.finish_frame(f);
        Ok(())
    }

    fn tested_nodes(&self, _gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(Some(self.q.tested_nodes()))
    }

    fn stats(&mut self, _gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        Ok(self.q.stats.rows())
    }
}
