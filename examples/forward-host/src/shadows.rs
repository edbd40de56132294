//! The host's directional light: a cascaded shadow map, one layer of a
//! depth array per cascade, each cascade an orthographic view of its own
//! culled by hroc against its own depth, drawn depth-only with depth bias.
//! The main pass samples the array to shade.
//!
//! A cascade is culled against the cascade's depth, never the camera's: a
//! caster hidden from the camera can still cast a visible shadow.

use glam::{Mat4, Vec3};
use hroc::device::Marks;
use hroc::{Culler, DepthRange, FrameInput, Method, View, ViewDesc, ViewTargets};

/// Width and height of every cascade.
pub const CASCADE_SIZE: u32 = 256;

/// Most cascades the main shader reads (`Camera::cascades`).
pub const MAX_CASCADES: u32 = 4;

/// The depth bias of the shadow pass, away from the light (standard
/// depth: ≥ 0; reversed: ≤ 0), against shadow acne.
fn bias(depth: DepthRange) -> wgpu::DepthBiasState {
    let sign = if depth == DepthRange::Reversed { -1 } else { 1 };
    wgpu::DepthBiasState { constant: 2 * sign, slope_scale: 1.5 * sign as f32, clamp: 0.0 }
}

/// The light's shadow map: its cascades' targets, pipeline and views.
pub(crate) struct Shadows {
    pub(crate) count: u32,
    depth_range: DepthRange,
    map: wgpu::Texture,
    /// Every layer, for the main pass to sample.
    pub(crate) array: wgpu::TextureView,
    /// The comparison sampler of the main pass (lit where the fragment is
    /// no farther from the light than the map).
    pub(crate) sampler: wgpu::Sampler,
    layers: Vec<wgpu::TextureView>,
    uniforms: Vec<wgpu::Buffer>,
    binds: Vec<wgpu::BindGroup>,
    pipeline: wgpu::RenderPipeline,
    /// Each cascade's view of the culler.
    pub(crate) views: Vec<View>,
    /// The lists each cascade drew last frame: (commands, count, max count).
    pub(crate) lists: Vec<Vec<(wgpu::Buffer, wgpu::Buffer, u32)>>,
}

impl Shadows {
    /// `count` cascades (0 to [`MAX_CASCADES`]; 0: an unlit placeholder the
    /// main pass binds) culled by `method` in the `depth` convention,
    /// drawing vertices of `stride` bytes (position first) and `instances`.
    pub(crate) fn new(device: &wgpu::Device, culler: &Culler, (count, method): (u32, Method), depth: DepthRange, stride: u64, instances: &wgpu::Buffer) -> hroc::Result<Shadows> {
        if count > MAX_CASCADES {
            return Err(hroc::Error::InvalidView(format!("{count} shadow cascades: the host's shader reads at most {MAX_CASCADES}")));
        }
        // Two layers at least: wgpu's GL backend makes a one-layer texture a 2D one.
        let map = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: CASCADE_SIZE, height: CASCADE_SIZE, depth_or_array_layers: count.max(2) },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer = |c| {
            map.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2), base_array_layer: c, array_layer_count: Some(1), ..Default::default() })
        };
        let layers: Vec<wgpu::TextureView> = (0..count).map(layer).collect();
        let array = map.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            compare: Some(if depth == DepthRange::Reversed { wgpu::CompareFunction::GreaterEqual } else { wgpu::CompareFunction::LessEqual }),
            ..Default::default()
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::VERTEX, ty, count: None };
        let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow"),
            entries: &[entry(0, buffer(wgpu::BufferBindingType::Uniform)), entry(1, buffer(wgpu::BufferBindingType::Storage { read_only: true }))],
        });
        let uniforms: Vec<wgpu::Buffer> = (0..count)
            .map(|_| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("cascade"),
                    size: 64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let binds = uniforms
            .iter()
            .map(|u| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("cascade"),
                    layout: &layout,
                    entries: &[wgpu::BindGroupEntry { binding: 0, resource: u.as_entire_binding() }, wgpu::BindGroupEntry { binding: 1, resource: instances.as_entire_binding() }],
                })
            })
            .collect();
        // hroc: a cascade of a method that reads marks under early-Z needs a
        // marking fragment stage; the default (hzb) reads none, and the pass
        // then has no fragment stage at all.
        let marked = method.reads_marks() && culler.capabilities().marks == Marks::EarlyZ;
        let mut source = include_str!("shadow.wgsl").to_string();
        if marked {
            source += &format!("\n{}\n{}", include_str!("shadow_marked.wgsl"), hroc::device::marks_wgsl(1));
        }
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("shadow"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow"),
            bind_group_layouts: &[Some(&layout), Some(culler.marks_layout())],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow"),
            layout: Some(&pl),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout { array_stride: stride, step_mode: wgpu::VertexStepMode::Vertex, attributes: &wgpu::vertex_attr_array![0 => Float32x3] })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(if depth == DepthRange::Reversed { wgpu::CompareFunction::Greater } else { wgpu::CompareFunction::Less }),
                stencil: Default::default(),
                bias: bias(depth),
            }),
            multisample: Default::default(),
            fragment: marked.then(|| wgpu::FragmentState { module: &module, entry_point: Some("fs_shadow_marked"), compilation_options: Default::default(), targets: &[] }),
            multiview_mask: None,
            cache: None,
        });
        // hroc: one view per cascade, on its layer of the array, with no ID target.
        let views = (0..count).map(|c| culler.view(method, &ViewTargets::new(&map, depth).at(c, 0))).collect::<hroc::Result<Vec<_>>>()?;
        Ok(Shadows { count, depth_range: depth, array, sampler, layers, uniforms, binds, pipeline, views, lists: vec![Vec::new(); count as usize], map })
    }

    /// Each cascade's view and projection for the camera `view`/`proj` of
    /// the main view (a perspective: its field of view is read from
    /// `proj`), the light shining along `-toward_light` onto the scene in
    /// `scene`.
    pub(crate) fn fit(&self, view: Mat4, proj: Mat4, aspect: f32, toward_light: Vec3, scene: &hroc::Aabb) -> Vec<(Mat4, Mat4)> {
        let inv = view.inverse();
        let eye = inv.w_axis.truncate();
        // The lens from the projection: its vertical field of view and its
        // near plane (NDC z 0 standard, 1 reversed); the far plane only
        // matters up to the scene, which caps it.
        let fov_y_deg = (2.0 * (1.0 / proj.y_axis.y).atan()).to_degrees();
        let near_ndc = if self.depth_range == DepthRange::Reversed { 1.0 } else { 0.0 };
        let at_near = proj.inverse() * glam::Vec4::new(0.0, 0.0, near_ndc, 1.0);
        let near = -at_near.z / at_near.w;
        let camera = hroc_scene::Camera { eye, target: eye - inv.z_axis.truncate(), up: inv.y_axis.truncate(), fov_y_deg, near, far: f32::INFINITY };
        let reversed = self.depth_range == DepthRange::Reversed;
        hroc_scene::camera::cascades(&camera, aspect, toward_light, scene, self.count).iter().map(|c| (c.view, c.proj(reversed))).collect()
    }

    /// Records every cascade's frame into `encoder`: its view-projection,
    /// a clear, the cull and the depth-only draws of what comes back.
    pub(crate) fn record(
        &mut self,
        queue: &wgpu::Queue,
        culler: &Culler,
        encoder: &mut wgpu::CommandEncoder,
        (vertices, indices): (&wgpu::Buffer, &wgpu::Buffer),
        cascades: &[(Mat4, Mat4)],
    ) -> hroc::Result<()> {
        let far = if self.depth_range == DepthRange::Reversed { 0.0 } else { 1.0 };
        for (c, &(view, proj)) in cascades.iter().enumerate() {
            queue.write_buffer(&self.uniforms[c], 0, bytemuck::bytes_of(&(proj * view).to_cols_array_2d()));
            drop(depth_pass(encoder, &self.layers[c], Some(far)));
            let input = FrameInput { view: ViewDesc { view, proj, unclipped_depth: false }, cut: false, time: 0.0 };
            let (layer, pipeline, bind) = (&self.layers[c], &self.pipeline, &self.binds[c]);
            let mut lists = Vec::new();
            self.views[c].cull(culler, encoder, &input, &mut |enc: &mut wgpu::CommandEncoder, draw: &hroc::Draw| {
                let mut pass = depth_pass(enc, layer, None);
                pass.set_bind_group(0, bind, &[]);
                pass.set_vertex_buffer(0, vertices.slice(..));
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                draw.record(&mut pass, pipeline, 1);
                lists.push((draw.commands.clone(), draw.count.clone(), draw.max_count));
            })?;
            self.lists[c] = lists;
        }
        Ok(())
    }

    /// Each cascade's depth after the last frame, row by row.
    pub(crate) fn depth(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> hroc::Result<Vec<Vec<f32>>> {
        (0..self.count).map(|c| hroc_readback::read_depth(device, queue, &self.map, c).map_err(crate::read_error)).collect()
    }
}

/// A depth-only pass on one cascade: clears it to `Some(far)`, else loads it.
fn depth_pass<'e>(enc: &'e mut wgpu::CommandEncoder, layer: &wgpu::TextureView, clear: Option<f32>) -> wgpu::RenderPass<'e> {
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("shadow cascade"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: layer,
            depth_ops: Some(wgpu::Operations { load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
