//! Depth and object-ID targets read through a compute pass, every sample.

use crate::Result;

/// The texels a read-back returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Texels {
    /// The depth aspect, as `f32`.
    Depth,
    /// Object IDs of an `R32Uint` or `Rg16Uint` target, as the culler
    /// decodes them (`host_id` in `common.wgsl`).
    Ids,
}

/// The read-back pass over one texture kind and sample count.
fn source(texels: Texels, samples: u32) -> String {
    let kind = if samples > 1 { "texture_multisampled_2d" } else { "texture_2d" };
    let (scalar, value) = match texels {
        Texels::Depth => ("f32", "v.r"),
        Texels::Ids => ("u32", "v.r | (v.g << 16u)"),
    };
    format!(
        "@group(0) @binding(0) var t: {kind}<{scalar}>;
@group(0) @binding(1) var<storage, read_write> out: array<{scalar}>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let size = textureDimensions(t);
    if id.x < size.x && id.y < size.y {{
        // An i32 level or sample: naga's GLSL bounds checks need one.
        for (var s = 0; s < {samples}; s++) {{
            let v = textureLoad(t, id.xy, s);
            out[(id.y * size.x + id.x) * {samples}u + u32(s)] = {value};
        }}
    }}
}}
"
    )
}

/// The depth of `layer`, mip 0 of `tex` (a depth format with
/// `TEXTURE_BINDING`), row by row, every sample of a pixel in turn
/// (`width × height × samples` values).
pub fn read_depth(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, layer: u32) -> Result<Vec<f32>> {
    read_target(device, queue, tex, layer, Texels::Depth)
}

/// The object IDs (`object index + 1`, 0 for nothing) of layer 0, mip 0
/// of `tex` (`R32Uint`, or `Rg16Uint` holding the ID in 16-bit halves,
/// with `TEXTURE_BINDING`), as [`read_depth`] orders them.
pub fn read_ids(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture) -> Result<Vec<u32>> {
    read_target(device, queue, tex, 0, Texels::Ids)
}

fn read_target<T: bytemuck::Pod>(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, layer: u32, texels: Texels) -> Result<Vec<T>> {
    let (w, h, samples) = (tex.width(), tex.height(), tex.sample_count());
    let sample_type = match texels {
        Texels::Depth => wgpu::TextureSampleType::Float { filterable: false },
        Texels::Ids => wgpu::TextureSampleType::Uint,
    };
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("target read-back"),
        entries: &[
            entry(0, wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled: samples > 1 }),
            entry(1, wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: false }, has_dynamic_offset: false, min_binding_size: None }),
        ],
    });
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("target read-back"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("target read-back"), source: wgpu::ShaderSource::Wgsl(source(texels, samples).into()) });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("target read-back"),
        layout: Some(&pl),
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let values = (w * h * samples) as u64;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("target read-back"),
        size: values * 4,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect: if texels == Texels::Depth { wgpu::TextureAspect::DepthOnly } else { wgpu::TextureAspect::All },
        mip_level_count: Some(1),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("target read-back"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
            wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
        ],
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("target read-back") });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("target read-back"), timestamp_writes: None });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    queue.submit([enc.finish()]);
    crate::read(device, queue, &out, 0, values)
}
