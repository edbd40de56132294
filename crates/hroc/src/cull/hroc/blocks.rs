//! The occlusion test on blocks of pixels: the blocks' occlusion map
//! (each block's farthest depth, of every sample of its pixels) and the
//! draw that reduces the host's depth to it.

use super::*;
use crate::gpu::shape::{DeviceShape, EncoderShape, RenderShape};
use crate::gpu::{Gpu, PassCount};

/// The occlusion map of the test's blocks (`reduce_fs` in `hroc_test.wgsl`),
/// which the box tests are attached to. The rays take the same farthest
/// depth from the host's (`block_limit`), so no pass samples the map, and
/// the reduction is the test pass's first draw ([`Blocks::record_in`]).
pub(super) struct Blocks {
    pub(super) scale: u32,
    pub(super) view: wgpu::TextureView,
    pub(super) bind: wgpu::BindGroup,
    pub(super) reduce: wgpu::RenderPipeline,
}

/// The largest block size up to `wanted` that divides both sides of `size`.
pub fn test_scale(wanted: u32, (w, h): (u32, u32)) -> u32 {
    (1..=wanted.max(1)).rev().find(|s| w % s == 0 && h % s == 0).unwrap_or(1)
}

/// Depth format of the blocks' occlusion map (depth formats are
/// renderable on every backend).
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
        let view = map("hroc test blocks", BLOCK_FORMAT);
        let layout = crate::reflect::Layout::HrocReduce.create_for(gpu, cx.targets.samples);
        let bind = device.counted_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hroc reduce"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: cx.frame.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&cx.targets.depth_sampled) },
            ],
        });
        let pl = crate::reflect::pipeline_layout(gpu, "hroc reduce", &layout);
        let constants = [("TEST_SCALE", scale as f64)];
        let key = crate::gpu::RenderKey {
            label: "hroc reduce".to_owned(),
            layout: pl.clone(),
            module: module.clone(),
            entries: ("reduce_vs".to_owned(), Some("reduce_fs".to_owned())),
            constants: crate::gpu::constants_key(&constants),
            depth: Some((BLOCK_FORMAT, wgpu::CompareFunction::Always, 0, true)),
            samples: 1,
            targets: Vec::new(),
        };
        let reduce = gpu.cache.render(key, || {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
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
            })
        });
        Blocks { scale, view, bind, reduce }
    }

    /// Reduces the host's depth (the occlusion map) to the blocks' farthest
    /// depth, in a pass of its own.
    pub(super) fn reduce(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount) {
        let mut pass = enc.counted_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hroc test blocks"),
            color_attachments: &[],
            depth_stencil_attachment: Some(self.attachment()),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        count.around(&mut pass, |pass| self.record_in(pass));
    }

    /// The map as a depth attachment that the reduction writes whole (the
    /// clear only keeps the pass from loading).
    pub(super) fn attachment(&self) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }
    }

    /// Draws the reduction into an open pass attached to the map (its
    /// pipeline writes every block, whatever the depth before).
    pub(super) fn record_in(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.reduce);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.counted_draw(0..3, 0..1);
    }
}
