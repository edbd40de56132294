//! An engine that draws its own frame (`View::steps`): one pipeline whose
//! vertex stage reads the view's visibility as data
//! (`hroc::device::visibility_wgsl`) and drops the objects the pass does
//! not draw; every object's command drawn in both passes, the early one
//! keeping `hroc_early`'s, the late one `hroc_late`'s. It draws the
//! street host's cubes into the street host's targets.

use super::street::Host;
use hroc::{Culler, FrameInput, View, ViewDesc};
use wgpu::util::DeviceExt;

/// The engine's pipelines (early and late pass) for `host`'s targets.
pub struct Engine {
    early: wgpu::RenderPipeline,
    late: wgpu::RenderPipeline,
    /// Frames whose late pass was left out (`Steps::late` false).
    pub late_left_out: std::cell::Cell<u32>,
}

impl Engine {
    pub fn new(device: &wgpu::Device, host: &Host) -> Engine {
        Engine::lifting(device, host, None)
    }

    /// The engine with a vertex shader that lifts object `lifted.0` by
    /// `lifted.1` past its box (wind, a custom material's displacement).
    pub fn lifting(device: &wgpu::Device, host: &Host, lifted: Option<(u32, f32)>) -> Engine {
        let at = host.at;
        let value = if at.ids_format() == wgpu::TextureFormat::Rg16Uint { "vec4<u32>(id & 0xffffu, id >> 16u, 0u, 0u)" } else { "vec4<u32>(id, 0u, 0u, 0u)" };
        let source = format!(
            "@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;\n{}\n\
             override LATE: bool = false;\n\
             override LIFTED: u32 = 0xffffffffu;\n\
             override LIFT: f32 = 0.0;\n\
             struct Out {{ @builtin(position) clip: vec4<f32>, @location(0) @interpolate(flat) object: u32 }}\n\
             @vertex fn vs(@location(0) p: vec3<f32>, @builtin(instance_index) i: u32) -> Out {{\n\
                 let q = select(p, p + vec3<f32>(0.0, LIFT, 0.0), i == LIFTED);\n\
                 if select(hroc_early(i), hroc_late(i), LATE) {{ return Out(view_proj * vec4<f32>(q, 1.0), i); }}\n\
                 return Out(vec4<f32>(0.0, 0.0, -2.0, 1.0), i);\n\
             }}\n\
             @fragment fn fs(in: Out) -> @location(0) vec4<u32> {{ let id = in.object + 1u; return {value}; }}\n",
            hroc::device::visibility_wgsl(1, 0)
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("engine"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let pipeline = |late: bool| {
            let (object, lift) = lifted.unwrap_or((u32::MAX, 0.0));
            let constants = [("LATE", late as u32 as f64), ("LIFTED", object as f64), ("LIFT", lift as f64)];
            let options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if late { "engine late pass" } else { "engine early pass" }),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: options.clone(),
                    buffers: &[Some(wgpu::VertexBufferLayout { array_stride: 12, step_mode: wgpu::VertexStepMode::Vertex, attributes: &wgpu::vertex_attr_array![0 => Float32x3] })],
                },
                primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), unclipped_depth: at.unclipped, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: at.format,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(if at.range == hroc::DepthRange::Standard { wgpu::CompareFunction::Less } else { wgpu::CompareFunction::Greater }),
                    stencil: Default::default(),
                    bias: at.bias,
                }),
                multisample: wgpu::MultisampleState { count: at.samples, ..Default::default() },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: options,
                    targets: &[Some(wgpu::ColorTargetState { format: at.ids_format(), blend: None, write_mask: wgpu::ColorWrites::ALL })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        Engine { early: pipeline(false), late: pipeline(true), late_left_out: Default::default() }
    }

    /// One frame of `view` driven by the engine: the targets cleared,
    /// [`hroc::Steps::begin`], the early pass, `occluders_drawn`, the late
    /// pass, `occludees_drawn`, submitted in that order. Returns the
    /// objects the two passes drew (read from the visibility buffer).
    #[allow(clippy::too_many_arguments)]
    pub fn frame(&self, device: &wgpu::Device, queue: &wgpu::Queue, host: &Host, culler: &Culler, view: &mut View, desc: ViewDesc, cut: bool) -> hroc::Result<Vec<u32>> {
        let visibility = view.visibility(culler).clone();
        let mut begin = device.create_command_encoder(&Default::default());
        let camera = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::bytes_of(&(desc.proj * desc.view)),
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        begin.copy_buffer_to_buffer(&camera, 0, &host.camera, 0, 64);
        drop(host.pass(&mut begin, true));
        let steps = view.steps(culler, &FrameInput { view: desc, cut, time: 0.0 })?;
        let pass = |pipeline: &wgpu::RenderPipeline| {
            let bind = |group: u32, buffer: &wgpu::Buffer| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &pipeline.get_bind_group_layout(group),
                    entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
                })
            };
            let (camera, visible) = (bind(0, &host.camera), bind(1, &visibility));
            let mut enc = device.create_command_encoder(&Default::default());
            let mut pass = host.pass(&mut enc, false);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, &visible, &[]);
            pass.set_vertex_buffer(0, host.vertices.slice(..));
            pass.set_index_buffer(host.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.multi_draw_indexed_indirect(culler.commands(), 0, culler.object_count());
            drop(pass);
            enc.finish()
        };
        // An engine leaves out the late pass where the frame draws nothing in it.
        let steps_late = steps.late;
        self.late_left_out.set(self.late_left_out.get() + !steps_late as u32);
        let late = steps_late.then(|| pass(&self.late));
        queue.submit([begin.finish(), steps.begin, pass(&self.early), steps.occluders_drawn].into_iter().chain(late).chain([steps.occludees_drawn]));
        let slots: Vec<u32> = hroc_readback::read(device, queue, &visibility, 0, (hroc::device::VISIBILITY_HEADER + culler.object_count()) as u64).unwrap();
        let (header, slots) = slots.split_at(hroc::device::VISIBILITY_HEADER as usize);
        // Drawn in a pass: stamped with this frame's early or late phase.
        let passes = &header[..4];
        assert!(steps_late || !slots.contains(&header[3]), "a frame whose Steps::late is false stamped objects for its late pass");
        Ok((0..slots.len() as u32).filter(|&o| passes.contains(&slots[o as usize])).collect())
    }
}
