//! `roc` and `roc-all`: raster occlusion culling (NVIDIA's, refs. KT14 and BK15 of Lee et al. 2021).
//!
//! One frame:
//! 1. occlusion map — draw V (last frame's visible set, packed in object
//!    order) with forced early-Z;
//! 2. occlusion test — rasterize the box of every object in the frustum
//!    (`roc`: only those not in V; `roc-all`: every one, the HROC paper's
//!    ROC row) against that depth with forced early-Z, depth writes off and
//!    a small bias toward the camera; a passing fragment marks the object
//!    (`roc_boxes.wgsl`). Boxes reaching the near plane lose fragments to
//!    clipping, so their objects are visible without a test (`roc.wgsl`);
//! 3. occludee rendering — draw the newly visible objects (packed in order).
//!
//! Next frame's V, the part where the two differ:
//! - `roc-all` keeps the test result of every object, as NVIDIA's temporal
//!   ROC does (its `bitsLast = bits`): an object of V stays in V while its
//!   box is not hidden by the depth of V.
//! - `roc` tests no box of V, so it has no test result for them; it keeps
//!   the objects that had a fragment pass early-Z when drawn (in step 1 or
//!   3), like HROC's O ∪ D. A V object hidden by another V object drawn
//!   before it still counts (early-Z is order-dependent), so V stays a
//!   superset of what owns pixels; what is dropped from V had no visible
//!   fragment and is tested again next frame. With ID marks
//!   ([`crate::capabilities::Marks::Ids`]) V is exactly what owns a pixel after step 1
//!   or 3, and the same holds.
//!
//! Both are conservative: an object owning a pixel is in V (drawn), or its
//! box's front face at that pixel lies in front of its surface, which lies
//! in front of (or on) the depth of V there, so the box fragment passes
//! `LessEqual` with the bias.

use super::{CullMethod, Frame, Method, MethodContext, Stage, Stat};
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::shape::{EncoderShape, PassShape, RenderShape};
use crate::gpu::{dispatch_size, Gpu};
use crate::layout::DrawArgs;
use crate::reflect::Layout;
use crate::shaders::source as shader_source;
use crate::shaders::{box_pipeline, BoxDepth, BoxTarget};

/// `roc`'s facts: it reads the marks of V's draw.
pub(crate) const FACTS: Facts = Facts {
    name: "roc",
    description: "raster occlusion culling: draw V, rasterize the boxes of the rest with early-Z, draw what passed",
    reads_marks: true,
    layouts: &[Layout::RocBoxes, Layout::Roc, Layout::Compact],
    ..Facts::GPU
};

/// `roc-all`'s facts: every object's box tested, no marks read.
pub(crate) const FACTS_ALL: Facts =
    Facts { name: "roc-all", description: "raster occlusion culling testing every object's box (the HROC paper's ROC)", reads_marks: false, ..FACTS };

/// The box rasterization test (`roc_boxes.wgsl`), shared with IOC: a
/// pipeline with forced early-Z on a read-only depth attachment, no depth
/// writes, `LessEqual` and a small bias toward the camera (as HROC's); or,
/// with ID marks (no forced early-Z), a pipeline whose fragments load the
/// depth and compare themselves ([`BoxTarget`]).
pub(crate) struct BoxPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    target: BoxTarget,
    depth: wgpu::TextureView,
}

/// How many boxes a [`BoxPass`] draws: from an indirect `DrawArgs` the GPU
/// filled, or a count the host knows.
pub(crate) enum BoxCount<'a> {
    Indirect(&'a wgpu::Buffer),
    /// `DrawArgs` at an offset of the buffer.
    IndirectAt(&'a wgpu::Buffer, u64),
    Direct(u32),
}

impl BoxPass {
    /// `commands`: the items are a list's indexed draw commands (box
    /// marks, [`super::marks::BoxMarks`]), not object indices.
    pub(crate) fn new(cx: &MethodContext, commands: bool) -> Self {
        let gpu = cx.gpu;
        let samples = cx.targets.samples;
        let layout = Layout::RocBoxes.create_for(gpu, samples);
        let pl = crate::reflect::pipeline_layout(gpu, "roc boxes", &layout);
        let module = gpu.shader("roc_boxes.wgsl", &crate::shaders::source_for("roc_boxes.wgsl", samples));
        // Marks from boxes that load depth themselves (on a device without
        // early-Z) rasterize at a reduced size, one sample.
        let scale = match commands {
            true if !cx.capabilities.attached_box_tests(&gpu.device, false) => super::marks::MARKS_SCALE.max(cx.options.box_marks_scale),
            true => cx.options.box_marks_scale.max(1),
            false => 1,
        };
        let (target, drawn) = match scale {
            1 => (BoxTarget::new(gpu, cx.capabilities, false, (cx.targets.size, samples)), samples),
            s => (BoxTarget::manual(gpu, (cx.targets.size.0.div_ceil(s), cx.targets.size.1.div_ceil(s))), 1),
        };
        let depth = (cx.targets.depth_format, cx.targets.depth, drawn);
        // Loading multisampled depth itself, the test runs per sample.
        let stages = if target.mode() == BoxDepth::Manual && drawn > 1 { ("box_vs_sample", Some("box_fs_sample")) } else { ("box_vs", Some("box_fs")) };
        let constants = [("MANUAL_DEPTH", target.manual_depth()), ("COMMANDS", commands as u32 as f64), ("MARKS_SCALE", scale as f64)];
        let pipeline = box_pipeline(gpu, "roc boxes", &pl, &module, stages, depth, target.mode(), &constants);
        // Attached, the test never loads depth: a stand-in fills the binding,
        // so GL (no read-only depth attachments) can attach the depth.
        let depth = match target.mode() {
            BoxDepth::Manual => cx.targets.depth_sampled.clone(),
            _ => gpu.stand_in("roc no depth", wgpu::TextureFormat::Depth32Float, samples),
        };
        BoxPass { pipeline, layout, target, depth }
    }

    /// Binds the frame uniform, the item list (one per instance), the boxes
    /// it indexes (object bounds or BVH nodes), the marks it sets and the
    /// view's depth.
    pub(crate) fn bind(&self, gpu: &Gpu, frame: &wgpu::Buffer, list: &wgpu::Buffer, boxes: &wgpu::Buffer, marks: &wgpu::Buffer) -> wgpu::BindGroup {
        let buffers = [frame, list, boxes, marks].map(|b| b.as_entire_binding());
        let mut resources: Vec<(u32, wgpu::BindingResource)> = buffers.into_iter().enumerate().map(|(i, r)| (i as u32, r)).collect();
        resources.push((4, wgpu::BindingResource::TextureView(&self.depth)));
        Layout::RocBoxes.bind(gpu, &self.layout, &resources)
    }

    pub(crate) fn record(&self, f: &mut Frame, bind: &wgpu::BindGroup, count: BoxCount) {
        self.record_all(f, "box occlusion test", &[(bind, count)]);
    }

    /// One pass `label` of a draw per `(bind group, count)`.
    pub(crate) fn record_all(&self, f: &mut Frame, label: &str, draws: &[(&wgpu::BindGroup, BoxCount)]) {
        let targets = f.targets;
        let (enc, q) = f.counted();
        let mut pass = self.target.begin(enc, label, &targets.depth_attachment);
        q.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            for (bind, count) in draws {
                pass.set_bind_group(0, *bind, &[]);
                match *count {
                    BoxCount::Indirect(args) => pass.counted_draw_indirect(args, 0),
                    BoxCount::IndirectAt(args, offset) => pass.counted_draw_indirect(args, offset),
                    BoxCount::Direct(n) => pass.counted_draw(0..36, 0..n),
                }
            }
        });
    }
}

/// The `roc` and `roc-all` methods, with per-view temporal state (V).
pub struct Roc {
    all: bool,
    n: u32,
    /// V: last frame's visible set, per object.
    visible: wgpu::Buffer,
    /// `roc`: objects with a fragment through early-Z this frame (next V).
    next: wgpu::Buffer,
    tested: wgpu::Buffer,
    candidates: wgpu::Buffer,
    args: wgpu::Buffer,
    v_list: DrawList,
    u_list: DrawList,
    compactor: Compactor,
    v_job: CompactJob,
    u_job: CompactJob,
    /// `roc`: where its lists mark next V (`roc-all` reads no marks).
    marks_next: Option<super::MarkTarget>,
    bind: wgpu::BindGroup,
    select: wgpu::ComputePipeline,
    split: wgpu::ComputePipeline,
    boxes: BoxPass,
    box_bind: wgpu::BindGroup,
    leaf_of_object: Vec<u32>,
}

impl Roc {
    /// `all`: test every object's box (`roc-all`), not only those outside V.
    pub fn new(cx: &MethodContext, all: bool) -> Self {
        let gpu = cx.gpu;
        let n = cx.object_count;
        use wgpu::BufferUsages as U;
        let flags = |label| gpu.buffer(label, n as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let (visible, next, tested, fresh, candidates) = (flags("roc V"), flags("roc next V"), flags("roc tested"), flags("roc fresh"), flags("roc boxes"));
        let args = gpu.buffer("roc box args", 16, U::STORAGE | U::INDIRECT | U::COPY_DST | U::COPY_SRC);
        let compactor = Compactor::new(gpu, n);
        let (v_list, v_job) = compactor.packed_list(gpu, "roc V list", &visible, cx.commands);
        let (u_list, u_job) = compactor.packed_list(gpu, "roc U list", if all { &fresh } else { &tested }, cx.commands);
        let layout = Layout::Roc.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "roc", &layout);
        let module = gpu.shader("roc.wgsl", &shader_source("roc.wgsl"));
        let constants = [("ALL", if all { 1.0 } else { 0.0 })];
        let boxes = BoxPass::new(cx, false);
        Roc {
            all,
            n,
            bind: gpu.bind_buffers(&layout, &[cx.frame, cx.bounds, &visible, &tested, &candidates, &args, &fresh]),
            select: gpu.compute_pipeline(&module, "select_boxes", Some(&pl), &constants),
            split: gpu.compute_pipeline(&module, "split", Some(&pl), &constants),
            box_bind: boxes.bind(gpu, cx.frame, &candidates, cx.bounds, &tested),
            boxes,
            marks_next: (!all).then(|| cx.mark_target(&next, None)),
            visible,
            next,
            tested,
            candidates,
            args,
            v_list,
            u_list,
            compactor,
            v_job,
            u_job,
            leaf_of_object: cx.bvh.leaf_of_object.clone(),
        }
    }

    fn dispatch(&self, f: &mut Frame, label: &str, pipeline: &wgpu::ComputePipeline) {
        let (x, y) = dispatch_size(self.n, 256);
        let (enc, q) = f.counted();
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None });
        q.around(&mut pass, |pass| {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind, &[]);
            pass.counted_dispatch(x, y, 1);
        });
    }

    /// Objects whose boxes the last frame rasterized.
    pub fn tested_objects(&self, gpu: &Gpu) -> Result<Vec<u32>> {
        let count = gpu.read::<DrawArgs>(&self.args, 0, 1)?[0].instance_count.min(self.n);
        let mut objects: Vec<u32> = gpu.read(&self.candidates, 0, count as u64)?;
        objects.sort_unstable();
        Ok(objects)
    }
}

impl CullMethod for Roc {
    fn method(&self) -> Method {
        if self.all {
            Method::RocAll
        } else {
            Method::Roc
        }
    }

    fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.visible, 0, None);
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // 1. Occlusion map: last frame's visible set.
        f.stage(Stage::OcclusionMap);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.v_job);
        if !self.all {
            enc.counted_clear(&self.next, 0, None);
        }
        f.draw(Phase::Occluders, &self.v_list, self.marks_next.as_ref());
        // 2. Box test.
        f.stage(Stage::OcclusionTest);
        let enc = f.encoder();
        enc.counted_clear(&self.tested, 0, None);
        enc.counted_clear(&self.args, 0, None);
        self.dispatch(f, "roc select", &self.select);
        self.boxes.record(f, &self.box_bind, BoxCount::Indirect(&self.args));
        if self.all {
            self.dispatch(f, "roc split", &self.split);
        }
        // 3. The newly visible objects.
        f.stage(Stage::OccludeeRendering);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.u_job);
        f.draw(Phase::Occludees, &self.u_list, self.marks_next.as_ref());
        if !self.all {
            let bytes = self.n as u64 * 4;
            f.encoder().counted_copy(&self.next, 0, &self.visible, 0, bytes);
        }
        Ok(())
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let count = |b: &wgpu::Buffer| -> Result<f64> { Ok(gpu.read::<u32>(b, 0, 1)?[0] as f64) };
        let boxes = gpu.read::<DrawArgs>(&self.args, 0, 1)?[0].instance_count;
        Ok(vec![(Stat::V, count(&self.v_list.count)?), (Stat::Boxes, boxes as f64), (Stat::U, count(&self.u_list.count)?), (Stat::Readbacks, 0.0)])
    }

    fn tested_nodes(&self, gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        let mut nodes: Vec<u32> = self.tested_objects(gpu)?.iter().map(|&o| self.leaf_of_object[o as usize]).collect();
        nodes.sort_unstable();
        Ok(Some(nodes))
    }
}
