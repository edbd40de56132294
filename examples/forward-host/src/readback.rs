//! The host's own read-backs, for its tests and printout (not part of
//! culling): copy to a staging buffer, map it, wait.

use bytemuck::Pod;

/// Maps `staging` after the submitted work that fills it, and copies it out.
fn map(device: &wgpu::Device, staging: &wgpu::Buffer) -> hroc::Result<Vec<u8>> {
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| hroc::Error::Gpu(e.to_string()))?;
    rx.recv().map_err(|e| hroc::Error::Gpu(e.to_string()))?.map_err(|e| hroc::Error::Gpu(format!("map: {e}")))?;
    let data = slice.get_mapped_range().map_err(|e| hroc::Error::Gpu(format!("mapped range: {e:?}")))?.to_vec();
    staging.unmap();
    Ok(data)
}

fn staging(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor { label: Some("read-back"), size, usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST, mapped_at_creation: false })
}

/// The first `count` values of `src` (usage `COPY_SRC`).
pub fn buffer<T: Pod>(device: &wgpu::Device, queue: &wgpu::Queue, src: &wgpu::Buffer, count: u64) -> hroc::Result<Vec<T>> {
    let size = (count * std::mem::size_of::<T>() as u64).next_multiple_of(4).max(4);
    let out = staging(device, size);
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, 0, &out, 0, size);
    queue.submit([enc.finish()]);
    let bytes = map(device, &out)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes[..count as usize * std::mem::size_of::<T>()]))
}

/// The commands a [`hroc::Draw`] list drew: its `count` (at most `max_count`) first commands.
pub fn list(device: &wgpu::Device, queue: &wgpu::Queue, commands: &wgpu::Buffer, count: &wgpu::Buffer, max_count: u32) -> hroc::Result<Vec<wgpu::util::DrawIndexedIndirectArgs>> {
    let n = buffer::<u32>(device, queue, count, 1)?[0].min(max_count);
    let words: Vec<u32> = buffer(device, queue, commands, n as u64 * 5)?;
    Ok(words
        .chunks_exact(5)
        .map(|c| wgpu::util::DrawIndexedIndirectArgs { index_count: c[0], instance_count: c[1], first_index: c[2], base_vertex: c[3] as i32, first_instance: c[4] })
        .collect())
}

/// A 4-byte-per-texel texture's texels (mip 0, layer 0), row by row.
pub fn texture<T: Pod>(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, aspect: wgpu::TextureAspect) -> hroc::Result<Vec<T>> {
    let (w, h) = (tex.width(), tex.height());
    let row = (w * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let out = staging(device, (row * h) as u64);
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture: tex, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo { buffer: &out, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(h) } },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    queue.submit([enc.finish()]);
    let bytes = map(device, &out)?;
    Ok((0..h as usize).flat_map(|y| bytemuck::pod_collect_to_vec::<u8, T>(&bytes[y * row as usize..][..w as usize * 4])).collect())
}

/// A depth texture's depth (mip 0, layer `layer`), row by row, every sample
/// of a pixel in turn, read through a compute pass: GL cannot copy depth to
/// a buffer, and no copy reads a multisampled texture.
pub fn depth(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, layer: u32) -> hroc::Result<Vec<f32>> {
    through_shader(device, queue, tex, layer, false)
}

/// An object-ID target's IDs (`R32Uint`, or `Rg16Uint` halves), ordered as
/// [`depth`].
pub fn ids(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture) -> hroc::Result<Vec<u32>> {
    through_shader(device, queue, tex, 0, true)
}

fn through_shader<T: Pod>(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, layer: u32, ids: bool) -> hroc::Result<Vec<T>> {
    let (w, h, samples) = (tex.width(), tex.height(), tex.sample_count());
    let kind = if samples > 1 { "texture_multisampled_2d" } else { "texture_2d" };
    let (scalar, value, sample_type) = match ids {
        true => ("u32", "v.r | (v.g << 16u)", wgpu::TextureSampleType::Uint),
        // Depth loads as an unfilterable float texture on every backend.
        false => ("f32", "v.r", wgpu::TextureSampleType::Float { filterable: false }),
    };
    let wgsl = format!(
        "@group(0) @binding(0) var t: {kind}<{scalar}>;\n\
         @group(0) @binding(1) var<storage, read_write> out: array<{scalar}>;\n\
         @compute @workgroup_size(8, 8) fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             let size = textureDimensions(t);\n\
             if id.x < size.x && id.y < size.y {{\n\
                 for (var s = 0; s < {samples}; s++) {{ let v = textureLoad(t, id.xy, s); out[(id.y * size.x + id.x) * {samples}u + u32(s)] = {value}; }}\n\
             }}\n\
         }}\n"
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("target read-back"), source: wgpu::ShaderSource::Wgsl(wgsl.into()) });
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("target read-back"),
        entries: &[
            entry(0, wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled: samples > 1 }),
            entry(1, wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: false }, has_dynamic_offset: false, min_binding_size: None }),
        ],
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("target read-back"),
        layout: Some(&device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: None, bind_group_layouts: &[Some(&layout)], immediate_size: 0 })),
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
        aspect: if ids { wgpu::TextureAspect::All } else { wgpu::TextureAspect::DepthOnly },
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
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    queue.submit([enc.finish()]);
    buffer(device, queue, &out, values)
}
