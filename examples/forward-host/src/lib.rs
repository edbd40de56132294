//! A small forward renderer of its own that culls with `hroc`: its own
//! device, vertex layout (interleaved position/normal/uv), per-instance
//! transforms in a storage buffer, a lit shader and one alpha-blended
//! material. It uses neither hroc's benchmark nor its renderer: only the
//! public culling API, the scene crate's generators, and `hroc-readback`
//! for its tests' read-backs.
//!
//! What hroc adds to the renderer, all in [`ForwardHost::frame`]:
//! a [`hroc::Culler`] over the objects, a [`hroc::View`], and a draw
//! callback that records `multi_draw_indexed_indirect_count` with the
//! opaque or the blended pipeline by [`hroc::Phase`]. With [`Views`], the
//! main view is multisampled and a directional light casts shadows from a
//! cascaded shadow map whose cascades are views of the same culler.

use glam::{Mat4, Vec2, Vec3};
use hroc::device::{Capabilities, Marks};
use hroc::{Culler, CullerDesc, DepthRange, FrameInput, Method, ObjectDesc, ObjectFlags, Phase, View, ViewDesc, ViewTargets};
use hroc_scene::Scene;

mod demo;
mod shadows;

pub use demo::Demo;

pub use shadows::{CASCADE_SIZE, MAX_CASCADES};

/// Interleaved vertex: position, normal, uv (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

/// One instance: transform and material colour (alpha < 1: blended).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Instance {
    pub model: [[f32; 4]; 4],
    pub color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniform {
    view_proj: [[f32; 4]; 4],
    light_dir: [f32; 4],
    cascades: [[[f32; 4]; 4]; MAX_CASCADES as usize],
    cascade_count: [u32; 4],
}

const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The ID target's format: `R32Uint`, or, multisampled, `Rg16Uint` (which
/// every backend can multisample) holding the ID in 16-bit halves.
fn ids_format(samples: u32) -> wgpu::TextureFormat {
    if samples > 1 {
        wgpu::TextureFormat::Rg16Uint
    } else {
        wgpu::TextureFormat::R32Uint
    }
}

/// The direction towards the light.
fn toward_light() -> Vec3 {
    Vec3::new(0.4, 0.8, 0.45).normalize()
}

/// The views the host renders: its main view's samples per pixel, and its
/// light's shadow cascades with the method that culls them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Views {
    /// Samples per pixel of the main view (1: no MSAA).
    pub msaa: u32,
    /// Cascades of the light's shadow map, 0 to [`MAX_CASCADES`] (0: no
    /// shadows). Each is a layer of one depth array, which wgpu's GL
    /// backend cannot cull (hroc refuses it there, by name).
    pub cascades: u32,
    /// What culls the cascades: shadow passes have no ID target, so a
    /// method that needs none (`hzb`, or `hroc-na` with early-Z marks).
    pub shadow_method: Method,
}

impl Views {
    /// One single-sample view, no shadows.
    pub const SINGLE: Views = Views { msaa: 1, cascades: 0, shadow_method: Method::Hzb };
    /// A frame of an engine: a 4× MSAA main view and a shadow map of three
    /// cascades culled by `hzb`.
    pub const ENGINE: Views = Views { msaa: 4, cascades: 3, shadow_method: Method::Hzb };
}

/// Opens a headless device with the features hroc needs.
pub fn open_device() -> Result<(wgpu::Device, wgpu::Queue), String> {
    open_device_on(wgpu::Backends::all())
}

/// [`open_device`] on one of `backends` (OpenGL: through EGL, no display).
pub fn open_device_on(backends: wgpu::Backends) -> Result<(wgpu::Device, wgpu::Queue), String> {
    pollster::block_on(async {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let adapter = instance.request_adapter(&wgpu::RequestAdapterOptions::default()).await.map_err(|e| format!("no adapter: {e}"))?;
        let missing = hroc::device::REQUIRED_FEATURES - adapter.features();
        if !missing.is_empty() {
            return Err(format!("{} lacks {missing:?}", adapter.get_info().name));
        }
        adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("forward host"),
                required_features: hroc::device::features(&adapter),
                required_limits: hroc::device::limits(&adapter),
                ..Default::default()
            })
            .await
            .map_err(|e| format!("cannot open device: {e}"))
    })
}

/// The host's scene: meshes converted to its vertex format, one instance per object.
pub struct HostScene {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub instances: Vec<Instance>,
    /// Per object: world box, its draw in the index buffer, flags.
    pub objects: Vec<ObjectDesc>,
    /// Per object: its mesh's box in object space (world boxes of moved
    /// objects are this box transformed).
    pub local_bounds: Vec<hroc::Aabb>,
}

impl HostScene {
    /// Converts a scene of the scene crate; objects whose colour index is in
    /// `blended` get alpha 0.4 and [`ObjectFlags::NOT_OCCLUDER`].
    pub fn from_scene(scene: &Scene, blended: &[usize]) -> HostScene {
        let (mut vertices, mut indices, mut ranges) = (Vec::new(), Vec::new(), Vec::new());
        for m in &scene.meshes {
            ranges.push((indices.len() as u32, vertices.len() as i32, m.indices.len() as u32));
            let e = m.bounds.extent().max(Vec3::splat(1e-6));
            vertices.extend(m.vertices.iter().map(|v| {
                let p = (Vec3::from(v.position) - m.bounds.min) / e;
                Vertex { position: v.position, normal: v.normal, uv: (Vec2::new(p.x + p.z, p.y)).to_array() }
            }));
            indices.extend_from_slice(&m.indices);
        }
        let mut instances = Vec::new();
        let mut objects = Vec::new();
        let local_bounds = scene.objects.iter().map(|o| scene.meshes[o.mesh as usize].bounds).collect();
        for (i, o) in scene.objects.iter().enumerate() {
            let glass = blended.contains(&i);
            instances.push(Instance { model: o.transform.to_cols_array_2d(), color: [o.color[0], o.color[1], o.color[2], if glass { 0.4 } else { 1.0 }] });
            let (first_index, base_vertex, index_count) = ranges[o.mesh as usize];
            objects.push(ObjectDesc {
                bounds: o.bounds,
                index_count,
                first_index,
                base_vertex,
                flags: if glass { ObjectFlags::NOT_OCCLUDER } else { ObjectFlags::NONE },
                oriented: None,
            });
        }
        HostScene { vertices, indices, instances, objects, local_bounds }
    }
}

/// What one frame drew, from the host's own instrumentation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameOutput {
    /// Objects visible in the final picture: opaque objects that own a pixel
    /// of the ID target, blended objects with a fragment through the final
    /// depth (they are drawn last and write no depth, so that is exact).
    pub visible: Vec<bool>,
    /// Objects the culler handed over (a command with an instance).
    pub drawn: Vec<bool>,
    /// The depth buffer, row-major, every sample of a pixel in turn.
    pub depth: Vec<f32>,
    /// The colour image, RGBA8 (resolved, with MSAA).
    pub color: Vec<u8>,
    /// Each shadow cascade's depth, row-major.
    pub cascade_depth: Vec<Vec<f32>>,
    /// Objects each shadow cascade's lists drew.
    pub cascade_drawn: Vec<Vec<bool>>,
}

/// The forward renderer, with hroc culling it.
pub struct ForwardHost {
    device: wgpu::Device,
    queue: wgpu::Queue,
    size: (u32, u32),
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    camera: wgpu::Buffer,
    seen: wgpu::Buffer,
    bind: wgpu::BindGroup,
    opaque: wgpu::RenderPipeline,
    blend: wgpu::RenderPipeline,
    depth: wgpu::Texture,
    ids: wgpu::Texture,
    color: wgpu::Texture,
    /// With MSAA, the single-sample colour the frame resolves to.
    resolve: Option<wgpu::Texture>,
    shadows: shadows::Shadows,
    /// A box that holds every object (the cascades span it in depth).
    bounds: hroc::Aabb,
    n: u32,
    /// The lists the last frame drew: (commands, count, max count).
    lists: Vec<(wgpu::Buffer, wgpu::Buffer, u32)>,
    instances: wgpu::Buffer,
    colors: Vec<[f32; 4]>,
    local_bounds: Vec<hroc::Aabb>,
    blended: Vec<bool>,
    depth_range: DepthRange,
    /// The culler over the host's objects.
    pub culler: Culler,
    /// The main camera's view.
    pub view: View,
}

fn texture(device: &wgpu::Device, (w, h): (u32, u32), format: wgpu::TextureFormat, label: &str, samples: u32) -> wgpu::Texture {
    // Multisampled textures cannot be copied.
    let copy = if samples > 1 { wgpu::TextureUsages::empty() } else { wgpu::TextureUsages::COPY_SRC };
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | copy,
        view_formats: &[],
    })
}

impl ForwardHost {
    /// Uploads the scene and builds the pipelines; `method` culls it, with
    /// `capabilities` (`None`: the most the device allows): one
    /// single-sample view, no shadows ([`Views::SINGLE`]).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HostScene,
        size: (u32, u32),
        method: Method,
        depth_range: DepthRange,
        capabilities: Option<Capabilities>,
    ) -> hroc::Result<ForwardHost> {
        Self::with_views(device, queue, scene, size, (method, depth_range, capabilities), Views::SINGLE)
    }

    /// [`ForwardHost::new`] rendering `views`: the main view culled by
    /// `method` in `depth_range`, with `capabilities`.
    pub fn with_views(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HostScene,
        size: (u32, u32),
        (method, depth_range, capabilities): (Method, DepthRange, Option<Capabilities>),
        views: Views,
    ) -> hroc::Result<ForwardHost> {
        let samples = views.msaa;
        use wgpu::util::DeviceExt;
        use wgpu::BufferUsages as U;
        let init = |label, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let n = scene.instances.len() as u32;
        let vertices = init("vertices", bytemuck::cast_slice(&scene.vertices), U::VERTEX);
        let indices = init("indices", bytemuck::cast_slice(&scene.indices), U::INDEX);
        let instances = init("instances", bytemuck::cast_slice(&scene.instances), U::STORAGE | U::COPY_DST);
        let camera = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("camera"),
            size: std::mem::size_of::<CameraUniform>() as u64,
            usage: U::UNIFORM | U::COPY_DST,
            mapped_at_creation: false,
        });
        let seen = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("seen"),
            size: (n as u64 * 4).max(16),
            usage: U::STORAGE | U::COPY_SRC | U::COPY_DST,
            mapped_at_creation: false,
        });

        // hroc: the culler over the host's objects, and one view.
        // Validation on: every host mistake becomes an error of View::cull.
        let culler = Culler::new(device, queue, &CullerDesc { capabilities, validation: true, ..CullerDesc::new(&scene.objects) })?;
        let depth = texture(device, size, DEPTH, "depth", samples);
        let (ids, color) = (texture(device, size, ids_format(samples), "ids", samples), texture(device, size, COLOR, "color", samples));
        let resolve = (samples > 1).then(|| texture(device, size, COLOR, "resolved color", 1));
        let view = culler.view(method, &ViewTargets::new(&depth, depth_range).with_ids(&ids))?;
        // hroc: the light's cascades, each a view of the same culler.
        let shadows = shadows::Shadows::new(device, &culler, (views.cascades, views.shadow_method), depth_range, std::mem::size_of::<Vertex>() as u64, &instances)?;

        let entry = |binding, ty, visibility| wgpu::BindGroupLayoutEntry { binding, visibility, ty, count: None };
        let storage = |read_only| wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("host"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
                    wgpu::ShaderStages::VERTEX_FRAGMENT,
                ),
                entry(1, storage(true), wgpu::ShaderStages::VERTEX_FRAGMENT),
                entry(2, storage(false), wgpu::ShaderStages::FRAGMENT),
                entry(
                    3,
                    wgpu::BindingType::Texture { sample_type: wgpu::TextureSampleType::Depth, view_dimension: wgpu::TextureViewDimension::D2Array, multisampled: false },
                    wgpu::ShaderStages::FRAGMENT,
                ),
                entry(4, wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison), wgpu::ShaderStages::FRAGMENT),
            ],
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("host"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: instances.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: seen.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&shadows.array) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&shadows.sampler) },
            ],
        });
        // hroc: with early-Z marks, the marking fragment stage and the marks
        // snippet at group 1; with ID marks, nothing. The culler's marks
        // layout is at group 1 either way (its draws bind a sink there).
        let marks = culler.capabilities().marks;
        let mut source = include_str!("shader.wgsl").to_string();
        if marks == Marks::EarlyZ {
            source += &format!("\n{}\n{}", include_str!("marked.wgsl"), hroc::device::marks_wgsl(1));
        }
        if !device.features().contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST) {
            source = source.replace("@early_depth_test(force)", "");
        }
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("forward"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("forward"),
            bind_group_layouts: &[Some(&layout), Some(culler.marks_layout())],
            immediate_size: 0,
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2],
        };
        let pipeline = |blend: bool| {
            let over = wgpu::BlendState::ALPHA_BLENDING;
            let targets = [
                Some(wgpu::ColorTargetState { format: COLOR, blend: blend.then_some(over), write_mask: wgpu::ColorWrites::ALL }),
                Some(wgpu::ColorTargetState { format: ids_format(samples), blend: None, write_mask: if blend { wgpu::ColorWrites::empty() } else { wgpu::ColorWrites::ALL } }),
            ];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if blend { "blend" } else { "opaque" }),
                layout: Some(&pl),
                vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[Some(vertex_layout.clone())] },
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(!blend),
                    depth_compare: Some(if depth_range == DepthRange::Reversed { wgpu::CompareFunction::Greater } else { wgpu::CompareFunction::Less }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(match (blend, marks) {
                        (true, _) => "fs_blend",
                        (false, Marks::EarlyZ) => "fs_opaque_marked",
                        (false, Marks::Ids | Marks::Boxes) => "fs_opaque",
                    }),
                    compilation_options: wgpu::PipelineCompilationOptions { constants: &[("SPLIT_IDS", (samples > 1) as u32 as f64)], ..Default::default() },
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        Ok(ForwardHost {
            device: device.clone(),
            queue: queue.clone(),
            size,
            vertices,
            indices,
            camera,
            seen,
            bind,
            opaque: pipeline(false),
            blend: pipeline(true),
            depth,
            ids,
            color,
            resolve,
            shadows,
            bounds: scene.objects.iter().fold(scene.objects.first().map_or(hroc::Aabb::new(Vec3::ZERO, Vec3::ZERO), |o| o.bounds), |b, o| b.union(o.bounds)),
            n,
            lists: Vec::new(),
            instances,
            colors: scene.instances.iter().map(|i| i.color).collect(),
            local_bounds: scene.local_bounds.clone(),
            blended: scene.objects.iter().map(|o| o.flags.contains(ObjectFlags::NOT_OCCLUDER)).collect(),
            depth_range,
            culler,
            view,
        })
    }

    /// Renders one frame from `view`/`proj`, culled by the view's method;
    /// `cut` signals a camera cut. Submits; [`ForwardHost::output`] reads
    /// back what it drew.
    pub fn frame(&mut self, view: Mat4, proj: Mat4, cut: bool) -> hroc::Result<()> {
        let aspect = self.size.0 as f32 / self.size.1 as f32;
        let cascades = self.shadows.fit(view, proj, aspect, toward_light(), &self.bounds);
        let mut cam = CameraUniform { view_proj: (proj * view).to_cols_array_2d(), light_dir: toward_light().extend(0.0).to_array(), ..Default::default() };
        for (slot, (v, p)) in cam.cascades.iter_mut().zip(&cascades) {
            *slot = (*p * *v).to_cols_array_2d();
        }
        cam.cascade_count[0] = cascades.len() as u32;
        self.queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&cam));
        let (depth_view, ids_view, color_view) =
            (self.depth.create_view(&Default::default()), self.ids.create_view(&Default::default()), self.color.create_view(&Default::default()));
        let resolve_view = self.resolve.as_ref().map(|t| t.create_view(&Default::default()));
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.seen, 0, None);
        // The shadow map first: each cascade culled and drawn, depth only.
        self.shadows.record(&self.queue, &self.culler, &mut encoder, (&self.vertices, &self.indices), &cascades)?;
        // Clear the targets (hroc does not touch them).
        drop(begin_pass(&mut encoder, (&color_view, None), &ids_view, &depth_view, Some(self.depth_range)));
        let mut lists = Vec::new();
        let input = FrameInput { view: ViewDesc { view, proj, unclipped_depth: false }, cut, time: 0.0 };
        // hroc: cull, and draw each list it hands back with our own pipelines.
        self.view.cull(&self.culler, &mut encoder, &input, &mut |enc: &mut wgpu::CommandEncoder, draw: &hroc::Draw| {
            let mut pass = begin_pass(enc, (&color_view, resolve_view.as_ref()), &ids_view, &depth_view, None);
            pass.set_bind_group(0, &self.bind, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            draw.record(&mut pass, if draw.phase == Phase::NonOccluders { &self.blend } else { &self.opaque }, 1);
            lists.push((draw.commands.clone(), draw.count.clone(), draw.max_count));
        })?;
        self.queue.submit([encoder.finish()]);
        self.lists = lists;
        Ok(())
    }

    /// What the last frame drew (the host's instrumentation for tests and
    /// the example's printout; it waits for the GPU).
    pub fn output(&self) -> hroc::Result<FrameOutput> {
        let (device, queue) = (&self.device, &self.queue);
        let mut drawn = vec![false; self.n as usize];
        for (commands, count, max) in &self.lists {
            for [index_count, instance_count, _, _, object] in drawn_list(device, queue, commands, count, *max)? {
                drawn[object as usize] |= instance_count > 0 && index_count > 0;
            }
        }
        let seen: Vec<u32> = hroc_readback::read(device, queue, &self.seen, 0, self.n as u64).map_err(read_error)?;
        let mut visible: Vec<bool> = (0..self.n as usize).map(|o| self.blended[o] && seen[o] != 0).collect();
        for id in hroc_readback::read_ids(device, queue, &self.ids).map_err(read_error)? {
            if id > 0 {
                visible[id as usize - 1] = true;
            }
        }
        let mut cascade_drawn = Vec::new();
        for lists in &self.shadows.lists {
            let mut drawn = vec![false; self.n as usize];
            for (commands, count, max) in lists {
                for [index_count, instance_count, _, _, object] in drawn_list(device, queue, commands, count, *max)? {
                    drawn[object as usize] |= instance_count > 0 && index_count > 0;
                }
            }
            cascade_drawn.push(drawn);
        }
        let color = self.resolve.as_ref().unwrap_or(&self.color);
        Ok(FrameOutput {
            visible,
            drawn,
            depth: hroc_readback::read_depth(device, queue, &self.depth, 0).map_err(read_error)?,
            color: hroc_readback::read_texture::<u8>(device, queue, color, wgpu::TextureAspect::All).map_err(read_error)?,
            cascade_depth: self.shadows.depth(device, queue)?,
            cascade_drawn,
        })
    }

    /// Moves objects to new transforms before the next frame: the host's
    /// instance data, and hroc's boxes (the mesh box transformed, which holds
    /// every vertex) through [`Culler::set_bounds`].
    pub fn move_objects(&mut self, moves: &[(u32, Mat4)]) -> hroc::Result<()> {
        let boxes: Vec<(u32, hroc::Aabb)> = moves.iter().map(|&(i, m)| (i, self.local_bounds[i as usize].transformed(&m))).collect();
        self.culler.set_bounds(&boxes)?;
        self.bounds = boxes.iter().fold(self.bounds, |b, (_, o)| b.union(*o));
        for &(i, m) in moves {
            let inst = Instance { model: m.to_cols_array_2d(), color: self.colors[i as usize] };
            self.queue.write_buffer(&self.instances, i as u64 * std::mem::size_of::<Instance>() as u64, bytemuck::bytes_of(&inst));
        }
        Ok(())
    }

    /// What the culler runs with.
    pub fn capabilities(&self) -> Capabilities {
        self.culler.capabilities()
    }

    /// Width and height.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }
}

/// The host's read-backs, for its tests and printout (not part of culling).
fn read_error(e: hroc_readback::Error) -> hroc::Error {
    hroc::Error::Gpu(e.to_string())
}

/// The commands of a [`hroc::Draw`] list within its count (at most
/// `max_count`): index count, instances, first index, base vertex, object.
fn drawn_list(device: &wgpu::Device, queue: &wgpu::Queue, commands: &wgpu::Buffer, count: &wgpu::Buffer, max_count: u32) -> hroc::Result<Vec<[u32; 5]>> {
    let n = hroc_readback::read::<u32>(device, queue, count, 0, 1).map_err(read_error)?[0].min(max_count);
    hroc_readback::read(device, queue, commands, 0, n as u64).map_err(read_error)
}

/// A render pass on the host's targets: clears them for `Some(depth range)`,
/// else loads them; resolves colour to `color.1` where given (MSAA).
fn begin_pass<'e>(
    enc: &'e mut wgpu::CommandEncoder,
    color: (&wgpu::TextureView, Option<&wgpu::TextureView>),
    ids: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    clear: Option<DepthRange>,
) -> wgpu::RenderPass<'e> {
    let far = if clear == Some(DepthRange::Reversed) { 0.0 } else { 1.0 };
    let clear = clear.is_some();
    let op = |c: wgpu::Color| wgpu::Operations { load: if clear { wgpu::LoadOp::Clear(c) } else { wgpu::LoadOp::Load }, store: wgpu::StoreOp::Store };
    let colors = [
        Some(wgpu::RenderPassColorAttachment { view: color.0, depth_slice: None, resolve_target: color.1, ops: op(wgpu::Color { r: 0.55, g: 0.7, b: 0.9, a: 1.0 }) }),
        Some(wgpu::RenderPassColorAttachment { view: ids, depth_slice: None, resolve_target: None, ops: op(wgpu::Color::TRANSPARENT) }),
    ];
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: &colors,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations { load: if clear { wgpu::LoadOp::Clear(far) } else { wgpu::LoadOp::Load }, store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
