//! `ioc`: iterative GPU occlusion culling with a BVH (Lee & Lee, HPG 2020
//! poster; the HROC paper's IOC row). ROC on BVH nodes, level by level:
//! 1. occlusion map — draw V (last frame's visible set, packed in object
//!    order) with forced early-Z; fragments that pass mark next frame's V
//!    (with ID marks, the objects owning a pixel after the draw);
//! 2. from depth `start` down to `bottom`: rasterize the boxes of the
//!    level's queue with the ROC box test (`roc_boxes.wgsl`), then one
//!    thread per queued node (`ioc.wgsl`): a culled node leaves its subtree
//!    occluded, a passing leaf is visible, a passing interior node enqueues
//!    its children; the queue's size is read back to size the next level's
//!    draw (the poster's read-back). At the bottom level every object
//!    below a passing node is visible. Boxes reaching the near plane pass
//!    without a test;
//! 3. occludee rendering — draw the visible objects not in V (packed in
//!    order), marking next frame's V as in step 1.
//!
//! Nodes above `start` are never tested, so the first queue is every node
//! at depth `start` plus every leaf shallower than it: a cut of the tree,
//! which keeps every object under test ([`cpu::start_queue`]).

pub mod cpu;

use super::roc::{BoxCount, BoxPass};
use super::{CullMethod, Frame, Method, MethodContext, Stage, Stat};
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::cull::DrawList;
use crate::error::{Error, Result};
use crate::gpu::shape::{EncoderShape, PassShape};
use crate::gpu::{dispatch_size, Gpu};
use crate::reflect::Layout;
use crate::shaders::source as shader_source;

/// `ioc`'s facts: level queues read back mid-frame, built from the tree.
pub(crate) const FACTS: Facts = Facts {
    name: "ioc",
    description: "ROC over BVH levels [start, bottom] with a queue read-back per level (HPG 2020 poster)",
    submits_mid_frame: true,
    reads_marks: true,
    takes_dynamic: false,
    keeps_tree: true,
    layouts: &[Layout::Ioc, Layout::RocBoxes, Layout::Compact],
    ..Facts::GPU
};

/// Per-frame counts of the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IocCounts {
    /// Nodes in the queues of all levels (tested, frustum-culled or not).
    pub nodes_tested: u32,
    /// Levels processed (queues drawn), `start` down to at most `bottom`.
    pub levels: u32,
    /// Queue sizes read back between levels (each a submit and a wait).
    pub readbacks: u32,
}

/// The `ioc` method: level-by-level ROC on BVH nodes, with per-view state.
pub struct Ioc {
    n: u32,
    node_count: u32,
    start: u32,
    bottom: u32,
    start_len: u32,
    visible: wgpu::Buffer,
    next: wgpu::Buffer,
    fresh: wgpu::Buffer,
    marks: wgpu::Buffer,
    /// 0: the static start queue; 1 and 2: ping-pong for the levels below.
    queues: [wgpu::Buffer; 3],
    counts: [wgpu::Buffer; 3],
    expand_binds: Vec<wgpu::BindGroup>,
    box_binds: Vec<wgpu::BindGroup>,
    expand: wgpu::ComputePipeline,
    expand_bottom: wgpu::ComputePipeline,
    boxes: BoxPass,
    v_list: DrawList,
    u_list: DrawList,
    compactor: Compactor,
    v_job: CompactJob,
    u_job: CompactJob,
    marks_next: crate::cull::MarkTarget,
    last: IocCounts,
    debug: bool,
    debug_queues: Vec<Vec<u32>>,
}

/// The queue a level's output goes to.
fn out_of(q: usize) -> usize {
    if q == 1 {
        2
    } else {
        1
    }
}

impl Ioc {
    /// `range`: the depths [start, bottom]; `None` picks [`cpu::default_range`].
    pub fn new(cx: &MethodContext, range: Option<(u32, u32)>) -> Result<Self> {
        let (gpu, bvh) = (cx.gpu, cx.bvh);
        let (start, bottom) = range.unwrap_or_else(|| cpu::default_range(bvh.depth()));
        if start > bottom {
            return Err(Error::Arg(format!("IOC range {start}:{bottom}: start deeper than bottom")));
        }
        let n = cx.object_count;
        let node_count = bvh.nodes.len() as u32;
        use wgpu::BufferUsages as U;
        let flags = |label, len: u32| gpu.buffer(label, len as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let (visible, next, fresh) = (flags("ioc V", n), flags("ioc next V", n), flags("ioc fresh", n));
        let marks = flags("ioc node marks", node_count);
        let start_queue = cpu::start_queue(bvh, start);
        let start_len = start_queue.len() as u32;
        let queues =
            [gpu.buffer_init("ioc start queue", bytemuck::cast_slice(&start_queue), U::STORAGE | U::COPY_SRC), flags("ioc queue a", node_count), flags("ioc queue b", node_count)];
        let counts = [gpu.buffer_init("ioc start count", bytemuck::bytes_of(&start_len), U::STORAGE | U::COPY_SRC), flags("ioc count a", 1), flags("ioc count b", 1)];
        let (order, ranges) = cpu::leaf_ranges(bvh);
        let leaf_objects = gpu.buffer_init("ioc leaf objects", bytemuck::cast_slice(&order), U::STORAGE);
        let leaf_range = gpu.buffer_init("ioc leaf ranges", bytemuck::cast_slice(&ranges), U::STORAGE);
        let nodes = cx.bvh_nodes.clone();

        let layout = Layout::Ioc.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "ioc", &layout);
        let module = gpu.shader("ioc.wgsl", &shader_source("ioc.wgsl"));
        let expand_binds = (0..3)
            .map(|q| {
                let o = out_of(q);
                gpu.bind_buffers(&layout, &[cx.frame, &nodes, &marks, &queues[q], &counts[q], &queues[o], &counts[o], &visible, &fresh, &leaf_objects, &leaf_range])
            })
            .collect();
        let boxes = BoxPass::new(cx, false);
        let box_binds = (0..3).map(|q| boxes.bind(gpu, cx.frame, &queues[q], &nodes, &marks)).collect();
        let compactor = Compactor::new(gpu, n);
        let (v_list, v_job) = compactor.packed_list(gpu, "ioc V list", &visible, cx.commands);
        let (u_list, u_job) = compactor.packed_list(gpu, "ioc U list", &fresh, cx.commands);
        Ok(Ioc {
            n,
            node_count,
            start,
            bottom,
            start_len,
            marks_next: cx.mark_target(&next, None),
            expand: gpu.compute_pipeline(&module, "expand", Some(&pl), &[("BOTTOM", 0.0)]),
            expand_bottom: gpu.compute_pipeline(&module, "expand", Some(&pl), &[("BOTTOM", 1.0)]),
            visible,
            next,
            fresh,
            marks,
            queues,
            counts,
            expand_binds,
            box_binds,
            boxes,
            v_list,
            u_list,
            compactor,
            v_job,
            u_job,
            last: IocCounts::default(),
            debug: false,
            debug_queues: Vec::new(),
        })
    }

    /// The depth range [start, bottom] in use.
    pub fn range(&self) -> (u32, u32) {
        (self.start, self.bottom)
    }

    /// With `on`, every frame also reads back each level's queue (an extra
    /// stall per level; for the CPU reference only).
    pub fn set_debug(&mut self, on: bool) {
        self.debug = on;
    }

    /// Each level's queue of the last frame, sorted (with [`Ioc::set_debug`]).
    pub fn debug_queues(&self) -> &[Vec<u32>] {
        &self.debug_queues
    }

    /// Per-node decision bits of the last frame (1 = a box fragment passed,
    /// 2 = box rasterized, 4 = visible untested; see `ioc.wgsl`).
    pub fn node_marks(&self, gpu: &Gpu) -> Result<Vec<u32>> {
        gpu.read(&self.marks, 0, self.node_count as u64)
    }

    /// Last frame's V and the objects it drew after the test (not in V).
    pub fn sets(&self, gpu: &Gpu) -> Result<(Vec<bool>, Vec<bool>)> {
        let read = |b: &wgpu::Buffer| -> Result<Vec<bool>> { Ok(gpu.read::<u32>(b, 0, self.n as u64)?.iter().map(|&x| x != 0).collect()) };
        Ok((read(&self.visible)?, read(&self.fresh)?))
    }

    /// Counts of the last frame (kept on the CPU, no read-back).
    pub fn counts(&self) -> IocCounts {
        self.last
    }
}

impl CullMethod for Ioc {
    fn method(&self) -> Method {
        Method::Ioc
    }

    fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.visible, 0, None);
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // 1. Occlusion map.
        f.stage(Stage::OcclusionMap);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.v_job);
        enc.counted_clear(&self.next, 0, None);
        f.draw(Phase::Occluders, &self.v_list, Some(&self.marks_next));
        // 2. Levels start..=bottom.
        f.stage(Stage::OcclusionTest);
        let enc = f.encoder();
        for b in [&self.marks, &self.fresh] {
            enc.counted_clear(b, 0, None);
        }
        self.last = IocCounts::default();
        self.debug_queues.clear();
        let (mut q, mut count, mut level) = (0usize, self.start_len, self.start);
        while count > 0 && self.node_count > 0 {
            if self.debug {
                let mut queue = f.read_u32(&self.queues[q], count as u64)?;
                queue.sort_unstable();
                self.debug_queues.push(queue);
            }
            self.last.nodes_tested += count;
            self.last.levels += 1;
            self.boxes.record(f, &self.box_binds[q], BoxCount::Direct(count));
            let bottom = level >= self.bottom;
            let o = out_of(q);
            let (enc, pq) = f.counted();
            enc.counted_clear(&self.counts[o], 0, None);
            {
                let mut pass =
                    enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some(if bottom { "ioc expand bottom" } else { "ioc expand" }), timestamp_writes: None });
                let (x, y) = dispatch_size(count, 256);
                pq.around(&mut pass, |pass| {
                    pass.set_pipeline(if bottom { &self.expand_bottom } else { &self.expand });
                    pass.set_bind_group(0, &self.expand_binds[q], &[]);
                    pass.counted_dispatch(x, y, 1);
                });
            }
            if bottom {
                break;
            }
            f.stage(Stage::ReadBack);
            count = f.read_u32(&self.counts[o], 1)?[0].min(self.node_count);
            self.last.readbacks += 1;
            f.stage(Stage::OcclusionTest);
            q = o;
            level += 1;
        }
        // 3. The newly visible objects.
        f.stage(Stage::OccludeeRendering);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.u_job);
        f.draw(Phase::Occludees, &self.u_list, Some(&self.marks_next));
        f.encoder().counted_copy(&self.next, 0, &self.visible, 0, self.n as u64 * 4);
        Ok(())
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let count = |b: &wgpu::Buffer| -> Result<f64> { Ok(gpu.read::<u32>(b, 0, 1)?[0] as f64) };
        let boxes = self.node_marks(gpu)?.iter().filter(|&&m| m & 2 != 0).count();
        let c = self.last;
        Ok(vec![
            (Stat::V, count(&self.v_list.count)?),
            (Stat::NodesTested, c.nodes_tested as f64),
            (Stat::Boxes, boxes as f64),
            (Stat::Levels, c.levels as f64),
            (Stat::Readbacks, c.readbacks as f64),
            (Stat::U, count(&self.u_list.count)?),
        ])
    }

    fn tested_nodes(&self, gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(Some(self.node_marks(gpu)?.iter().enumerate().filter(|(_, &m)| m & 2 != 0).map(|(n, _)| n as u32).collect()))
    }
}
