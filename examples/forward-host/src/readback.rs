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
