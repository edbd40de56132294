//! `hzb`: two-phase Hi-Z occlusion culling as shipped by modern engines
//! (Nanite, niagara, Bevy). One frame:
//! 1. occlusion map (early pass) — draw V, last frame's visible set
//!    (packed in object order);
//! 2. Hi-Z build — a conservative depth pyramid of that depth: MAX
//!    reduction (standard depth: near 0, far 1, `Less`), whole footprints
//!    on non-power-of-two sizes (`hzb_pyramid.wgsl`);
//! 3. occlusion test (late pass) — every object's projected box against the
//!    level where its screen rect spans at most 2x2 texels, all of them
//!    read; boxes reaching the near plane are visible (`hzb_test.wgsl`);
//!    the result for every object is next frame's V (as niagara does);
//! 4. occludee rendering — draw what passed and was not in V.
//!
//! Failure modes of shipped implementations avoided here: a too fine mip
//! (reading 2x2 texels of a level where the rect spans more), dropping the
//! odd row/column of non-power-of-two levels, and projecting boxes that
//! cross the near plane.

pub mod cpu;

use super::{CullMethod, Frame, Method, MethodContext, Stage, Stat};
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::shape::{DeviceShape, EncoderShape, PassShape};
use crate::gpu::{dispatch_size, Gpu, PassCount};
use crate::reflect::Layout;
use crate::shaders::source as shader_source;

/// `hzb`'s facts.
pub(crate) const FACTS: Facts =
    Facts { name: "hzb", description: "two-phase Hi-Z culling (Nanite, niagara, Bevy)", layouts: &[Layout::HiZBuild, Layout::HiZTest, Layout::Compact], ..Facts::GPU };
pub use cpu::Mip;

/// Levels of at most this many texels are reduced by one workgroup, all of
/// them in one dispatch (a dispatch costs more than such a level on lavapipe).
const TAIL_TEXELS: u32 = 16384;

/// A Hi-Z pyramid of the renderer's depth target, every level in one
/// storage buffer (`f32` depth; level 0 at offset 0, full size).
pub struct Pyramid {
    /// Level layout ([`cpu::mip_chain`]): level 0 full size, down to 1x1.
    pub mips: Vec<Mip>,
    /// The levels, concatenated as [`cpu::mip_chain`] lays them out.
    pub levels: wgpu::Buffer,
    /// `mips` as a storage buffer of [`Mip`]s for the shaders.
    pub mip_table: wgpu::Buffer,
    from_depth: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
    reduce_tail: wgpu::ComputePipeline,
    /// One per level (its `Step` uniform).
    binds: Vec<wgpu::BindGroup>,
}

impl Pyramid {
    /// A pyramid for a `width` x `height` depth target of `samples`
    /// samples per pixel, built from `depth_view` (a pixel's farthest sample).
    pub fn new(gpu: &Gpu, depth_view: &wgpu::TextureView, (width, height, samples): (u32, u32, u32), depth: crate::DepthRange) -> Self {
        let reversed = (depth == crate::DepthRange::Reversed) as u32;
        use wgpu::BufferUsages as U;
        let mips = cpu::mip_chain(width, height);
        let texels = mips.last().map_or(1, |m| m.offset + 1);
        let levels = gpu.buffer("hi-z levels", texels as u64 * 4, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        let mip_table = gpu.buffer_init("hi-z mips", bytemuck::cast_slice(&mips), U::STORAGE);
        let layout = Layout::HiZBuild.create_for(gpu, samples);
        let pl = crate::reflect::pipeline_layout(gpu, "hi-z build", &layout);
        let module = gpu.shader("hzb_pyramid.wgsl", &crate::shaders::source_for("hzb_pyramid.wgsl", samples));
        let binds = (0..mips.len() as u32)
            .map(|l| {
                let step = gpu.buffer_init("hi-z step", bytemuck::cast_slice(&[l, reversed, 0, 0]), U::UNIFORM);
                gpu.device.counted_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("hi-z step"),
                    layout: &layout,
                    entries: &[
                        wgpu::BindGroupEntry { binding: 0, resource: step.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 1, resource: mip_table.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 2, resource: levels.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(depth_view) },
                    ],
                })
            })
            .collect();
        Pyramid {
            from_depth: gpu.compute_pipeline(&module, "from_depth", Some(&pl), &[]),
            reduce: gpu.compute_pipeline(&module, "reduce", Some(&pl), &[]),
            reduce_tail: gpu.compute_pipeline(&module, "reduce_tail", Some(&pl), &[]),
            mips,
            levels,
            mip_table,
            binds,
        }
    }

    /// Levels 0 and 1 from the depth target, then the reduction.
    pub fn record_from_depth(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount) {
        self.record(enc, count, true);
    }

    /// The reduction only (level 0 already written, as WOC's warp does).
    pub fn record_reduce(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount) {
        self.record(enc, count, false);
    }

    fn record(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount, from_depth: bool) {
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hi-z build"), timestamp_writes: None });
        count.around(&mut pass, |pass| self.record_levels(pass, from_depth));
    }

    fn record_levels(&self, pass: &mut wgpu::ComputePass<'_>, from_depth: bool) {
        let first = if from_depth {
            // Levels 0 and 1 at once, one thread per level-1 texel.
            let m = self.mips[1.min(self.mips.len() - 1)];
            pass.set_pipeline(&self.from_depth);
            pass.set_bind_group(0, &self.binds[0], &[]);
            pass.counted_dispatch(m.width.div_ceil(16), m.height.div_ceil(16), 1);
            2
        } else {
            1
        };
        for (l, m) in self.mips.iter().enumerate().skip(first) {
            if m.width * m.height <= TAIL_TEXELS {
                // This level and all above it in one workgroup.
                pass.set_pipeline(&self.reduce_tail);
                pass.set_bind_group(0, &self.binds[l], &[]);
                pass.counted_dispatch(1, 1, 1);
                break;
            }
            pass.set_pipeline(&self.reduce);
            pass.set_bind_group(0, &self.binds[l], &[]);
            pass.counted_dispatch(m.width.div_ceil(16), m.height.div_ceil(16), 1);
        }
    }

    /// Binds each pipeline with no work ([`crate::cull::CullMethod::warm`]).
    pub fn warm(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_bind_group(0, &self.binds[0], &[]);
        for p in [&self.from_depth, &self.reduce, &self.reduce_tail] {
            pass.set_pipeline(p);
            pass.counted_dispatch(0, 0, 0);
        }
    }

    /// Every level, read back (tests).
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        let texels = self.mips.last().map_or(1, |m| m.offset + 1);
        gpu.read(&self.levels, 0, texels as u64)
    }
}

/// The per-object test against a [`Pyramid`] (`hzb_test.wgsl`).
pub(crate) struct HizTest {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    /// Objects tested against the pyramid, and visible for reaching the near plane.
    pub stats: wgpu::Buffer,
    n: u32,
}

impl HizTest {
    /// `two_phase`: write `fresh` = passed and not in `visible`, then
    /// `visible` = passed; else `fresh` = passed (`visible` unused).
    pub(crate) fn new(cx: &MethodContext, pyramid: &Pyramid, visible: &wgpu::Buffer, fresh: &wgpu::Buffer, two_phase: bool) -> Self {
        let gpu = cx.gpu;
        let stats = gpu.buffer("hi-z test stats", 8, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC);
        let layout = Layout::HiZTest.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "hi-z test", &layout);
        let module = gpu.shader("hzb_test.wgsl", &shader_source("hzb_test.wgsl"));
        HizTest {
            pipeline: gpu.compute_pipeline(&module, "test", Some(&pl), &[("TWO_PHASE", if two_phase { 1.0 } else { 0.0 })]),
            bind: gpu.bind_buffers(&layout, &[cx.frame, cx.bounds, &pyramid.mip_table, &pyramid.levels, visible, fresh, &stats]),
            stats,
            n: cx.object_count,
        }
    }

    pub(crate) fn record(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount) {
        enc.counted_clear(&self.stats, 0, None);
        let (x, y) = dispatch_size(self.n, 256);
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hi-z test"), timestamp_writes: None });
        count.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind, &[]);
            pass.counted_dispatch(x, y, 1);
        });
    }

    /// Binds the pipeline with no work ([`crate::cull::CullMethod::warm`]).
    pub(crate) fn warm(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.counted_dispatch(0, 0, 0);
    }

    /// (tested, near-plane) of the last test.
    pub(crate) fn counts(&self, gpu: &Gpu) -> Result<(u32, u32)> {
        let s: Vec<u32> = gpu.read(&self.stats, 0, 2)?;
        Ok((s[0], s[1]))
    }
}

/// The `hzb` method: two-phase Hi-Z culling with per-view temporal state.
pub struct Hzb {
    n: u32,
    visible: wgpu::Buffer,
    pyramid: Pyramid,
    test: HizTest,
    v_list: DrawList,
    u_list: DrawList,
    compactor: Compactor,
    v_job: CompactJob,
    u_job: CompactJob,
}

impl Hzb {
    /// Creates the method's buffers, pyramid and pipelines for the view's targets.
    pub fn new(cx: &MethodContext) -> Self {
        let gpu = cx.gpu;
        let n = cx.object_count;
        use wgpu::BufferUsages as U;
        let flags = |label| gpu.buffer(label, n as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let (visible, fresh) = (flags("hzb V"), flags("hzb fresh"));
        let pyramid = Pyramid::new(gpu, &cx.targets.depth_sampled, (cx.targets.size.0, cx.targets.size.1, cx.targets.samples), cx.targets.depth);
        let test = HizTest::new(cx, &pyramid, &visible, &fresh, true);
        let compactor = Compactor::new(gpu, n);
        let (v_list, v_job) = compactor.packed_list(gpu, "hzb V list", &visible, cx.commands);
        let (u_list, u_job) = compactor.packed_list(gpu, "hzb U list", &fresh, cx.commands);
        Hzb { n, visible, pyramid, test, v_list, u_list, compactor, v_job, u_job }
    }

    /// The pyramid of the last frame (built from the depth of V).
    pub fn pyramid(&self) -> &Pyramid {
        &self.pyramid
    }

    /// The last frame's test result per object (next frame's V).
    pub fn test_result(&self, gpu: &Gpu) -> Result<Vec<bool>> {
        Ok(gpu.read::<u32>(&self.visible, 0, self.n as u64)?.iter().map(|&x| x != 0).collect())
    }
}

impl CullMethod for Hzb {
    fn method(&self) -> Method {
        Method::Hzb
    }

    fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.visible, 0, None);
    }

    fn visible_set(&self) -> Option<&wgpu::Buffer> {
        Some(&self.visible)
    }

    fn warm(&self, enc: &mut wgpu::CommandEncoder) {
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hzb warm"), timestamp_writes: None });
        self.pyramid.warm(&mut pass);
        self.test.warm(&mut pass);
        self.compactor.warm(&mut pass, &self.v_job);
    }

    fn take_over(&mut self, enc: &mut wgpu::CommandEncoder, visible: Option<&wgpu::Buffer>) {
        match visible {
            // Its early pass draws the set handed over, and its pyramid is
            // built from that depth: no frame drawing the whole frustum.
            Some(v) => enc.counted_copy(v, 0, &self.visible, 0, v.size().min(self.visible.size())),
            None => self.reset(enc),
        }
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // 1. Early pass: last frame's visible set.
        f.stage(Stage::OcclusionMap);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.v_job);
        f.draw(Phase::Occluders, &self.v_list, None);
        // 2. Pyramid of that depth.
        f.stage(Stage::HiZBuild);
        let (enc, q) = f.counted();
        self.pyramid.record_from_depth(enc, &q);
        // 3. Late pass: every object against it.
        f.stage(Stage::OcclusionTest);
        let (enc, q) = f.counted();
        self.test.record(enc, &q);
        // 4. The newly visible.
        f.stage(Stage::OccludeeRendering);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.u_job);
        f.draw(Phase::Occludees, &self.u_list, None);
        Ok(())
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let count = |b: &wgpu::Buffer| -> Result<f64> { Ok(gpu.read::<u32>(b, 0, 1)?[0] as f64) };
        let (tested, near) = self.test.counts(gpu)?;
        Ok(vec![(Stat::V, count(&self.v_list.count)?), (Stat::Tested, tested as f64), (Stat::Near, near as f64), (Stat::U, count(&self.u_list.count)?), (Stat::Readbacks, 0.0)])
    }
}
