//! The hardware-occlusion-query baselines:
//! - [`oq`]: "simple OC" of Kovalčík & Sochor 2005, a front-to-back BVH traversal that
//!   queries every node's box and waits for each result;
//! - [`soq`]: 004's statistical algorithm, a node queue with RENDER / SKIP /
//!   QUERY actions, several queries in flight, queries skipped for nodes
//!   visible in recent frames (`not_query_time = BASE_TIME * (2 - 0.5^n)`);
//! - [`chc`]: CHC++ (Mattausch, Bittner, Wimmer 2008) as the HROC paper
//!   configures it (§5.1): batched multiqueries of previously invisible
//!   nodes, randomized re-queries of visible leaves, tighter bounds.
//!
//! They share [`QueryRenderer`]: a box pass on the renderer's depth target
//! (HROC's box pipeline — `box_vs` of `hroc_test.wgsl`, padded boxes,
//! front faces, `LessEqual` with a bias toward the camera — with no
//! fragment stage and no writes) that records wgpu occlusion queries, and a
//! render queue that draws objects through [`Frame::draw`]. Draws and
//! queries keep program order: queued draws are recorded before the next
//! query and queued queries before the next draw, so each query sees every
//! object drawn before it. Results come back in batches
//! ([`QueryRenderer::collect`]: resolve, submit, map — a stall).
//!
//! Conservative within the frame, whatever the statistics say: a node is
//! culled only when a query of its box (or of tighter boxes that hold all
//! of its leaves) drew no sample against the depth of objects drawn this
//! frame. Boxes that cross the near plane or hold the eye lose fragments to
//! clipping, so they count as visible without a query.

pub mod chc;
pub mod oq;
pub mod soq;

use crate::gpu::shape::{DeviceShape, EncoderShape, RenderShape};
use glam::{Vec3, Vec4};
use std::time::Instant;

use super::{hroc::cpu, Frame, MethodContext, Stat};
use crate::bvh::Bvh;
use crate::contract::Phase;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::layout::DrawCommand;
use crate::shaders::source as shader_source;
use crate::{frustum::aabb_in_frustum, Aabb};

/// Queries per `wgpu::QuerySet` (`wgpu::QUERY_SET_MAX_QUERIES` in wgpu 30);
/// more in one batch chain further sets.
pub const SET_SIZE: u32 = wgpu::QUERY_SET_MAX_QUERIES;

/// What the CPU needs of the frame's camera to classify BVH nodes, with the
/// shaders' box padding (`padded_box`, `crosses_near` in common.wgsl).
#[derive(Clone, Copy, Debug)]
pub struct NodeView {
    /// Frustum planes, plane 4 the near plane (`n·p + d >= 0` inside).
    pub planes: [Vec4; 6],
    /// The near plane ([`crate::frustum::ViewGeometry::near_plane`]).
    pub near_plane: Vec4,
    /// Distance from the eye to the near plane.
    pub near: f32,
    /// Camera position in world space.
    pub eye: Vec3,
    /// A pixel's height at distance d from the eye, `a + b d`
    /// ([`cpu::pixel_angle`]), for box padding.
    pub pixel: glam::Vec2,
}

/// How a node's padded box stands to the view frustum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// Wholly outside a frustum plane: cull the subtree.
    Outside,
    /// Crosses the near plane or holds the eye: visible without a query.
    Near,
    /// Can be tested by rasterizing its box.
    Testable,
}

impl NodeView {
    /// The camera of the frame's uniform.
    pub fn from_frame(f: &Frame) -> Self {
        let u = &f.uniform;
        let pixel = glam::Vec2::new(u.footprint[0], u.footprint[1]);
        NodeView { planes: u.planes.map(Vec4::from), near_plane: Vec4::from(u.near_plane), near: u.near, eye: Vec3::new(u.eye[0], u.eye[1], u.eye[2]), pixel }
    }

    /// Classifies `b` after the shaders' pixel padding.
    pub fn classify(&self, b: Aabb) -> Class {
        let p = cpu::padded(b, self.eye, self.pixel);
        if !aabb_in_frustum(&self.planes, p.min, p.max) {
            Class::Outside
        } else if cpu::crosses_near(self.near_plane, self.near, &p) {
            Class::Near
        } else {
            Class::Testable
        }
    }
}

/// Distance from `eye` to the closest point of `b` (0 inside).
pub fn box_distance(b: &Aabb, eye: Vec3) -> f32 {
    (b.min - eye).max(eye - b.max).max(Vec3::ZERO).length()
}

/// The two children of a node, nearer box first (ties: nearer centre first,
/// then the left child).
pub fn front_to_back(bvh: &Bvh, eye: Vec3, [a, b]: [u32; 2]) -> [u32; 2] {
    let key = |n: u32| {
        let bx = bvh.aabb(n);
        (box_distance(&bx, eye), (bx.center() - eye).length_squared())
    };
    let (ka, kb) = (key(a), key(b));
    if kb.0.total_cmp(&ka.0).then(kb.1.total_cmp(&ka.1)).is_lt() {
        [b, a]
    } else {
        [a, b]
    }
}

/// Per-frame counters every query method reports through `CullMethod::stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QueryStats {
    /// Occlusion queries issued (a multiquery counts once).
    pub queries: u64,
    /// Boxes rasterized inside queries.
    pub boxes: u64,
    /// Read-backs of query results (each a submit and a wait).
    pub batches: u64,
    /// Host wall-clock ms spent submitting and waiting for results.
    pub wait_ms: f64,
    /// Lists drawn through `Frame::draw`.
    pub draws: u64,
}

impl QueryStats {
    /// The counters as `(Stat, value)` rows.
    pub fn rows(&self) -> Vec<(Stat, f64)> {
        vec![
            (Stat::Queries, self.queries as f64),
            (Stat::QueryBatches, self.batches as f64),
            (Stat::WaitMs, self.wait_ms),
            (Stat::QueryBoxes, self.boxes as f64),
            (Stat::DrawCalls, self.draws as f64),
        ]
    }
}

/// Command buffers of drawn lists, handed out once per frame: a host may
/// keep every list it drew to check it after the frame (the benchmark does), so no
/// region is written twice within a frame. Power-of-two size classes,
/// reused from frame to frame.
#[derive(Default)]
struct ListPool {
    classes: Vec<Vec<wgpu::Buffer>>,
    used: Vec<usize>,
}

impl ListPool {
    fn take(&mut self, gpu: &Gpu, len: usize) -> wgpu::Buffer {
        let c = len.max(1).next_power_of_two().trailing_zeros() as usize;
        if self.classes.len() <= c {
            self.classes.resize_with(c + 1, Vec::new);
            self.used.resize(c + 1, 0);
        }
        if self.used[c] == self.classes[c].len() {
            use wgpu::BufferUsages as U;
            let size = (1u64 << c) * std::mem::size_of::<DrawCommand>() as u64;
            self.classes[c].push(gpu.buffer("query method list", size, U::STORAGE | U::INDIRECT | U::COPY_DST | U::COPY_SRC));
        }
        self.used[c] += 1;
        self.classes[c][self.used[c] - 1].clone()
    }

    fn reset(&mut self) {
        self.used.fill(0);
    }
}

/// The box-query pass and render queue shared by `oq`, `soq` and `chc++`.
pub struct QueryRenderer {
    pipeline: wgpu::RenderPipeline,
    bind: wgpu::BindGroup,
    sets: Vec<wgpu::QuerySet>,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    /// Queries `resolve` and `staging` hold.
    capacity: u32,
    /// Every object's draw command (the renderer's, read back once).
    commands: Vec<DrawCommand>,
    all_count: wgpu::Buffer,
    pool: ListPool,
    /// Objects to draw, not yet recorded.
    draw_queue: Vec<u32>,
    /// Boxes (BVH node ids) of queries not yet recorded, and where each
    /// query's boxes end in `query_boxes`.
    query_boxes: Vec<u32>,
    query_ends: Vec<usize>,
    /// Queries recorded and not yet collected (ids `0..recorded`).
    recorded: u32,
    /// Every box queried this frame (`tested_nodes`).
    tested: Vec<u32>,
    /// This frame's counters.
    pub stats: QueryStats,
}

impl QueryRenderer {
    /// Builds the box pipeline and reads back every object's draw command once.
    pub fn new(cx: &MethodContext) -> Result<Self> {
        let (gpu, bvh) = (cx.gpu, cx.bvh);
        use wgpu::BufferUsages as U;
        let nodes = gpu.buffer_init("query bvh nodes", bytemuck::cast_slice(&bvh.nodes), U::STORAGE);
        let device = &gpu.device;
        let layout = crate::reflect::Layout::QueryBoxes.create(gpu);
        let bind = device.counted_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("query boxes"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: cx.frame.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: nodes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: cx.bounds.as_entire_binding() },
            ],
        });
        let pl = crate::reflect::pipeline_layout(gpu, "query boxes", &layout);
        // HROC's box vertex stage (group 0: frame, nodes, boxes; node = instance).
        let module = gpu.shader("hroc_test.wgsl", &shader_source("hroc_test.wgsl"));
        // Depth-only: the occlusion query counts the samples that pass.
        let pipeline = crate::shaders::box_test_pipeline(gpu, "query boxes", &pl, &module, None, (cx.targets.depth_format, cx.targets.depth, cx.targets.samples), &[]);
        let commands = if cx.object_count > 0 { gpu.read::<DrawCommand>(cx.commands, 0, cx.object_count as u64)? } else { Vec::new() };
        let mut q = QueryRenderer {
            pipeline,
            bind,
            sets: Vec::new(),
            resolve: gpu.buffer("query results", 16, U::QUERY_RESOLVE | U::COPY_SRC),
            staging: gpu.buffer("query read-back", 16, U::MAP_READ | U::COPY_DST),
            capacity: 0,
            commands,
            all_count: gpu.buffer_init(
                "query list count",
                bytemuck::bytes_of(&u32::MAX),
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC,
            ),
            pool: ListPool::default(),
            draw_queue: Vec::new(),
            query_boxes: Vec::new(),
            query_ends: Vec::new(),
            recorded: 0,
            tested: Vec::new(),
            stats: QueryStats::default(),
        };
        q.grow_sets(gpu, 1);
        Ok(q)
    }

    fn grow_sets(&mut self, gpu: &Gpu, sets: usize) {
        if self.sets.len() >= sets {
            return;
        }
        while self.sets.len() < sets {
            self.sets.push(gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("occlusion queries"), ty: wgpu::QueryType::Occlusion, count: SET_SIZE }));
        }
        self.capacity = sets as u32 * SET_SIZE;
        use wgpu::BufferUsages as U;
        let bytes = self.capacity as u64 * wgpu::QUERY_SIZE as u64;
        self.resolve = gpu.buffer("query results", bytes, U::QUERY_RESOLVE | U::COPY_SRC);
        self.staging = gpu.buffer("query read-back", bytes, U::MAP_READ | U::COPY_DST);
    }

    /// Starts a frame: list buffers are free again, counters restart, and
    /// whatever a frame that failed part-way left queued is forgotten.
    pub fn begin_frame(&mut self) {
        self.recorded = 0;
        self.query_boxes.clear();
        self.query_ends.clear();
        self.draw_queue.clear();
        self.pool.reset();
        self.tested.clear();
        self.stats = QueryStats::default();
    }

    /// Queues a draw of object `o`.
    pub fn draw_object(&mut self, f: &mut Frame, o: u32) {
        self.record_queries(f);
        self.draw_queue.push(o);
    }

    /// Queues one occlusion query over the boxes of `nodes` (one box each:
    /// several make a multiquery, or a node's tighter bounds). Returns its
    /// index in the results of the next [`collect`](Self::collect).
    pub fn query(&mut self, f: &mut Frame, nodes: &[u32]) -> usize {
        self.record_draws(f);
        self.query_boxes.extend_from_slice(nodes);
        self.tested.extend_from_slice(nodes);
        self.query_ends.push(self.query_boxes.len());
        self.stats.queries += 1;
        self.stats.boxes += nodes.len() as u64;
        self.recorded as usize + self.query_ends.len() - 1
    }

    /// BVH nodes whose boxes were queried this frame, sorted, once each.
    pub fn tested_nodes(&self) -> Vec<u32> {
        let mut t = self.tested.clone();
        t.sort_unstable();
        t.dedup();
        t
    }

    /// Queries issued and not yet collected.
    pub fn outstanding(&self) -> usize {
        self.recorded as usize + self.query_ends.len()
    }

    fn record_draws(&mut self, f: &mut Frame) {
        if self.draw_queue.is_empty() {
            return;
        }
        let cmds: Vec<DrawCommand> = self.draw_queue.drain(..).map(|o| self.commands[o as usize]).collect();
        let buf = self.pool.take(f.gpu, cmds.len());
        f.write(&buf, 0, bytemuck::cast_slice(&cmds));
        // The renderer's count buffer holds N >= len: max_count bounds the draw.
        f.draw(Phase::Interleaved, &DrawList { commands: buf, count: self.all_count.clone(), max_count: cmds.len() as u32 }, None);
        self.stats.draws += 1;
    }

    fn record_queries(&mut self, f: &mut Frame) {
        if self.query_ends.is_empty() {
            return;
        }
        let total = self.recorded as usize + self.query_ends.len();
        self.grow_sets(f.gpu, total.div_ceil(SET_SIZE as usize));
        let targets = f.targets;
        let mut start = 0usize;
        let mut i = 0usize;
        while i < self.query_ends.len() {
            // One pass per query set the queries fall in.
            let set = (self.recorded as usize + i) / SET_SIZE as usize;
            let (enc, count) = f.counted();
            let mut pass = enc.counted_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("occlusion queries"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment { view: &targets.depth_attachment, depth_ops: None, stencil_ops: None }),
                timestamp_writes: None,
                occlusion_query_set: Some(&self.sets[set]),
                multiview_mask: None,
            });
            count.around(&mut pass, |pass| {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind, &[]);
                while i < self.query_ends.len() && (self.recorded as usize + i) / SET_SIZE as usize == set {
                    pass.begin_occlusion_query(((self.recorded as usize + i) % SET_SIZE as usize) as u32);
                    for &node in &self.query_boxes[start..self.query_ends[i]] {
                        pass.counted_draw(0..36, node..node + 1);
                    }
                    pass.end_occlusion_query();
                    start = self.query_ends[i];
                    i += 1;
                }
            });
        }
        self.recorded = total as u32;
        self.query_boxes.clear();
        self.query_ends.clear();
    }

    /// Samples that passed, for every query issued since the last collect
    /// (in issue order). Records what is queued, resolves, submits and
    /// waits: the host time of that is `wait_ms`.
    pub fn collect(&mut self, f: &mut Frame) -> Result<Vec<u64>> {
        self.record_draws(f);
        self.record_queries(f);
        let n = self.recorded;
        if n == 0 {
            return Ok(Vec::new());
        }
        let enc = f.encoder();
        for (s, set) in self.sets.iter().enumerate() {
            let first = s as u32 * SET_SIZE;
            if first >= n {
                break;
            }
            let count = (n - first).min(SET_SIZE);
            enc.counted_resolve(set, 0..count, &self.resolve, first as u64 * wgpu::QUERY_SIZE as u64);
        }
        let bytes = n as u64 * wgpu::QUERY_SIZE as u64;
        enc.counted_copy(&self.resolve, 0, &self.staging, 0, bytes);
        let t = Instant::now();
        let data = f.map_read(&self.staging, bytes)?;
        self.stats.wait_ms += t.elapsed().as_secs_f64() * 1e3;
        self.stats.batches += 1;
        self.recorded = 0;
        Ok(bytemuck::pod_collect_to_vec(&data))
    }

    /// Records what is still queued (call at the end of the frame, after
    /// the last collect).
    pub fn finish_frame(&mut self, f: &mut Frame) {
        debug_assert!(self.outstanding() == 0, "queries left uncollected");
        self.record_queries(f);
        self.record_draws(f);
    }
}
