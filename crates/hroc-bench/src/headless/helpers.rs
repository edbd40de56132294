//! What the bench records and reads back with on its device: buffers,
//! encoders, shaders, waits that report device errors, and blocking
//! read-backs ([`hroc_readback`]).

use super::Headless;
use crate::error::{Error, Result};
use wgpu::util::DeviceExt;

/// One command of a draw list as the GPU reads it
/// (`DrawIndexedIndirectArgs`): `first_instance` is the object.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DrawCommand {
    /// Indices to draw.
    pub index_count: u32,
    /// 1, or 0: culled.
    pub instance_count: u32,
    /// The object's first index.
    pub first_index: u32,
    /// The object's base vertex.
    pub base_vertex: i32,
    /// The object.
    pub first_instance: u32,
}

fn read_error(e: hroc_readback::Error) -> Error {
    Error::Device(e.to_string())
}

impl Headless {
    /// Routes the device's uncaptured errors to [`Headless::check`] instead
    /// of wgpu's default panic.
    pub(super) fn capture_errors(&self) {
        let sink = self.errors.clone();
        self.device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
            slot.get_or_insert_with(|| e.to_string().lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(": "));
        }));
    }

    /// The device's limits.
    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// A buffer holding `contents` (16 bytes at least, so an empty list still binds).
    pub fn buffer_init(&self, label: &str, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let mut padded = contents.to_vec();
        padded.resize(contents.len().max(16), 0);
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: &padded, usage })
    }

    /// A zeroed buffer of at least `size` bytes (16 at least, a multiple of 4).
    pub fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16).next_multiple_of(4), usage, mapped_at_creation: false })
    }

    /// A command encoder.
    pub fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// A WGSL module; on a device without `SHADER_EARLY_DEPTH_TEST`
    /// (which rejects the attribute), without `@early_depth_test(force)`.
    pub fn shader(&self, label: &str, source: &str) -> wgpu::ShaderModule {
        let source = match self.device.features().contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST) {
            true => source.to_string(),
            false => source.replace("@early_depth_test(force)", ""),
        };
        self.device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(source.into()) })
    }

    /// A bind group of whole buffers at bindings 0, 1, 2, ...
    pub fn bind_buffers(&self, layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        let entries: Vec<_> = buffers.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() }).collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
    }

    /// Blocks until the submitted work is done; reports any device error.
    pub fn wait(&self) -> Result<()> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::Device(format!("poll: {e}")))?;
        self.check()
    }

    /// The first error the device reported since it was opened, if any.
    pub fn check(&self) -> Result<()> {
        match self.errors.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
            Some(e) => Err(Error::Device(e.clone())),
            None => Ok(()),
        }
    }

    /// `count` items of `T` of `src` from item `first`. Submits and waits.
    pub fn read<T: bytemuck::Pod>(&self, src: &wgpu::Buffer, first: u64, count: u64) -> Result<Vec<T>> {
        let items = hroc_readback::read(&self.device, &self.queue, src, first, count).map_err(read_error)?;
        self.check()?;
        Ok(items)
    }

    /// The commands of a draw list within its GPU count, in list order.
    /// Submits and waits.
    pub fn read_list(&self, commands: &wgpu::Buffer, count: &wgpu::Buffer, max_count: u32) -> Result<Vec<DrawCommand>> {
        let n = self.read::<u32>(count, 0, 1)?[0].min(max_count);
        self.read(commands, 0, n as u64)
    }

    /// Mip 0 of a 2D texture of 4-byte texels, row by row ([`hroc_readback::read_texture`]).
    pub fn read_texture<T: bytemuck::Pod>(&self, tex: &wgpu::Texture, aspect: wgpu::TextureAspect) -> Result<Vec<T>> {
        hroc_readback::read_texture(&self.device, &self.queue, tex, aspect).map_err(read_error)
    }

    /// Layer 0 of a depth target, every sample ([`hroc_readback::read_depth`]).
    pub fn read_depth(&self, tex: &wgpu::Texture) -> Result<Vec<f32>> {
        self.read_depth_layer(tex, 0)
    }

    /// `layer` of a depth target, every sample ([`hroc_readback::read_depth`]).
    pub fn read_depth_layer(&self, tex: &wgpu::Texture, layer: u32) -> Result<Vec<f32>> {
        hroc_readback::read_depth(&self.device, &self.queue, tex, layer).map_err(read_error)
    }

    /// The object IDs of an ID target, every sample ([`hroc_readback::read_ids`]).
    pub fn read_ids(&self, tex: &wgpu::Texture) -> Result<Vec<u32>> {
        hroc_readback::read_ids(&self.device, &self.queue, tex).map_err(read_error)
    }
}
