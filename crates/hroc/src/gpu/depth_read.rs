//! Reads a depth texture back through a compute pass: portable where depth
//! cannot be copied to a buffer (wgpu's GL backend lacks
//! `DEPTH_TEXTURE_AND_BUFFER_COPIES`). For tests and the benchmark's checks.

use super::Gpu;
use crate::error::Result;

const WGSL: &str = "@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(depth);
    if id.x < size.x && id.y < size.y {
        out[id.y * size.x + id.x] = textureLoad(depth, id.xy, 0).r;
    }
}
";

impl Gpu {
    /// The depth of layer 0, mip 0 of `tex` (a depth format with
    /// `TEXTURE_BINDING`), row by row. Submits and waits.
    pub fn read_depth(&self, tex: &wgpu::Texture) -> Result<Vec<f32>> {
        let (w, h) = (tex.width(), tex.height());
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
        let layout = self.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("depth read-back"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(1, wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: false }, has_dynamic_offset: false, min_binding_size: None }),
            ],
        });
        let pl = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("depth read-back"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module = self.shader("depth read-back", WGSL);
        let pipeline = self.compute_pipeline(&module, "main", Some(&pl), &[]);
        let out = self.buffer("depth read-back", (w * h) as u64 * 4, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
        let view = tex.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            aspect: wgpu::TextureAspect::DepthOnly,
            mip_level_count: Some(1),
            array_layer_count: Some(1),
            ..Default::default()
        });
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("depth read-back"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
            ],
        });
        let mut enc = self.encoder("depth read-back");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("depth read-back"), timestamp_writes: None });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        self.queue.submit([enc.finish()]);
        self.read(&out, 0, (w * h) as u64)
    }
}
