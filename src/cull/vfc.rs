//! `vfc`: GPU view-frustum culling, one thread per object box, then ordered
//! compaction into a packed list.

use super::{Culler, Frame, SceneContext};
use crate::error::Result;
use crate::gpu::dispatch_size;
use crate::render::{compact::{storage_entry, uniform_entry, CompactJob, Compactor}, shader_source, DrawList};

pub struct FrustumCuller {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    compactor: Compactor,
    job: CompactJob,
    list: DrawList,
}

impl FrustumCuller {
    pub fn new(cx: &SceneContext) -> Self {
        let (gpu, r) = (cx.gpu, cx.renderer);
        let n = r.object_count;
        use wgpu::BufferUsages as U;
        let flags = gpu.buffer("vfc flags", n as u64 * 4, U::STORAGE);
        let layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("vfc"),
            entries: &[uniform_entry(0), storage_entry(1, true), storage_entry(2, false)],
        });
        let pl = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("vfc"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module = gpu.shader("vfc.wgsl", &shader_source("vfc.wgsl"));
        let compactor = Compactor::new(gpu, n);
        let (list, job) = compactor.packed_list(gpu, "vfc list", &flags, &r.commands);
        FrustumCuller {
            pipeline: gpu.compute_pipeline(&module, "main", Some(&pl), &[]),
            bind: gpu.bind_buffers(&layout, &[&r.frame, &r.bounds, &flags]),
            compactor,
            job,
            list,
        }
    }
}

impl Culler for FrustumCuller {
    fn name(&self) -> &str {
        "vfc"
    }
    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage("frustum cull");
        let n = f.renderer.object_count;
        {
            let mut pass = f.encoder().begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind, &[]);
            let (x, y) = dispatch_size(n, 256);
            pass.dispatch_workgroups(x, y, 1);
        }
        f.stage("compact");
        self.compactor.record(f.encoder(), &self.job);
        f.stage("draw");
        f.draw(&self.list, None);
        Ok(())
    }
}
