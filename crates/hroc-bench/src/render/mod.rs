//! hroc's own renderer, the first host of the culling API: every mesh in
//! one vertex/index pool, one object = one indexed draw (its
//! `instance_index` is the object index), colour, depth and object-ID
//! targets. It draws whatever a [`hroc::View`] hands it ([`Recorder`]),
//! with forced early-Z and hroc's marks snippet, as the crate docs of
//! `hroc` ask of any host.

pub mod cascades;
pub mod pictures;

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::gpu::Headless;
use crate::scene::Scene;

/// A list the culler handed the renderer, kept to check the frame: the
/// draw's buffers (shared handles) and its bound.
#[derive(Clone, Debug)]
pub struct DrawList {
    /// `DrawIndexedIndirectArgs`, `first_instance` the object.
    pub commands: wgpu::Buffer,
    /// One u32: how many commands to draw.
    pub count: wgpu::Buffer,
    /// Upper bound on the count.
    pub max_count: u32,
}

pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The ID format of multisampled targets: `object + 1` split in 16-bit
/// halves (r low, g high), which every backend can multisample.
pub const MSAA_ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Uint;

/// The ID format of targets of `samples` samples per pixel.
pub fn id_format(samples: u32) -> wgpu::TextureFormat {
    if samples > 1 {
        MSAA_ID_FORMAT
    } else {
        ID_FORMAT
    }
}
const OVERDRAW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

/// Buffer sizes the renderer needs for a scene, checked against the device before upload.
pub fn check_limits(scene: &Scene, limits: &wgpu::Limits) -> Result<()> {
    let verts: u64 = scene.meshes.iter().map(|m| m.vertices.len() as u64).sum();
    let idx: u64 = scene.meshes.iter().map(|m| m.indices.len() as u64).sum();
    let n = scene.objects.len() as u64;
    let storage = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    let checks = [
        ("vertex pool", verts * std::mem::size_of::<crate::scene::Vertex>() as u64, limits.max_buffer_size),
        ("index pool", idx * 4, limits.max_buffer_size),
        ("object data", n * std::mem::size_of::<ObjectData>() as u64, storage),
    ];
    for (what, need, limit) in checks {
        if need > limit {
            return Err(Error::TooLarge(format!("{what} needs {need} bytes, the device allows {limit}")));
        }
    }
    if idx > u32::MAX as u64 || verts > i32::MAX as u64 {
        return Err(Error::TooLarge(format!("{idx} indices / {verts} vertices exceed 32-bit draw offsets")));
    }
    // The culler checks its own buffers and the object count (`Culler::new`).
    Ok(())
}

pub struct Targets {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of every target (MSAA above 1).
    pub samples: u32,
    pub color: wgpu::Texture,
    pub depth: wgpu::Texture,
    pub id: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    pub depth_view: wgpu::TextureView,
    pub id_view: wgpu::TextureView,
}

fn target(gpu: &Headless, label: &str, w: u32, h: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    target_of(gpu, label, (w, h, 1), 1, format)
}

/// A target of `layers` layers of `w` × `h` pixels of `samples` samples.
pub(crate) fn target_of(gpu: &Headless, label: &str, (w, h, layers): (u32, u32, u32), samples: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    // Multisampled textures cannot be copied.
    let copy = if samples > 1 { wgpu::TextureUsages::empty() } else { wgpu::TextureUsages::COPY_SRC };
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: layers },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | copy | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// Each object of `scene` as one indexed draw of the renderer's pool, in
/// object order: what the renderer registers with [`hroc::Culler`]. An
/// object whose transform turns its axes also gets its mesh's (or
/// cluster's) box in its own frame ([`oriented_box`]).
pub fn object_descs(scene: &Scene) -> Vec<hroc::ObjectDesc> {
    let (mut first_index, mut base_vertex, mut ranges) = (0u32, 0i32, Vec::new());
    for m in &scene.meshes {
        ranges.push((first_index, base_vertex, m.indices.len() as u32));
        first_index += m.indices.len() as u32;
        base_vertex += m.vertices.len() as i32;
    }
    scene
        .objects
        .iter()
        .map(|o| {
            let (first_index, base_vertex, _) = ranges[o.mesh as usize];
            let (first, index_count) = scene.meshes[o.mesh as usize].range(o.cluster);
            hroc::ObjectDesc { bounds: o.bounds, index_count, first_index: first_index + first, base_vertex, flags: hroc::ObjectFlags::NONE, oriented: oriented_box(scene, o) }
        })
        .collect()
}

/// The box of an object's mesh (or cluster) in the mesh's frame, placed by
/// its transform, when the transform turns axes away from axes: otherwise
/// that box is just the object's world box, and testing it twice gains
/// nothing. `None` also for a transform that cannot be inverted.
pub fn oriented_box(scene: &Scene, o: &hroc_scene::Object) -> Option<hroc::geometry::OrientedBox> {
    if hroc_scene::keeps_axes(&o.transform) {
        return None;
    }
    let b = hroc::geometry::OrientedBox::new(scene.meshes[o.mesh as usize].part_local_bounds(o.cluster), glam::Affine3A::from_mat4(o.transform));
    b.to_local().map(|_| b)
}

/// The renderer's per-object data (`ObjectData` in `draw.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObjectData {
    pub model: [[f32; 4]; 4],
    pub color: [f32; 4],
}

/// The renderer's uniform (`View` in `draw.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ViewUniform {
    pub view_proj: [[f32; 4]; 4],
    pub light_dir: [f32; 4],
}

/// The renderer's shader: its own structs and passes, then hroc's marks
/// snippet at group 1.
pub fn draw_wgsl() -> String {
    format!("{}\n{}", include_str!("draw.wgsl"), hroc::device::marks_wgsl(1))
}

pub struct Renderer {
    pub object_count: u32,
    pub targets: Targets,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub objects: wgpu::Buffer,
    /// Each object's indexed draw in the pool, in object order: what the
    /// renderer registers with the culler.
    pub descs: Vec<hroc::ObjectDesc>,
    pub frame: wgpu::Buffer,
    pub frame_layout: wgpu::BindGroupLayout,
    pub frame_bind: wgpu::BindGroup,
    no_marks: wgpu::BindGroup,
    draw: wgpu::RenderPipeline,
    draw_mark: wgpu::RenderPipeline,
    overdraw: wgpu::RenderPipeline,
    pub light_dir: Vec3,
    /// The draw shader and its pipeline layout, for passes of other targets
    /// ([`cascades::Cascades`]).
    pub(crate) module: wgpu::ShaderModule,
    pub(crate) layout: wgpu::PipelineLayout,
}

/// A draw pipeline of the renderer's shader writing depth with `bias` into a
/// depth target of `samples` samples, with `color` colour at location 0 and
/// object IDs at 1, else object IDs alone at 0; marking with `mark`.
pub(crate) fn draw_pipeline(
    gpu: &Headless,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    mark: bool,
    color: bool,
    bias: wgpu::DepthBiasState,
    samples: u32,
) -> wgpu::RenderPipeline {
    let constants = [("MARK", if mark { 1.0 } else { 0.0 }), ("SPLIT_IDS", if samples > 1 { 1.0 } else { 0.0 })];
    let ids = Some(wgpu::ColorTargetState::from(id_format(samples)));
    let targets = if color { vec![Some(wgpu::ColorTargetState::from(COLOR_FORMAT)), ids] } else { vec![ids] };
    gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if mark { "draw+mark" } else { "draw" }),
        layout: Some(layout),
        vertex: wgpu::VertexState { module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[Some(vertex_layout())] },
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias,
        }),
        multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(if color { "fs" } else { "fs_ids" }),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The pooled vertices: position and normal.
fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRIBUTES: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
    wgpu::VertexBufferLayout { array_stride: std::mem::size_of::<crate::scene::Vertex>() as u64, step_mode: wgpu::VertexStepMode::Vertex, attributes: &ATTRIBUTES }
}

impl Renderer {
    /// `marks_layout`: the culler's ([`hroc::Culler::marks_layout`]), which
    /// the draw pipelines take at group 1. `samples`: per pixel of every
    /// target (MSAA above 1; IDs are then [`MSAA_ID_FORMAT`]).
    pub fn new(gpu: &Headless, scene: &Scene, (width, height, samples): (u32, u32, u32), marks_layout: &wgpu::BindGroupLayout) -> Result<Renderer> {
        scene.validate()?;
        check_limits(scene, &gpu.limits())?;
        let max_dim = gpu.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max_dim || height > max_dim {
            return Err(Error::Options(format!("resolution {width}x{height} outside 1..={max_dim}")));
        }
        // Pool all meshes; remember where each starts.
        let (mut verts, mut idx, mut ranges) = (Vec::new(), Vec::new(), Vec::new());
        for m in &scene.meshes {
            ranges.push((idx.len() as u32, verts.len() as i32, m.indices.len() as u32));
            verts.extend_from_slice(&m.vertices);
            idx.extend_from_slice(&m.indices);
        }
        let objects: Vec<ObjectData> =
            scene.objects.iter().map(|o| ObjectData { model: o.transform.to_cols_array_2d(), color: [o.color[0], o.color[1], o.color[2], 1.0] }).collect();
        let descs = object_descs(scene);
        use wgpu::BufferUsages as U;
        let n = scene.objects.len() as u32;
        let frame = gpu.buffer("frame", std::mem::size_of::<ViewUniform>() as u64, U::UNIFORM | U::COPY_DST);
        let objects_buf = gpu.buffer_init("objects", bytemuck::cast_slice(&objects), U::STORAGE | U::COPY_DST);
        // The view uniform and the objects' transforms and colours.
        let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let frame_layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[buffer(0, wgpu::BufferBindingType::Uniform), buffer(1, wgpu::BufferBindingType::Storage { read_only: true })],
        });
        let frame_bind = gpu.bind_buffers(&frame_layout, &[&frame, &objects_buf]);
        let dummy = gpu.buffer("no marks", n as u64 * 4, U::STORAGE);
        let no_marks = gpu.bind_buffers(marks_layout, &[&dummy]);

        let module = gpu.shader("draw.wgsl", &draw_wgsl());
        let layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("draw"),
            bind_group_layouts: &[Some(&frame_layout), Some(marks_layout)],
            immediate_size: 0,
        });
        let blend = wgpu::BlendComponent { src_factor: wgpu::BlendFactor::One, dst_factor: wgpu::BlendFactor::One, operation: wgpu::BlendOperation::Add };
        let overdraw_target =
            [Some(wgpu::ColorTargetState { format: OVERDRAW_FORMAT, blend: Some(wgpu::BlendState { color: blend, alpha: blend }), write_mask: wgpu::ColorWrites::ALL })];
        let overdraw = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("overdraw"),
            layout: Some(&layout),
            vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[Some(vertex_layout())] },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState { module: &module, entry_point: Some("fs_overdraw"), compilation_options: Default::default(), targets: &overdraw_target }),
            multiview_mask: None,
            cache: None,
        });
        let no_bias = wgpu::DepthBiasState::default();
        let (draw, draw_mark) = (draw_pipeline(gpu, &module, &layout, false, true, no_bias, samples), draw_pipeline(gpu, &module, &layout, true, true, no_bias, samples));

        let color = target_of(gpu, "colour", (width, height, 1), samples, COLOR_FORMAT);
        let depth = target_of(gpu, "depth", (width, height, 1), samples, DEPTH_FORMAT);
        let id = target_of(gpu, "object id", (width, height, 1), samples, id_format(samples));
        let targets = Targets {
            width,
            height,
            samples,
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            id_view: id.create_view(&Default::default()),
            color,
            depth,
            id,
        };
        Ok(Renderer {
            object_count: n,
            targets,
            vertices: gpu.buffer_init("vertices", bytemuck::cast_slice(&verts), U::VERTEX),
            indices: gpu.buffer_init("indices", bytemuck::cast_slice(&idx), U::INDEX),
            objects: objects_buf,
            descs,
            frame,
            frame_layout,
            frame_bind,
            no_marks,
            draw,
            draw_mark,
            overdraw,
            light_dir: Vec3::new(0.4, 0.8, 0.45).normalize(),
            module,
            layout,
        })
    }

    pub fn aspect(&self) -> f32 {
        self.targets.width as f32 / self.targets.height as f32
    }

    /// New transforms for some objects (the renderer's side of motion).
    pub fn set_transforms(&self, gpu: &Headless, moves: &[(u32, Mat4)], colors: &[[f32; 3]]) {
        for &(i, m) in moves {
            let c = colors[i as usize];
            let d = ObjectData { model: m.to_cols_array_2d(), color: [c[0], c[1], c[2], 1.0] };
            gpu.queue.write_buffer(&self.objects, i as u64 * std::mem::size_of::<ObjectData>() as u64, bytemuck::bytes_of(&d));
        }
    }

    /// Writes the view-projection this frame is drawn with.
    pub fn write_view(&self, gpu: &Headless, view_proj: &Mat4) {
        let u = ViewUniform { view_proj: view_proj.to_cols_array_2d(), light_dir: self.light_dir.extend(0.0).to_array() };
        gpu.queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&u));
    }

    /// The depth attachment and ID target as a view of the culler sees them.
    pub fn view_targets(&self) -> hroc::ViewTargets<'_> {
        hroc::ViewTargets::new(&self.targets.depth, hroc::DepthRange::Standard).with_ids(&self.targets.id)
    }

    /// Clears colour to the sky, depth to far, IDs to 0 (background).
    pub fn clear(&self, enc: &mut wgpu::CommandEncoder) {
        let t = &self.targets;
        let _pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[
                Some(color_attachment(&t.color_view, Some(wgpu::Color { r: 0.55, g: 0.7, b: 0.9, a: 1.0 }))),
                Some(color_attachment(&t.id_view, Some(wgpu::Color::TRANSPARENT))),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    }

    /// Draws `list` over what the targets hold. With `marks`, fragments that
    /// pass the depth test mark their object.
    pub fn draw(&self, enc: &mut wgpu::CommandEncoder, list: &DrawList, marks: Option<&wgpu::BindGroup>) {
        self.draw_raw(enc, &list.commands, &list.count, list.max_count, marks)
    }

    fn draw_raw(&self, enc: &mut wgpu::CommandEncoder, commands: &wgpu::Buffer, count: &wgpu::Buffer, max_count: u32, marks: Option<&wgpu::BindGroup>) {
        let mut pass = self.draw_pass(enc, marks);
        pass.multi_draw_indexed_indirect_count(commands, 0, count, 0, max_count);
    }

    /// A pass over the targets with the scene's pipeline (marking with
    /// `marks`) and geometry bound.
    fn draw_pass<'e>(&self, enc: &'e mut wgpu::CommandEncoder, marks: Option<&wgpu::BindGroup>) -> wgpu::RenderPass<'e> {
        let t = &self.targets;
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("draw"),
            color_attachments: &[Some(color_attachment(&t.color_view, None)), Some(color_attachment(&t.id_view, None))],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(if marks.is_some() { &self.draw_mark } else { &self.draw });
        self.bind_geometry(&mut pass, marks);
        pass
    }

    fn bind_geometry(&self, pass: &mut wgpu::RenderPass<'_>, marks: Option<&wgpu::BindGroup>) {
        pass.set_bind_group(0, &self.frame_bind, &[]);
        pass.set_bind_group(1, marks.unwrap_or(&self.no_marks), &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
    }

    /// Fragments per pixel of `lists` (no depth test): the overdraw view.
    pub fn overdraw(&self, gpu: &Headless, lists: &[DrawList]) -> Result<Vec<f32>> {
        let (w, h) = (self.targets.width, self.targets.height);
        let tex = target(gpu, "overdraw", w, h, OVERDRAW_FORMAT);
        let view = tex.create_view(&Default::default());
        let mut enc = gpu.encoder("overdraw");
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("overdraw"),
                color_attachments: &[Some(color_attachment(&view, Some(wgpu::Color::TRANSPARENT)))],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.overdraw);
            self.bind_geometry(&mut pass, None);
            for l in lists {
                pass.multi_draw_indexed_indirect_count(&l.commands, 0, &l.count, 0, l.max_count);
            }
        }
        gpu.queue.submit([enc.finish()]);
        let texels: Vec<[u16; 2]> = gpu.read_texture(&tex, wgpu::TextureAspect::All)?;
        Ok(texels.into_iter().map(|t| f16_to_f32(t[0])).collect())
    }
}

/// The renderer as a [`hroc::DrawHost`] for one frame: draws every list the
/// culler hands it into the targets (forced early-Z; marks when asked) and
/// keeps the lists, so the benchmark can check what was drawn.
pub struct Recorder<'r> {
    pub renderer: &'r Renderer,
    pub lists: Vec<DrawList>,
}

impl hroc::DrawHost for Recorder<'_> {
    fn draw(&mut self, enc: &mut wgpu::CommandEncoder, d: &hroc::Draw<'_>) {
        // Every object here is opaque: NonOccluders never come (no flags).
        let mut pass = self.renderer.draw_pass(enc, d.mark.then_some(d.marks));
        // Binds the marks at group 1 and draws, counted in the culler's
        // pipeline statistics.
        d.record(&mut pass, if d.mark { &self.renderer.draw_mark } else { &self.renderer.draw }, 1);
        drop(pass);
        self.lists.push(DrawList { commands: d.commands.clone(), count: d.count.clone(), max_count: d.max_count });
    }
}

fn color_attachment(view: &wgpu::TextureView, clear: Option<wgpu::Color>) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear), store: wgpu::StoreOp::Store },
    }
}

/// IEEE half to f32 (overdraw counts are small integers, exact in f16 up to 2048).
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 => f32::INFINITY,
        e => (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_over_the_device_limits_are_refused() {
        let scene = crate::scene::load("radial-city", Some(500), 1).unwrap();
        assert!(check_limits(&scene, &wgpu::Limits::default()).is_ok());
        let tiny = wgpu::Limits { max_buffer_size: 4096, max_storage_buffer_binding_size: 4096, ..Default::default() };
        let e = check_limits(&scene, &tiny).unwrap_err();
        assert!(matches!(e, Error::TooLarge(_)), "{e}");
        assert!(e.to_string().contains("the device allows 4096"), "{e}");
    }

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0x4800), 8.0);
        assert_eq!(f16_to_f32(0), 0.0);
    }
}
