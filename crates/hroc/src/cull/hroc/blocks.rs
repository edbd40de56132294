//! The occlusion test on blocks of pixels: the blocks' occlusion map
//! (each block's farthest depth, of every sample of its pixels) and the
//! pass that reduces the host's depth to it.

use crate::gpu::shape::{DeviceShape, EncoderShape, RenderShape};
use super::*;
use crate::gpu::{Gpu, PassCount};

/// The occlusion map of the test's blocks (`reduce_fs` in `hroc_test.wgsl`),
/// and, where the culler has early-Z marks but no read-only depth
/// attachments (GL), a copy: the box tests are attached to the map and
/// their rays load the copy, so no texture is attached and sampled in one
/// pass.
pub(super) struct Blocks {
    pub(super) scale: u32,
    pub(super) view: wgpu::TextureView,
    pub(super) copy: Option<wgpu::TextureView>,
    pub(super) bind: wgpu::BindGroup,
    pub(super) reduce: wgpu::RenderPipeline,
}

/// The largest block size up to `wanted` that divides both sides of `size`.
pub fn test_scale(wanted: u32, (w, h): (u32, u32)) -> u32 {
    (1..=wanted.max(1)).rev().find(|s| w % s == 0 && h % s == 0).unwrap_or(1)
}

/// Depth format of the blocks' occlusion map (and its copy: depth formats
/// are renderable on every backend).
pub(super) const BLOCK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl Blocks {
    pub(super) fn new(gpu: &Gpu, cx: &MethodContext, module: &wgpu::ShaderModule, scale: u32) -> Blocks {
        let device = &gpu.device;
        let (w, h) = cx.targets.size;
        let map = |label, format| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d { width: w / scale, height: h / scale, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let caps = cx.capabilities;
        let view = map("hroc test blocks", BLOCK_FORMAT);
        let copy = (caps.marks == crate::Marks::EarlyZ && !caps.read_only_depth).then(|| map("hroc test blocks copy", BLOCK_FORMAT));
        let layout = crate::reflect::Layout::HrocReduce.create_for(gpu, cx.targets.samples);
        let bind = device.counted_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hroc reduce"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: cx.frame.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::TextureView(&cx.targets.depth_sampled) },
            ],
        });
        let pl = crate::reflect::pipeline_layout(gpu, "hroc reduce", &layout);
        let constants = [("TEST_SCALE", scale as f64)];
        let reduce = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("hroc reduce"),
            layout: Some(&pl),
            vertex: wgpu::VertexState { module, entry_point: Some("reduce_vs"), compilation_options: Default::default(), buffers: &[] },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: BLOCK_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("reduce_fs"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        Blocks { scale, view, copy, bind, reduce }
    }

    /// Reduces the host's depth (the occlusion map) to the blocks' farthest
    /// depth, in the map and in its copy, if it has one.
    pub(super) fn reduce(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount) {
        for view in std::iter::once(&self.view).chain(&self.copy) {
            let mut pass = enc.counted_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hroc test blocks"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    // Every block is written; the clear only keeps the pass from loading.
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            count.around(&mut pass, |pass| {
                pass.set_pipeline(&self.reduce);
                pass.set_bind_group(0, &self.bind, &[]);
                pass.counted_draw(0..3, 0..1);
            });
        }
    }
}
