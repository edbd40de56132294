//! Blocking read-backs for hroc's tests and tools: buffers, 2D textures
//! by copy, and depth or object-ID targets through a compute pass
//! (portable where depth cannot be copied to a buffer, as on wgpu's GL
//! backend, which lacks `DEPTH_TEXTURE_AND_BUFFER_COPIES`, and for
//! multisampled targets, which no copy reads). Every call submits its own
//! work on `queue` and waits for the device. Not for a renderer's frame:
//! the culler never reads back this way.

mod targets;

pub use targets::{read_depth, read_ids};

/// What a read-back can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Waiting for the device failed (it was lost, or timed out).
    #[error("poll: {0}")]
    Poll(String),
    /// The buffer could not be mapped.
    #[error("map: {0}")]
    Map(String),
}

/// A read-back's result.
pub type Result<T> = std::result::Result<T, Error>;

/// `count` items of `T` of `src` from item `first` (`src` has `COPY_SRC`).
pub fn read<T: bytemuck::Pod>(device: &wgpu::Device, queue: &wgpu::Queue, src: &wgpu::Buffer, first: u64, count: u64) -> Result<Vec<T>> {
    let item = std::mem::size_of::<T>() as u64;
    let size = (count * item).next_multiple_of(4);
    if size == 0 {
        return Ok(Vec::new());
    }
    let staging = staging(device, size);
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("read-back") });
    enc.copy_buffer_to_buffer(src, first * item, &staging, 0, size);
    queue.submit([enc.finish()]);
    let bytes = map(device, &staging, size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes[..(count * item) as usize]))
}

/// Mip 0, layer 0 of a 2D texture of 4-byte texels (`R32Uint`,
/// `R32Float`, `Depth32Float`, `Rgba8*`, with `COPY_SRC`), row by row.
pub fn read_texture<T: bytemuck::Pod>(device: &wgpu::Device, queue: &wgpu::Queue, tex: &wgpu::Texture, aspect: wgpu::TextureAspect) -> Result<Vec<T>> {
    let (w, h) = (tex.width(), tex.height());
    let row = (w * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let staging = staging(device, (row * h) as u64);
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("texture read-back") });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture: tex, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo { buffer: &staging, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(h) } },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    queue.submit([enc.finish()]);
    let bytes = map(device, &staging, (row * h) as u64)?;
    Ok((0..h as usize).flat_map(|y| bytemuck::pod_collect_to_vec::<u8, T>(&bytes[y * row as usize..][..w as usize * 4])).collect())
}

fn staging(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor { label: Some("read-back"), size, usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST, mapped_at_creation: false })
}

/// The first `size` bytes of `staging` (`MAP_READ`), once the work
/// submitted before has written them.
fn map(device: &wgpu::Device, staging: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
    let slice = staging.slice(..size);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::Poll(e.to_string()))?;
    rx.recv().map_err(|e| Error::Map(e.to_string()))?.map_err(|e| Error::Map(e.to_string()))?;
    let data = slice.get_mapped_range().map_err(|e| Error::Map(format!("{e:?}")))?.to_vec();
    staging.unmap();
    Ok(data)
}
