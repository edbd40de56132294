//! `soq`: occlusion queries with statistically skipped queries (Kovalčík & Sochor 2005).
//!
//! A queue of nodes, initially the root, is walked in order; each node gets
//! an action ([`action`]):
//! - SKIP: outside the frustum;
//! - RENDER: drawn (leaf) or replaced by its children, front to back, at its
//!   place in the queue — without a query, when the eye is in its box (or
//!   the box crosses the near plane), or when its recent queries found it
//!   unoccluded and the last one is younger than
//!   `not_query_time = BASE_TIME * (2 - 0.5^n)`, n the unoccluded results
//!   among the recent ones;
//! - QUERY: its box is queried and the walk goes on; after [`IN_FLIGHT`]
//!   queries (004: "about 20") or at the end of the queue the results are
//!   collected, visible nodes are drawn or their children are put at the
//!   front of the queue, and the walk starts again from the front.
//!
//! Time is the host's clock (`FrameInput::time`; the benchmark passes camera-path time), not wall time, so the
//! statistics expire at the same places of the path on any machine. Skipping
//! a query means treating the node as visible, never culling it untested.

use crate::cull::facts::Facts;
use std::collections::VecDeque;

use super::{front_to_back, Class, NodeView, QueryRenderer};
use crate::bvh::Bvh;
use crate::cull::{CullMethod, Frame, MethodContext};
use crate::cull::{Method, Stage, Stat};
use crate::error::Result;
use crate::gpu::Gpu;

/// `soq`'s facts.
pub(crate) const FACTS: Facts = Facts { name: "soq", description: "occlusion queries skipped for recently visible nodes (004's statistical OC)", ..Facts::QUERIES };

/// 004's BASE_TIME in seconds of camera path ("2/3 of second").
pub const DEFAULT_BASE_TIME: f32 = 2.0 / 3.0;
/// Queries issued before the results are collected (004: "about 20").
pub const IN_FLIGHT: usize = 20;
/// Query results remembered per node.
pub const HISTORY: u32 = 8;

/// `BASE_TIME * (2 - 0.5^n)`: how long after its last query a node found
/// unoccluded `n` times recently is rendered without a new query.
pub fn not_query_time(base_time: f32, unoccluded: u32) -> f32 {
    base_time * (2.0 - 0.5f32.powi(unoccluded.min(64) as i32))
}

/// What the walk does with a node ([`action`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Draw it (leaf) or replace it by its children, without a query.
    Render,
    /// Outside the frustum: drop the subtree.
    Skip,
    /// Query its box; act on the result when the batch is collected.
    Query,
}

/// A node's recent query results.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct History {
    /// Path time of the last query; `None` before the first.
    pub last_query: Option<f32>,
    /// Bit i: the result i queries ago was unoccluded.
    pub results: u8,
    /// Results stored (at most [`HISTORY`]).
    pub stored: u8,
    /// Frame number in which the traversal last reached the node.
    pub last_seen: u64,
}

impl History {
    /// Stores one query result (`visible`: unoccluded) taken at path time `now`.
    pub fn record(&mut self, visible: bool, now: f32) {
        self.results = (self.results << 1) | visible as u8;
        self.stored = (self.stored + 1).min(HISTORY as u8);
        self.last_query = Some(now);
    }
    /// Unoccluded results among the stored ones.
    pub fn unoccluded(&self) -> u32 {
        let mask = if self.stored >= 8 { 0xff } else { (1u16 << self.stored) as u8 - 1 };
        (self.results & mask).count_ones()
    }
    /// True when the latest stored result was unoccluded.
    pub fn last_visible(&self) -> bool {
        self.stored > 0 && self.results & 1 != 0
    }
}

/// 004's CalcNodeAction. `frame` is the current frame number (the node
/// statistics are too old unless the traversal reached the node in the
/// frame before), `now` the path time.
pub fn action(class: Class, h: &History, frame: u64, now: f32, base_time: f32) -> Action {
    match class {
        Class::Outside => Action::Skip,
        Class::Near => Action::Render,
        Class::Testable => {
            let Some(tq) = h.last_query else { return Action::Query };
            let too_old = h.last_seen + 1 != frame || now < tq;
            if too_old || !h.last_visible() {
                return Action::Query;
            }
            if now - tq < not_query_time(base_time, h.unoccluded()) {
                Action::Render
            } else {
                Action::Query
            }
        }
    }
}

/// The `soq` method: per-node query histories and the shared query renderer.
pub struct Soq {
    bvh: Bvh,
    q: QueryRenderer,
    base_time: f32,
    history: Vec<History>,
    frame: u64,
    /// Nodes rendered (or descended into) without a query, last frame.
    skipped: u64,
}

impl Soq {
    /// Empty histories for every node; `BASE_TIME` from the method options.
    pub fn new(cx: &MethodContext) -> Result<Self> {
        Ok(Soq {
            bvh: cx.bvh.clone(),
            q: QueryRenderer::new(cx)?,
            base_time: cx.options.soq_base_time,
            history: vec![History::default(); cx.bvh.nodes.len()],
            frame: 0,
            skipped: 0,
        })
    }

    /// Draws a leaf, or puts the children (front to back) at the front of the queue.
    fn render(&mut self, f: &mut Frame, eye: glam::Vec3, n: u32, front: &mut Vec<u32>) {
        match self.bvh.children(n) {
            Some(c) => front.extend(front_to_back(&self.bvh, eye, c)),
            None => self.q.draw_object(f, self.bvh.object(n).unwrap_or(0)),
        }
    }
}

impl CullMethod for Soq {
    fn method(&self) -> Method {
        Method::Soq
    }

    fn reset(&mut self, _enc: &mut wgpu::CommandEncoder) {
        self.history.fill(History::default());
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage(Stage::QueriesAndDraws);
        self.q.begin_frame();
        self.frame += 1;
        self.skipped = 0;
        let (frame, now) = (self.frame, f.time);
        let view = NodeView::from_frame(f);
        let mut queue: VecDeque<u32> = VecDeque::new();
        if !self.bvh.is_empty() {
            queue.push_back(0);
        }
        let mut pending: Vec<u32> = Vec::new();
        let mut front = Vec::new();
        loop {
            while let Some(n) = queue.pop_front() {
                let class = view.classify(self.bvh.aabb(n));
                let h = self.history[n as usize];
                let a = action(class, &h, frame, now, self.base_time);
                if class != Class::Outside {
                    self.history[n as usize].last_seen = frame;
                }
                match a {
                    Action::Skip => {}
                    Action::Render => {
                        self.skipped += (class == Class::Testable) as u64;
                        front.clear();
                        self.render(f, view.eye, n, &mut front);
                        for &c in front.iter().rev() {
                            queue.push_front(c);
                        }
                    }
                    Action::Query => {
                        self.q.query(f, &[n]);
                        pending.push(n);
                        if pending.len() >= IN_FLIGHT {
                            break;
                        }
                    }
                }
            }
            if pending.is_empty() {
                break;
            }
            let samples = self.q.collect(f)?;
            // Children of visible nodes go first, in the order of the results.
            front.clear();
            for (&n, &s) in pending.iter().zip(&samples) {
                self.history[n as usize].record(s > 0, now);
                if s > 0 {
                    self.render(f, view.eye, n, &mut front);
                }
            }
            pending.clear();
            for &c in front.iter().rev() {
                queue.push_front(c);
            }
        }
        self.q.finish_frame(f);
        Ok(())
    }

    fn tested_nodes(&self, _gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(Some(self.q.tested_nodes()))
    }

    fn stats(&mut self, _gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let mut rows = self.q.stats.rows();
        rows.push((Stat::RenderedUnqueried, self.skipped as f64));
        Ok(rows)
    }
}
