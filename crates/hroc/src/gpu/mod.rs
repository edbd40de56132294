//! The host's device and queue as the culler records with them, read-back
//! helpers, GPU timestamps and pipeline statistics.

mod cache;
mod readback;
pub mod shape;
pub mod stats;
pub mod timer;
mod uploads;

use crate::error::{Error, Result};
use crate::gpu::shape::{DeviceShape, EncoderShape, QueueShape};
use wgpu::util::DeviceExt;

pub use cache::{constants_key, Cache, RenderKey};
pub use readback::{Readback, Submission};
pub use shape::FrameShape;
pub use stats::{InvocationCounter, Invocations, PassCount};
pub use timer::GpuTimer;
pub use uploads::Uploads;

/// A device and its queue (cheap clones of the host's), with the helpers
/// the methods record with.
#[derive(Clone, Debug)]
pub struct Gpu {
    /// The host's device.
    pub device: wgpu::Device,
    /// The host's queue.
    pub queue: wgpu::Queue,
    /// Modules, layouts and pipelines made once, shared by every view
    /// of the culler (`cache.rs`).
    pub cache: cache::Cache,
}

impl Gpu {
    /// Wraps the host's device and queue (clones share them).
    pub fn from_device(device: &wgpu::Device, queue: &wgpu::Queue) -> Gpu {
        Gpu { device: device.clone(), queue: queue.clone(), cache: cache::Cache::default() }
    }

    /// The device's limits.
    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// A buffer holding `contents` (at least 16 bytes, so empty lists still bind).
    pub fn buffer_init(&self, label: &str, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        // wgpu rejects zero-sized mapped-at-creation buffers of odd sizes; keep a
        // minimum so empty lists still bind.
        let padded;
        let contents = if contents.len() < 16 {
            padded = {
                let mut v = contents.to_vec();
                v.resize(16, 0);
                v
            };
            &padded[..]
        } else {
            contents
        };
        shape::count(|s| s.buffers += 1);
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    }

    /// An uninitialized (zeroed) buffer of at least `size` bytes, 16 at least.
    pub fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        shape::count(|s| s.buffers += 1);
        self.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16).next_multiple_of(4), usage, mapped_at_creation: false })
    }

    /// A 1 × 1 texture of `format` and `samples` samples to fill a binding
    /// no pass reads. Multisampled, `format` must be one every backend can
    /// multisample (`Depth32Float` for depth; `Rg16Uint` for IDs).
    pub fn stand_in(&self, label: &str, format: wgpu::TextureFormat, samples: u32) -> wgpu::TextureView {
        // wgpu multisamples only textures that can be attached.
        let attach = if samples > 1 { wgpu::TextureUsages::RENDER_ATTACHMENT } else { wgpu::TextureUsages::empty() };
        self.device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | attach,
                view_formats: &[],
            })
            .create_view(&Default::default())
    }

    /// A command encoder.
    pub fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// Blocks until all submitted work is done (a lost device is an
    /// error; other device errors go to the host's own handler).
    pub fn wait(&self) -> Result<()> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::Gpu(format!("poll: {e}")))?;
        Ok(())
    }

    /// Copies `size` bytes of `src` from `offset` to the host. Submits and waits.
    pub fn read_bytes(&self, src: &wgpu::Buffer, offset: u64, size: u64) -> Result<Vec<u8>> {
        let size = size.next_multiple_of(4);
        if size == 0 {
            return Ok(Vec::new());
        }
        let staging = self.buffer("read-back", size, wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        let mut enc = self.encoder("read-back");
        enc.counted_copy(src, offset, &staging, 0, size);
        self.queue.counted_submit([enc.finish()]);
        self.map_read(&staging, size)
    }

    /// Maps a MAP_READ buffer already written by submitted work.
    pub fn map_read(&self, staging: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let slice = staging.slice(..size);
        let (tx, rx) = std::sync::mpsc::channel();
        shape::count(|s| s.map_requests += 1);
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv().map_err(|e| Error::Gpu(e.to_string()))?.map_err(|e| Error::Gpu(format!("map: {e}")))?;
        let data = slice.get_mapped_range().map_err(|e| Error::Gpu(format!("mapped range: {e:?}")))?.to_vec();
        staging.unmap();
        Ok(data)
    }

    /// Reads `count` items of `T` from `src`, starting at item `first`. Submits and waits.
    pub fn read<T: bytemuck::Pod>(&self, src: &wgpu::Buffer, first: u64, count: u64) -> Result<Vec<T>> {
        let sz = std::mem::size_of::<T>() as u64;
        let bytes = self.read_bytes(src, first * sz, count * sz)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes[..(count * sz) as usize]))
    }

    /// The commands of a draw list within its GPU count, in list order, as
    /// the draw read them (a debug read-back: submits and waits). Commands
    /// with `instance_count` 0 are emptied ones and draw nothing.
    pub fn read_list(&self, commands: &wgpu::Buffer, count: &wgpu::Buffer, max_count: u32) -> Result<Vec<crate::layout::DrawCommand>> {
        let n = self.read::<u32>(count, 0, 1)?[0].min(max_count);
        self.read(commands, 0, n as u64)
    }

    /// A WGSL module.
    ///
    /// On a device without `SHADER_EARLY_DEPTH_TEST` (DX12, Metal), which
    /// rejects the attribute, `@early_depth_test(force)` is removed: there
    /// the culler runs with ID marks and its box tests compare depth in the
    /// fragment stage, with no depth attachment to test early against.
    pub fn shader(&self, label: &str, source: &str) -> wgpu::ShaderModule {
        let source = match self.device.features().contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST) {
            true => std::borrow::Cow::Borrowed(source),
            false => std::borrow::Cow::Owned(without_early_z(source)),
        };
        self.cache
            .module(label, &source, || self.device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(source.clone()) }))
    }

    /// A compute pipeline at `entry`, with override `constants`.
    /// Made once per culler for each module, entry, layout and constants.
    pub fn compute_pipeline(&self, module: &wgpu::ShaderModule, entry: &str, layout: Option<&wgpu::PipelineLayout>, constants: &[(&str, f64)]) -> wgpu::ComputePipeline {
        self.cache.compute(module, entry, layout, constants, || {
            self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout,
                module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
                cache: None,
            })
        })
    }

    /// Bind group whose entries are whole buffers at bindings 0, 1, 2, ...
    pub fn bind_buffers(&self, layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        let entries: Vec<_> = buffers.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() }).collect();
        self.device.counted_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
    }
}

/// `source` without its `@early_depth_test(force)` attributes.
pub fn without_early_z(source: &str) -> String {
    source.replace("@early_depth_test(force)", "")
}

/// Workgroups for `n` threads of `size`, as a 2D grid when one dimension is
/// not enough (65535 groups per dimension); shaders rebuild the flat id.
pub fn dispatch_size(n: u32, size: u32) -> (u32, u32) {
    let groups = n.div_ceil(size).max(1);
    if groups <= 65535 {
        (groups, 1)
    } else {
        (65535, groups.div_ceil(65535))
    }
}
