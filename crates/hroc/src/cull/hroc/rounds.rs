//! Front-to-back rounds over one list (U in step 4, or V in step 1):
//! each round draws the list's objects whose box is nearest at some block
//! and tests the rest again against the depth that left.

use super::*;
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::shape::{DeviceShape, EncoderShape, PassShape, RenderShape};
use crate::gpu::{dispatch_size, Gpu};
use stall_free::Counted;

/// Front-to-back rounds over one list ([`RoundsOf`]): U in step 4 with
/// [`MethodOptions::hroc_rounds`](super::MethodOptions) above 1, or V in
/// step 1 with [`MethodOptions::hroc_occluder_rounds`](super::MethodOptions)
/// ([`OCCLUDER_ROUNDS`] of them). Round k's candidates are flagged k + 1:
/// the list's own marks in round 0, then the late test's marks, in two
/// buffers that take turns; front marks are k + 1 too.
pub(super) struct Rounds {
    pub(super) count: u32,
    /// Front marks, and round k + 1's candidates by the parity of k.
    pub(super) front: wgpu::Buffer,
    pub(super) alive: [wgpu::Buffer; 2],
    /// One draw of U's boxes, 36 |U| vertices (sized on the GPU).
    pub(super) box_args: wgpu::Buffer,
    /// Nearest candidate box depth over the blocks' occlusion map.
    pub(super) front_map: Blocks,
    /// Per round: the bindings of its front passes and of its late test.
    pub(super) front_binds: Vec<wgpu::BindGroup>,
    pub(super) late_binds: Vec<wgpu::BindGroup>,
    pub(super) init: wgpu::ComputePipeline,
    pub(super) init_bind: wgpu::BindGroup,
    pub(super) front_depth: wgpu::RenderPipeline,
    pub(super) front_marks: wgpu::RenderPipeline,
    pub(super) late: wgpu::RenderPipeline,
    /// Each round's front list, but the last round's.
    pub(super) fronts: Vec<(DrawList, CompactJob)>,
    /// The last round's list: its candidates, all drawn.
    pub(super) last: (DrawList, CompactJob),
}

/// Which list [`Hroc::rounds`] draws front to back.
#[derive(Clone, Copy)]
pub(super) enum RoundsOf {
    /// V, in step 1 ([`MethodOptions::hroc_occluder_rounds`](super::MethodOptions)).
    Occluders,
    /// U, in step 4 ([`MethodOptions::hroc_rounds`](super::MethodOptions)).
    Occludees,
}

impl Hroc {
    /// Front-to-back rounds over `r`'s candidates: in each round but the
    /// last, the candidates whose box is nearest at some block are drawn,
    /// and the others are tested again, alone, against the depth those
    /// draws left; the last round draws all of its candidates. Round 0's
    /// candidates are U in step 4 (or V in step 1), whose list (just
    /// compacted) instances every box pass.
    pub(super) fn rounds(&self, f: &mut Frame, r: &Rounds, of: RoundsOf) -> Result<()> {
        let n = self.n;
        let (stage, draw_stage, phase, marks, last_counted) = match of {
            RoundsOf::Occluders => (Stage::OccluderRounds, Stage::OcclusionMap, Phase::Occluders, Some(&self.marks_o), Counted::OccluderRest),
            RoundsOf::Occludees => (Stage::OccludeeRounds, Stage::OccludeeRendering, Phase::Occludees, self.d_marks(), Counted::U),
        };
        let front_counted = |k| match of {
            RoundsOf::Occluders => Counted::OccluderFront,
            RoundsOf::Occludees => Counted::Front(k),
        };
        f.stage(stage);
        {
            let (enc, q) = f.counted();
            let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc rounds init"), timestamp_writes: None });
            q.around(&mut pass, |pass| {
                pass.set_pipeline(&r.init);
                pass.set_bind_group(0, &r.init_bind, &[]);
                let (x, y) = dispatch_size(n, 256);
                pass.counted_dispatch(x, y, 1);
            });
        }
        let boxes = |f: &mut Frame, label: &str, view: &wgpu::TextureView, write: bool, pipeline: &wgpu::RenderPipeline, bind: &wgpu::BindGroup| {
            let (enc, q) = f.counted();
            let depth_ops = write.then_some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store });
            let mut pass = enc.counted_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment { view, depth_ops, stencil_ops: None }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            q.around(&mut pass, |pass| {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, bind, &[]);
                pass.counted_draw_indirect(&r.box_args, 0);
            });
        };
        for k in 0..r.count - 1 {
            let (list, job) = &r.fronts[k as usize];
            // The nearest candidate boxes over the occlusion map, then the
            // candidates that own some of that depth.
            f.stage(stage);
            {
                let (enc, q) = f.counted();
                r.front_map.reduce(enc, &q);
            }
            let bind = &r.front_binds[k as usize];
            boxes(f, "hroc front depth", &r.front_map.view, true, &r.front_depth, bind);
            boxes(f, "hroc front", &r.front_map.view, false, &r.front_marks, bind);
            let over = self.compact(f, &[], job, Some(front_counted(k)));
            let max_count = self.max_count(f, front_counted(k), &list.count, n, stage)?;
            f.stage(draw_stage);
            let drawn = DrawList { max_count, ..list.clone() };
            self.draw_list(f, phase, &drawn, over, marks);
            // The other candidates against the depth just drawn.
            f.stage(stage);
            let targets = f.targets;
            if let Some(b) = &self.blocks {
                let (enc, q) = f.counted();
                b.reduce(enc, &q);
            }
            let test_view = self.blocks.as_ref().map_or(&targets.depth_attachment, |b| &b.view);
            boxes(f, "hroc late test", test_view, false, &r.late, &r.late_binds[k as usize]);
        }
        let (list, job) = &r.last;
        let over = self.compact(f, &[], job, Some(last_counted));
        let max_count = self.max_count(f, last_counted, &list.count, n, stage)?;
        f.stage(draw_stage);
        self.draw_list(f, phase, &DrawList { max_count, ..list.clone() }, over, marks);
        Ok(())
    }
}

impl Rounds {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        gpu: &Gpu,
        cx: &MethodContext,
        module: &wgpu::ShaderModule,
        scale: u32,
        test_depth: (wgpu::TextureFormat, crate::DepthRange, u32),
        occlusion_map: &wgpu::TextureView,
        count: u32,
        list_marks: &wgpu::Buffer,
        list: &DrawList,
        compactor: &Compactor,
    ) -> Rounds {
        // Each round but the last has a front list; the stall-free counters
        // count V's as exactly two lists.
        debug_assert!(count >= 2, "rounds over one list: at least a front round and the last");
        use wgpu::BufferUsages as U;
        let device = &gpu.device;
        let n = cx.object_count;
        let flags = |label| gpu.buffer(label, n as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let (front, alive) = (flags("hroc front marks"), [flags("hroc round candidates"), flags("hroc round candidates")]);
        let unused = gpu.buffer("hroc unused", 4, U::STORAGE);
        let box_args = gpu.buffer_init("hroc round boxes", bytemuck::cast_slice(&[0u32, 1, 0, 0]), U::INDIRECT | U::STORAGE);
        let layout = crate::reflect::Layout::HrocRounds.create_for(gpu, cx.targets.samples);
        let init_layout = crate::reflect::Layout::HrocRoundsInit.create_for(gpu, cx.targets.samples);
        let candidates = |k: u32| if k == 0 { list_marks } else { &alive[(k as usize - 1) % 2] };
        let (mut front_binds, mut late_binds, mut init_bind) = (Vec::new(), Vec::new(), None);
        for k in 0..count {
            let params = gpu.buffer_init("hroc round params", bytemuck::cast_slice(&[k + 1, k + 1, k + 2, 0]), U::UNIFORM);
            let bind = |layout: &wgpu::BindGroupLayout, marks: &wgpu::Buffer, front_in: &wgpu::Buffer, init: bool| {
                let mut buffers = vec![(0, cx.frame), (6, cx.bounds), (8, &params), (9, &list.commands), (10, marks), (11, candidates(k)), (12, front_in), (15, cx.oriented)];
                if init {
                    buffers.extend([(13, &list.count), (14, &box_args)]);
                }
                // The late test reads the map it tests against (read-only
                // there); the front passes write a map of their own.
                let mut entries: Vec<_> = buffers.iter().map(|&(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }).collect();
                entries.push(wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(occlusion_map) });
                device.counted_bind_group(&wgpu::BindGroupDescriptor { label: Some("hroc rounds"), layout, entries: &entries })
            };
            if k == 0 {
                init_bind = Some(bind(&init_layout, &front, &unused, true));
            }
            front_binds.push(bind(&layout, &front, &unused, false));
            late_binds.push(bind(&layout, candidates(k + 1), &front, false));
        }
        let (pl, init_pl) = (crate::reflect::pipeline_layout(gpu, "hroc rounds", &layout), crate::reflect::pipeline_layout(gpu, "hroc rounds init", &init_layout));
        let constants = [("TEST_SCALE", scale as f64)];
        let block_depth = (BLOCK_FORMAT, cx.targets.depth, 1);
        use crate::shaders::{box_pipeline, BoxDepth};
        let make_list = |label: &str, flags: &wgpu::Buffer, select: u32| {
            let list = compactor.list(gpu, label);
            let job = compactor.job_selecting(gpu, flags, select, cx.commands, &list.commands, &list.count);
            (list, job)
        };
        Rounds {
            count,
            front_map: Blocks::new(gpu, cx, module, scale),
            init: gpu.compute_pipeline(module, "rounds_init", Some(&init_pl), &constants),
            init_bind: init_bind.expect("at least one round"),
            front_depth: box_pipeline(gpu, "hroc front depth", &pl, module, ("front_vs", None), block_depth, BoxDepth::Write, &constants),
            front_marks: box_pipeline(gpu, "hroc front", &pl, module, ("round_vs", Some("front_fs")), block_depth, BoxDepth::Test, &constants),
            late: box_pipeline(gpu, "hroc late test", &pl, module, ("round_vs", Some("late_fs")), test_depth, BoxDepth::Test, &constants),
            fronts: (0..count - 1).map(|k| make_list("hroc front list", &front, k + 1)).collect(),
            last: make_list("hroc last round list", candidates(count - 1), count),
            front,
            alive,
            box_args,
            front_binds,
            late_binds,
        }
    }

    /// Clears the marks of the last frame.
    pub(super) fn clear(&self, enc: &mut wgpu::CommandEncoder) {
        for b in [&self.front, &self.alive[0], &self.alive[1]] {
            enc.counted_clear(b, 0, None);
        }
    }
}
