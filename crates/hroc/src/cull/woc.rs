//! `woc`: warping-based occlusion culling \[LKE18\] (the HROC paper's WOC
//! row: single-layer warping, holes left open). One frame:
//! 1. warp — last frame's final depth buffer, forward-splatted into the
//!    current view (one point per old pixel, `atomicMin` on depth bits);
//!    pixels nothing lands on stay at the far plane (`woc_warp.wgsl`);
//! 2. Hi-Z build — hzb's pyramid over the warped depth (level 0 is the
//!    warp target);
//! 3. occlusion test — hzb's per-object test, every object, *before*
//!    anything is drawn;
//! 4. draw the survivors (packed in object order), then keep this frame's
//!    depth and camera for the next.
//!
//! Not conservative: a splat lands on one pixel, so near silhouettes the
//! warped depth can be nearer than what a pixel centre sees now, and an
//! object seen only there is culled. The bench reports its false negatives
//! and missing pixels as they are.
//!
//! \[LKE18\] itself is an *iterative backward* warp (each new pixel searches
//! the old depth buffer along the motion field), which fills the holes a
//! forward splat leaves where the view magnifies (walking forward). This is
//! the simpler forward splat the issue asks for: the `far_texels` statistic
//! counts the texels it leaves open, and with the bench's frame spacing
//! (60 frames over a 10 s path) they are most of the screen, so it culls
//! little beyond the frustum.

use crate::cull::facts::Facts;
use crate::gpu::shape::{DeviceShape, EncoderShape, PassShape};
use crate::reflect::Layout;
use glam::{DMat4, Mat4};

use super::hzb::{HizTest, Pyramid};
use super::{CullMethod, Frame, Method, MethodContext, Stage, Stat};
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::Gpu;

/// `woc`'s facts: not conservative, standard depth only.
pub(crate) const FACTS: Facts = Facts {
    name: "woc",
    description: "warping-based: last frame's depth reprojected, Hi-Z test before drawing (not conservative)",
    conservative: false,
    reversed_depth: false,
    layouts: &[Layout::WocWarp, Layout::HiZBuild, Layout::HiZTest, Layout::Compact],
    ..Facts::GPU
};

/// The `woc` method: forward-warped last-frame depth, Hi-Z tested before drawing.
pub struct Woc {
    size: (u32, u32),
    reproject: wgpu::Buffer,
    bind: wgpu::BindGroup,
    splat: wgpu::ComputePipeline,
    save: wgpu::ComputePipeline,
    pyramid: Pyramid,
    /// Level-0 texels no splat reached in the last frame (holes or sky).
    holes: wgpu::Buffer,
    test: HizTest,
    list: DrawList,
    compactor: Compactor,
    job: CompactJob,
    /// Last frame's view-projection.
    prev: Option<Mat4>,
}

/// A view-projection in f64 (the warp composes it with an inverse).
fn view_proj64(m: &Mat4) -> DMat4 {
    DMat4::from_cols_array(&m.to_cols_array().map(|x| x as f64))
}

impl Woc {
    /// Creates the warp, pyramid, test and list for the view's targets (`woc` takes standard depth only).
    pub fn new(cx: &MethodContext) -> Self {
        let gpu = cx.gpu;
        let n = cx.object_count;
        let (w, h) = (cx.targets.size.0, cx.targets.size.1);
        use wgpu::BufferUsages as U;
        let reproject = gpu.buffer("woc reprojection", 64, U::UNIFORM | U::COPY_DST);
        let prev_depth = gpu.buffer("woc previous depth", w as u64 * h as u64 * 4, U::STORAGE | U::COPY_SRC);
        let flags = gpu.buffer("woc flags", n as u64 * 4, U::STORAGE | U::COPY_SRC);
        let unused = gpu.buffer("woc unused", 16, U::STORAGE);
        let pyramid = Pyramid::new(gpu, &cx.targets.depth_sampled, (w, h, cx.targets.samples), cx.targets.depth);
        // Level 0 starts at far; after that `save` resets it each frame.
        let far = vec![1.0f32; (w * h) as usize];
        gpu.queue.write_buffer(&pyramid.levels, 0, bytemuck::cast_slice(&far));
        let holes = gpu.buffer("woc holes", 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let test = HizTest::new(cx, &pyramid, &unused, &flags, false);
        let layout = Layout::WocWarp.create_for(gpu, cx.targets.samples);
        let bind = gpu.device.counted_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("woc warp"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: cx.frame.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: reproject.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: prev_depth.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: pyramid.levels.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&cx.targets.depth_sampled) },
                wgpu::BindGroupEntry { binding: 5, resource: holes.as_entire_binding() },
            ],
        });
        let pl = crate::reflect::pipeline_layout(gpu, "woc warp", &layout);
        let module = gpu.shader("woc_warp.wgsl", &crate::shaders::source_for("woc_warp.wgsl", cx.targets.samples));
        let list = DrawList {
            commands: gpu.buffer("woc list", n as u64 * 20, U::STORAGE | U::INDIRECT | U::COPY_SRC),
            count: gpu.buffer("woc count", 4, U::STORAGE | U::INDIRECT | U::COPY_SRC),
            max_count: n,
        };
        let compactor = Compactor::new(gpu, n);
        let job = compactor.job(gpu, &flags, cx.commands, &list.commands, &list.count);
        Woc {
            size: (w, h),
            reproject,
            bind,
            splat: gpu.compute_pipeline(&module, "splat", Some(&pl), &[]),
            save: gpu.compute_pipeline(&module, "save", Some(&pl), &[]),
            pyramid,
            holes,
            test,
            list,
            compactor,
            job,
            prev: None,
        }
    }

    fn dispatch(&self, f: &mut Frame, label: &str, pipeline: &wgpu::ComputePipeline) {
        let (enc, q) = f.counted();
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None });
        q.around(&mut pass, |pass| {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind, &[]);
            pass.counted_dispatch(self.size.0.div_ceil(16), self.size.1.div_ceil(16), 1);
        });
    }
}

impl CullMethod for Woc {
    fn method(&self) -> Method {
        Method::Woc
    }

    fn reset(&mut self, _enc: &mut wgpu::CommandEncoder) {
        self.prev = None;
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // 1. Warp last frame's depth (none on the first frame: all holes).
        f.stage(Stage::Warp);
        if let Some(prev) = self.prev {
            let m = view_proj64(&f.geometry.view_proj) * view_proj64(&prev).inverse();
            let m = Mat4::from_cols_array(&m.to_cols_array().map(|x| x as f32));
            f.write(&self.reproject, 0, bytemuck::cast_slice(&m.to_cols_array()));
            self.dispatch(f, "woc warp", &self.splat);
        }
        // 2. Pyramid of the warped depth.
        f.stage(Stage::HiZBuild);
        let (enc, q) = f.counted();
        self.pyramid.record_reduce(enc, &q);
        // 3. Every object against it.
        f.stage(Stage::OcclusionTest);
        let (enc, q) = f.counted();
        self.test.record(enc, &q);
        // 4. Draw the survivors; keep the depth for the next frame.
        f.stage(Stage::Draw);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.job);
        f.draw(Phase::Visible, &self.list, None);
        f.stage(Stage::SaveDepth);
        f.encoder().counted_clear(&self.holes, 0, None);
        self.dispatch(f, "woc save depth", &self.save);
        self.prev = Some(f.geometry.view_proj);
        Ok(())
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let (tested, near) = self.test.counts(gpu)?;
        let drawn = gpu.read::<u32>(&self.list.count, 0, 1)?[0];
        // Texels of the warped depth no splat reached: holes (or sky), which occlude nothing.
        let far = gpu.read::<u32>(&self.holes, 0, 1)?[0];
        Ok(vec![(Stat::Tested, tested as f64), (Stat::Near, near as f64), (Stat::U, drawn as f64), (Stat::FarTexels, far as f64), (Stat::Readbacks, 0.0)])
    }
}
