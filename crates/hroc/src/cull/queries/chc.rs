//! `chc++`: Coherent Hierarchical Culling revisited (Mattausch, Bittner,
//! Wimmer, Eurographics 2008), configured as in the HROC paper §5.1.
//!
//! Per frame, a front-to-back traversal of the BVH from the root:
//! - a node visible in the previous frame is not queried before use: an
//!   interior node is descended into, a leaf is drawn at once (render
//!   queue). Its visibility for the next frame comes from a query issued
//!   while waiting for other results (the v-queue) — only every `n_av`
//!   frames, with a random first offset (randomized sampling pattern);
//!   between those queries it is assumed to stay visible;
//! - a node not visible in the previous frame goes into the i-queue; every
//!   `b` nodes (batching), and whenever the traversal runs dry, the i-queue
//!   is issued as multiqueries: nodes sorted by the probability of staying
//!   invisible `p = 0.99 - 0.7 e^-i` (i: frames invisible in a row) are
//!   grouped greedily while the value `|M| / (1 + (1 - Π p) |M|)` grows;
//!   a multiquery that finds samples is re-issued node by node;
//! - an interior node's query rasterizes the boxes of its descendants down
//!   to `d_max` levels instead of its own, as long as their summed surface
//!   area stays within `s_max` times its own (tighter bounds);
//! - visible query results are pulled up the hierarchy; a previously
//!   invisible node found visible is drawn (leaf) or descended into.
//!
//! wgpu cannot ask whether a result is ready without waiting, so the
//! traversal runs until its stack is empty, then collects every
//! outstanding query in one read-back (a round) and continues with what
//! became visible. Boxes that cross the near plane or hold the eye are
//! visible without a query (the camera-inside-box case). The node is culled
//! only by a query of its own (tighter) boxes against the depth of objects
//! drawn earlier in the same frame, so every frame is conservative.

use super::{front_to_back, Class, NodeView, QueryRenderer};
use crate::bvh::{Bvh, NO_PARENT};
use crate::cull::facts::Facts;
use crate::cull::{CullMethod, Frame, MethodContext, MethodOptions};
use crate::cull::{Method, Stage, Stat};
use crate::error::Result;
use crate::gpu::Gpu;

/// `chc++`'s facts.
pub(crate) const FACTS: Facts = Facts { name: "chc++", description: "CHC++: batched multiqueries, randomized re-queries, tighter bounds", ..Facts::QUERIES };

/// The CHC++ parameters (HROC paper §5.1: n_av = 10, b = 4000, d_max = 4,
/// s_max = 1.4; b = 1000 here, see [`MethodOptions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChcParams {
    /// Previously invisible nodes per multiquery batch, b.
    pub batch: usize,
    /// Frames a visible leaf is assumed visible between queries, n_av.
    pub n_av: u32,
    /// Tighter bounds use descendants at most this many levels down, d_max.
    pub d_max: u32,
    /// Tighter bounds only while their summed area is within s_max × the node's.
    pub s_max: f32,
}

impl ChcParams {
    /// The parameters in `o`, with `batch` and `n_av` at least 1.
    pub fn from_options(o: &MethodOptions) -> Self {
        ChcParams { batch: o.chc_batch.max(1), n_av: o.chc_nav.max(1), d_max: o.chc_dmax, s_max: o.chc_smax }
    }
}

/// Probability that a node found invisible `age` times in a row stays
/// invisible (CHC++ §4.3).
pub fn p_stay_invisible(age: u32) -> f64 {
    0.99 - 0.7 * (-(age as f64)).exp()
}

/// Value of a multiquery of `k` nodes that all stay invisible with
/// probability `p_all`: nodes saved per query spent (a single node: 1).
pub fn multiquery_value(k: usize, p_all: f64) -> f64 {
    if k <= 1 {
        1.0
    } else {
        k as f64 / (1.0 + (1.0 - p_all) * k as f64)
    }
}

/// Splits nodes with invisibility ages into multiqueries: sorted most
/// likely invisible first, grown greedily while the value increases.
pub fn multiqueries(mut nodes: Vec<(u32, u32)>) -> Vec<Vec<u32>> {
    nodes.sort_by_key(|n| std::cmp::Reverse(n.1));
    let mut out = Vec::new();
    let mut i = 0;
    while i < nodes.len() {
        let mut p = p_stay_invisible(nodes[i].1);
        let mut value = multiquery_value(1, p);
        let mut j = i + 1;
        while j < nodes.len() {
            let p2 = p * p_stay_invisible(nodes[j].1);
            let v2 = multiquery_value(j + 1 - i, p2);
            if v2 <= value {
                break;
            }
            p = p2;
            value = v2;
            j += 1;
        }
        out.push(nodes[i..j].iter().map(|n| n.0).collect());
        i = j;
    }
    out
}

/// Tighter bounds of node `n`: the deepest cut of its subtree, at most
/// `d_max` levels down (leaves stay), whose boxes' summed surface area is
/// within `s_max` times the node's own. `[n]` for a leaf.
pub fn tight_boxes(bvh: &Bvh, n: u32, d_max: u32, s_max: f32) -> Vec<u32> {
    let area = |m: u32| bvh.aabb(m).area() as f64;
    let own = area(n);
    let mut best = vec![n];
    if own.is_nan() || own <= 0.0 {
        return best;
    }
    let mut level = best.clone();
    for _ in 0..d_max {
        let next: Vec<u32> = level.iter().flat_map(|&m| bvh.children(m).map_or_else(|| vec![m], |c| c.to_vec())).collect();
        if next.len() == level.len() {
            break;
        }
        let sum: f64 = next.iter().map(|&m| area(m)).sum();
        if sum > s_max as f64 * own {
            break;
        }
        best = next.clone();
        level = next;
    }
    best
}

#[derive(Clone, Copy, Debug, Default)]
struct NodeState {
    visible: bool,
    /// Frame that last reached the node (0: never).
    last_visited: u64,
    /// Frame from which a previously visible leaf is queried again.
    next_query: u64,
    /// Queries in a row that found the node invisible.
    invisible_age: u32,
}

/// One query in flight.
struct Pending {
    /// Nodes the query covers (several: a multiquery).
    nodes: Vec<u32>,
    /// A v-queue query (a previously visible leaf, already drawn).
    was_visible: bool,
}

/// The `chc++` method: per-view node visibility history and query state.
pub struct Chc {
    bvh: Bvh,
    q: QueryRenderer,
    params: ChcParams,
    /// Tighter-bound boxes of node i: `tight[tight_at[i]..tight_at[i + 1]]`.
    tight: Vec<u32>,
    tight_at: Vec<u32>,
    nodes: Vec<NodeState>,
    frame: u64,
    /// SplitMix64 state of the randomized re-query offsets (CHC++ §4.3).
    rng: u64,
    multi: u64,
    requeried: u64,
}

impl Chc {
    /// Precomputes every node's tighter-bound boxes and creates the shared query renderer.
    pub fn new(cx: &MethodContext) -> Result<Self> {
        let bvh = cx.bvh.clone();
        let params = ChcParams::from_options(cx.options);
        let (mut tight, mut tight_at) = (Vec::new(), vec![0u32]);
        for n in 0..bvh.nodes.len() as u32 {
            tight.extend(tight_boxes(&bvh, n, params.d_max, params.s_max));
            tight_at.push(tight.len() as u32);
        }
        Ok(Chc { q: QueryRenderer::new(cx)?, nodes: vec![NodeState::default(); bvh.nodes.len()], bvh, params, tight, tight_at, frame: 0, rng: 0x00C4_C0DE, multi: 0, requeried: 0 })
    }

    fn pull_up(&mut self, mut n: u32) {
        while n != NO_PARENT && !self.nodes[n as usize].visible {
            self.nodes[n as usize].visible = true;
            n = self.bvh.nodes[n as usize].parent;
        }
    }

    fn issue(&mut self, f: &mut Frame, nodes: Vec<u32>, was_visible: bool, pending: &mut Vec<Pending>) {
        let boxes: Vec<u32> = nodes.iter().flat_map(|&n| self.tight[self.tight_at[n as usize] as usize..self.tight_at[n as usize + 1] as usize].iter().copied()).collect();
        self.q.query(f, &boxes);
        self.multi += (nodes.len() > 1) as u64;
        pending.push(Pending { nodes, was_visible });
    }

    fn issue_multiqueries(&mut self, f: &mut Frame, i_queue: &mut Vec<u32>, pending: &mut Vec<Pending>) {
        if i_queue.is_empty() {
            return;
        }
        let aged: Vec<(u32, u32)> = i_queue.drain(..).map(|n| (n, self.nodes[n as usize].invisible_age)).collect();
        for m in multiqueries(aged) {
            self.issue(f, m, false, pending);
        }
    }

    /// Draws a leaf or pushes its children (front to back) on the stack.
    fn traverse_node(&mut self, f: &mut Frame, eye: glam::Vec3, n: u32, stack: &mut Vec<u32>) {
        match self.bvh.children(n) {
            Some(c) => {
                let [near, far] = front_to_back(&self.bvh, eye, c);
                stack.push(far);
                stack.push(near);
            }
            None => self.q.draw_object(f, self.bvh.object(n).unwrap_or(0)),
        }
    }
}

impl CullMethod for Chc {
    fn method(&self) -> Method {
        Method::Chc
    }

    fn reset(&mut self, _enc: &mut wgpu::CommandEncoder) {
        self.nodes.fill(NodeState::default());
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage(Stage::QueriesAndDraws);
        self.q.begin_frame();
        self.frame += 1;
        (self.multi, self.requeried) = (0, 0);
        let frame = self.frame;
        let view = NodeView::from_frame(f);
        let mut stack: Vec<u32> = if self.bvh.is_empty() { Vec::new() } else { vec![0] };
        let (mut i_queue, mut v_queue, mut pending) = (Vec::new(), Vec::new(), Vec::new());
        loop {
            // Hierarchical traversal.
            while let Some(n) = stack.pop() {
                let class = view.classify(self.bvh.aabb(n));
                if class == Class::Outside {
                    continue;
                }
                let st = self.nodes[n as usize];
                let was_visible = st.visible && st.last_visited + 1 == frame;
                self.nodes[n as usize].visible = false;
                self.nodes[n as usize].last_visited = frame;
                let leaf = self.bvh.is_leaf(n);
                if class == Class::Near {
                    // The eye is in the box or the box crosses the near plane.
                    if leaf {
                        self.pull_up(n);
                    }
                    self.traverse_node(f, view.eye, n, &mut stack);
                    continue;
                }
                if !was_visible {
                    i_queue.push(n);
                    if i_queue.len() >= self.params.batch {
                        self.issue_multiqueries(f, &mut i_queue, &mut pending);
                    }
                    continue;
                }
                if leaf {
                    if frame >= st.next_query {
                        v_queue.push(n);
                    } else {
                        self.pull_up(n); // assumed to stay visible
                    }
                }
                self.traverse_node(f, view.eye, n, &mut stack);
            }
            self.issue_multiqueries(f, &mut i_queue, &mut pending);
            // Previously visible leaves are queried while waiting.
            for n in v_queue.drain(..) {
                self.issue(f, vec![n], true, &mut pending);
            }
            if pending.is_empty() {
                break;
            }
            let samples = self.q.collect(f)?;
            for (p, s) in std::mem::take(&mut pending).into_iter().zip(samples) {
                if s == 0 {
                    for &n in &p.nodes {
                        self.nodes[n as usize].invisible_age += 1;
                    }
                } else if p.nodes.len() > 1 {
                    // A failed multiquery: query its nodes one by one.
                    self.requeried += p.nodes.len() as u64;
                    for &n in &p.nodes {
                        self.issue(f, vec![n], false, &mut pending);
                    }
                } else {
                    let n = p.nodes[0];
                    let st = &mut self.nodes[n as usize];
                    st.invisible_age = 0;
                    st.next_query = if p.was_visible { frame + self.params.n_av as u64 } else { frame + 1 + splitmix64(&mut self.rng) % self.params.n_av as u64 };
                    if !p.was_visible {
                        self.traverse_node(f, view.eye, n, &mut stack);
                    }
                    self.pull_up(n);
                }
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
        rows.push((Stat::Multiqueries, self.multi as f64));
        rows.push((Stat::Requeried, self.requeried as f64));
        Ok(rows)
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the next value of the stream at `state`.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
