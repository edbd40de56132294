//! The ID-marks pass (`Marks::Ids`) against its CPU reference: from an
//! object-ID image with every kind of value (background 0, IDs in range,
//! IDs past the marks buffer, which a host's bug could write), the GPU
//! marks exactly the objects whose `index + 1` appears (of those a set
//! holds, when given one), and nothing else.

use hroc::testing::gpu::Gpu;
use hroc::testing::id_marks::IdMarks;

mod common;

/// What the pass must mark: object `i` when some pixel holds `i + 1` and
/// `within` holds `i` (every object without it).
fn cpu_marks(ids: &[u32], objects: usize, within: Option<&[u32]>) -> Vec<u32> {
    let mut marks = vec![0u32; objects];
    for &id in ids {
        if id != 0 && (id as usize) <= objects && within.is_none_or(|w| w[id as usize - 1] != 0) {
            marks[id as usize - 1] = 1;
        }
    }
    marks
}

#[test]
fn id_marks_match_the_cpu_reference() {
    let (device, queue) = common::device(hroc::device::REQUIRED_FEATURES);
    let gpu = Gpu::from_device(&device, &queue);
    let pass = IdMarks::new(&gpu, 3000);
    // A xorshift: values below `n`.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut below = |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    for (w, h, objects) in [(37u32, 23u32, 50usize), (64, 64, 3000), (1, 1, 1)] {
        let ids: Vec<u32> = (0..w * h)
            .map(|_| match below(4) {
                0 => 0,
                1 => objects as u32 + 1 + below(10) as u32,
                _ => 1 + below(objects as u64 / 2 + 1) as u32,
            })
            .collect();
        let texture = common::texture(&device, wgpu::TextureFormat::R32Uint, (w, h, 1), 1, 1, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
        queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&ids),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: None },
            texture.size(),
        );
        // Every object, then every third one.
        let third: Vec<u32> = (0..objects as u32).map(|i| (i % 3 == 0) as u32).collect();
        let within = gpu.buffer_init("within", bytemuck::cast_slice(&third), wgpu::BufferUsages::STORAGE);
        for set in [None, Some(&third[..])] {
            let marks = gpu.buffer("marks", objects as u64 * 4, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
            let bound = pass.bind(&gpu, &texture.create_view(&Default::default()), ((w, h), 1), &marks, set.map(|_| &within));
            let mut enc = gpu.encoder("id marks");
            bound.record(&mut enc.begin_compute_pass(&Default::default()));
            queue.submit([enc.finish()]);
            let got: Vec<u32> = gpu.read(&marks, 0, objects as u64).unwrap();
            let want = cpu_marks(&ids, objects, set);
            assert!(want.contains(&1), "the image marks something");
            assert_eq!(got, want, "{w}x{h}, {objects} objects, within {}", set.is_some());
        }
    }
}

/// Over a 4× MSAA `Rg16Uint` ID target (what every backend can
/// multisample), with a different ID in each sample of a pixel and IDs past
/// 16 bits: the pass marks exactly the objects of every sample, decoded
/// from their two halves, as the CPU reference does.
#[test]
fn id_marks_read_every_sample_of_msaa_ids() {
    let (device, queue) = common::device(hroc::device::REQUIRED_FEATURES);
    let gpu = Gpu::from_device(&device, &queue);
    let (w, h, samples, objects) = (29u32, 17u32, 4u32, 70_000usize);
    // Per sample: 0, an ID past 16 bits, a small one, or one past the
    // marks buffer, in a pattern that differs between a pixel's samples.
    let ids: Vec<u32> = (0..w * h * samples)
        .map(|i| match (i * 7 + i / samples) % 5 {
            0 => 0,
            1 => 65_536 + (i * 13) % 4000,
            2 => 1 + (i * 31) % 300,
            3 => objects as u32 + 5,
            _ => 1 + (i * 17) % (objects as u32),
        })
        .collect();
    let source = format!(
        "@group(0) @binding(0) var<storage, read> ids: array<u32>;\n\
         @vertex fn vs(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> {{\n\
             return vec4<f32>(f32(v & 1u) * 4.0 - 1.0, f32(v >> 1u) * 4.0 - 1.0, 0.0, 1.0);\n\
         }}\n\
         @fragment fn fs(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> @location(0) vec4<u32> {{\n\
             let id = ids[(u32(p.y) * {w}u + u32(p.x)) * {samples}u + s];\n\
             return vec4<u32>(id & 0xffffu, id >> 16u, 0u, 0u);\n\
         }}\n"
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("per-sample ids"), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("per-sample ids"),
        layout: None,
        vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[] },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::TextureFormat::Rg16Uint.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let texture = common::texture(&device, wgpu::TextureFormat::Rg16Uint, (w, h, 1), 1, samples, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = texture.create_view(&Default::default());
    let source_ids = gpu.buffer_init("ids", bytemuck::cast_slice(&ids), wgpu::BufferUsages::STORAGE);
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: source_ids.as_entire_binding() }],
    });
    let mut enc = gpu.encoder("per-sample ids");
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
    queue.submit([enc.finish()]);
    // The target holds what was written, sample for sample.
    assert_eq!(hroc_readback::read_ids(&gpu.device, &gpu.queue, &texture).unwrap(), ids, "the per-sample IDs as written");
    let pass = IdMarks::new(&gpu, objects as u32);
    let marks = gpu.buffer("marks", objects as u64 * 4, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
    let bound = pass.bind(&gpu, &view, ((w, h), samples), &marks, None);
    let mut enc = gpu.encoder("id marks");
    bound.record(&mut enc.begin_compute_pass(&Default::default()));
    queue.submit([enc.finish()]);
    let got: Vec<u32> = gpu.read(&marks, 0, objects as u64).unwrap();
    let want = cpu_marks(&ids, objects, None);
    let sample_zero: Vec<u32> = ids.iter().step_by(samples as usize).copied().collect();
    assert_ne!(want, cpu_marks(&sample_zero, objects, None), "other samples hold objects the first does not");
    assert_eq!(got, want, "{w}x{h}, {samples} samples");
}
