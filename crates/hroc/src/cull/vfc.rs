//! `vfc`: GPU view-frustum culling, one thread per object box, then ordered
//! compaction into a packed list.

use super::{CullMethod, Frame, Method, MethodContext, Stage};
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::dispatch_size;
use crate::gpu::shape::{EncoderShape, PassShape};
use crate::reflect::Layout;
use crate::shaders::source as shader_source;

/// `vfc`'s facts.
pub(crate) const FACTS: Facts = Facts { name: "vfc", description: "GPU view-frustum culling", layouts: &[Layout::Vfc, Layout::Compact], ..Facts::GPU };

/// The `vfc` method: per-object frustum test, compacted into one list.
pub struct FrustumCuller {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    compactor: Compactor,
    job: CompactJob,
    list: DrawList,
}

impl FrustumCuller {
    /// Creates the test pipeline, flags and the compacted list for all objects.
    pub fn new(cx: &MethodContext) -> Self {
        let gpu = cx.gpu;
        let n = cx.object_count;
        use wgpu::BufferUsages as U;
        let flags = gpu.buffer("vfc flags", n as u64 * 4, U::STORAGE);
        let layout = Layout::Vfc.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "vfc", &layout);
        let module = gpu.shader("vfc.wgsl", &shader_source("vfc.wgsl"));
        let compactor = Compactor::new(gpu, n);
        let (list, job) = compactor.packed_list(gpu, "vfc list", &flags, cx.commands);
        FrustumCuller { pipeline: gpu.compute_pipeline(&module, "main", Some(&pl), &[]), bind: gpu.bind_buffers(&layout, &[cx.frame, cx.bounds, &flags]), compactor, job, list }
    }
}

impl CullMethod for FrustumCuller {
    fn method(&self) -> Method {
        Method::Vfc
    }

    fn plan_set(&mut self, _gpu: &crate::gpu::Gpu) -> Option<DrawList> {
        Some(self.list.clone())
    }

    fn planned_frame_needed(&self) -> bool {
        false
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // In a set of views, the set's pass packed the list.
        if f.set_frustum(&self.list) {
            return Ok(());
        }
        f.stage(Stage::FrustumCull);
        let n = f.object_count();
        {
            let (enc, q) = f.counted();
            let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("vfc frustum test"), timestamp_writes: None });
            let (x, y) = dispatch_size(n, 256);
            q.around(&mut pass, |pass| {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind, &[]);
                pass.counted_dispatch(x, y, 1);
            });
        }
        f.stage(Stage::Compact);
        let (enc, q) = f.counted();
        self.compactor.record(enc, &q, &self.job);
        f.stage(Stage::Draw);
        f.draw(Phase::Visible, &self.list, None);
        Ok(())
    }

    fn warm(&self, enc: &mut wgpu::CommandEncoder) {
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("vfc warm"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.counted_dispatch(0, 0, 0);
        self.compactor.warm(&mut pass, &self.job);
    }
}
