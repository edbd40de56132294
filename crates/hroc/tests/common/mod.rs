//! What the core crate's GPU tests share: a Vulkan device (lavapipe in CI),
//! a depth target the culler can sample, and a host pipeline built before
//! any culler.

// Each test binary uses part of this module.
#![allow(dead_code)]

pub mod engine;
pub mod street;

/// A device on the first Vulkan adapter, with `features` and the adapter's
/// own limits.
pub fn device(features: wgpu::Features) -> (wgpu::Device, wgpu::Queue) {
    device_with(features, |adapter| adapter.limits())
}

/// The first Vulkan adapter (lavapipe in CI).
pub fn adapter() -> wgpu::Adapter {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("a Vulkan adapter: install lavapipe (scripts/ensure-vulkan.sh)")
}

/// A device on [`adapter`] with `features` and the limits `limits` picks.
pub fn device_with(features: wgpu::Features, limits: impl FnOnce(&wgpu::Adapter) -> wgpu::Limits) -> (wgpu::Device, wgpu::Queue) {
    let adapter = adapter();
    let desc = wgpu::DeviceDescriptor { required_features: features, required_limits: limits(&adapter), ..Default::default() };
    pollster::block_on(adapter.request_device(&desc)).expect("a device with the features and limits asked for")
}

/// A 2D texture of `format`, `(width, height, layers)`, `mips` and `samples`.
pub fn texture(device: &wgpu::Device, format: wgpu::TextureFormat, (width, height, layers): (u32, u32, u32), mips: u32, samples: u32, usage: wgpu::TextureUsages) -> wgpu::Texture {
    let size = wgpu::Extent3d { width, height, depth_or_array_layers: layers };
    let dimension = wgpu::TextureDimension::D2;
    device.create_texture(&wgpu::TextureDescriptor { label: None, size, mip_level_count: mips, sample_count: samples, dimension, format, usage, view_formats: &[] })
}

/// A `Depth32Float` target of `size` × `size`, drawn into and sampled.
pub fn depth_texture(device: &wgpu::Device, size: u32) -> wgpu::Texture {
    texture(device, wgpu::TextureFormat::Depth32Float, (size, size, 1), 1, 1, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING)
}

/// A host's pipeline built before any culler (`hroc::device::marks_layout`):
/// positions at location 0, `view_proj` at group 0, hroc's marks at
/// group 1; with `mark`, the fragment stage forces early-Z and marks its
/// object (without, it has neither of the two hroc lines: what a host
/// writes for `Marks::Ids`); with `ids`, it writes `object + 1` to an
/// `R32Uint` target. Returns the pipeline and the camera's bind group
/// layout.
pub fn host_pipeline(device: &wgpu::Device, ids: bool, mark: bool) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    host_pipeline_on(device, ids, mark, &street::Depth::default())
}

/// [`host_pipeline`] drawing into the depth target `at` describes: its
/// format, samples (the ID target's format with them), depth test and
/// bias, and clamping rather than clipping at the near plane.
pub fn host_pipeline_on(device: &wgpu::Device, ids: bool, mark: bool, at: &street::Depth) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    let shader = Shader { ids: ids.then_some("in.object + 1u"), early_z: mark, mark, marks_group: true, discard: false };
    host_pipeline_with(device, &shader, at)
}

/// What a host's fragment stage does, and whether its layout has hroc's
/// marks group (the host contract's lines, each of which a test may
/// leave out).
pub struct Shader {
    /// The ID written (WGSL of `in.object`), if any.
    pub ids: Option<&'static str>,
    /// Declared `@early_depth_test(force)`.
    pub early_z: bool,
    /// Calls `hroc_mark(in.object)`.
    pub mark: bool,
    /// The layout has the marks group at group 1.
    pub marks_group: bool,
    /// Alpha testing: objects whose index is a multiple of 4 discard a
    /// 2 × 2-pixel checkerboard (a CUTOUT object's pipeline, which writes
    /// depth only where it draws); the others draw whole.
    pub discard: bool,
}

/// [`host_pipeline_on`] with the fragment stage and layout `shader` describes.
pub fn host_pipeline_with(device: &wgpu::Device, shader: &Shader, at: &street::Depth) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    let street::Depth { format, range, bias, unclipped, samples, .. } = *at;
    // Rg16Uint holds the ID's low 16 bits in r, its high in g.
    let value = if at.ids_format() == wgpu::TextureFormat::Rg16Uint { "vec4<u32>(id & 0xffffu, id >> 16u, 0u, 0u)" } else { "vec4<u32>(id, 0u, 0u, 0u)" };
    let (output, ret) = match shader.ids {
        Some(id) => (" -> @location(0) vec4<u32>".to_string(), format!(" let id = {id}; return {value};")),
        None => (String::new(), String::new()),
    };
    let early = if shader.early_z { "@early_depth_test(force) " } else { "" };
    let marking = match (shader.discard, shader.mark) {
        (true, _) => " if in.object % 4u == 0u && ((u32(in.clip.x) / 2u + u32(in.clip.y) / 2u) % 2u) == 0u { discard; }",
        (false, true) => " hroc_mark(in.object);",
        (false, false) => "",
    };
    let mark = shader.mark;
    let source = format!(
        "@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;\n{}\n\
         struct Out {{ @builtin(position) clip: vec4<f32>, @location(0) @interpolate(flat) object: u32 }}\n\
         @vertex fn vs(@location(0) p: vec3<f32>, @builtin(instance_index) i: u32) -> Out {{ return Out(view_proj * vec4<f32>(p, 1.0), i); }}\n\
         @fragment {early}fn fs(in: Out){output} {{{marking}{ret} }}\n",
        if mark { hroc::device::marks_wgsl(1) } else { String::new() }
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("host"), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let camera_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("camera"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        }],
    });
    let marks = hroc::device::marks_layout(device);
    let groups = if shader.marks_group { vec![Some(&camera_layout), Some(&marks)] } else { vec![Some(&camera_layout)] };
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("host"), bind_group_layouts: &groups, immediate_size: 0 });
    let targets = [Some(wgpu::ColorTargetState { format: at.ids_format(), blend: None, write_mask: wgpu::ColorWrites::ALL })];
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("host"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout { array_stride: 12, step_mode: wgpu::VertexStepMode::Vertex, attributes: &wgpu::vertex_attr_array![0 => Float32x3] })],
        },
        primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), unclipped_depth: unclipped, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(if range == hroc::DepthRange::Standard { wgpu::CompareFunction::Less } else { wgpu::CompareFunction::Greater }),
            stencil: Default::default(),
            bias,
        }),
        multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: if shader.ids.is_some() { &targets } else { &[] },
        }),
        multiview_mask: None,
        cache: None,
    });
    (pipeline, camera_layout)
}
