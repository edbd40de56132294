//! What one command of a frame's shape costs on this device: a compute
//! pass of one small dispatch, a dispatch inside an open pass, an empty
//! render pass over a 64x36 colour, ID and depth target (with and without
//! an indirect-count draw of nothing), a buffer clear and a buffer copy.
//! Each is recorded K times into one encoder, submitted and waited for;
//! the cost of one is the median over tries of (t(K) - t(0)) / K.
//!
//! `cargo run --release -p hroc-bench --example pass_costs [-- WIDTHxHEIGHT]`

use std::time::Instant;

use hroc_bench::gpu::Headless;

const SHADER: &str = r#"
@group(0) @binding(0) var<storage, read_write> data: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x < arrayLength(&data)) { data[id.x] = data[id.x] + 1u; }
}
@vertex fn vs(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> { return vec4<f32>(f32(v & 1u), f32(v >> 1u), 0.5, 1.0); }
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }
"#;

const K: u32 = 40;
const TRIES: usize = 15;

fn main() -> hroc_bench::Result<()> {
    let size = std::env::args().nth(1).unwrap_or_else(|| "64x36".into());
    let (w, h) = size.split_once('x').map(|(a, b)| (a.parse().unwrap(), b.parse().unwrap())).unwrap_or((64, 36));
    let gpu = Headless::new()?;
    let d = &gpu.device;
    use wgpu::BufferUsages as U;
    let data = d.create_buffer(&wgpu::BufferDescriptor { label: None, size: 256, usage: U::STORAGE | U::COPY_DST | U::COPY_SRC, mapped_at_creation: false });
    let other = d.create_buffer(&wgpu::BufferDescriptor { label: None, size: 256, usage: U::STORAGE | U::COPY_DST | U::COPY_SRC | U::INDIRECT, mapped_at_creation: false });
    let zero = d.create_buffer(&wgpu::BufferDescriptor { label: None, size: 16, usage: U::INDIRECT, mapped_at_creation: false });
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor { label: None, source: wgpu::ShaderSource::Wgsl(SHADER.into()) });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: data.as_entire_binding() }],
    });
    let tex = |format, usage| {
        d.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
        .create_view(&Default::default())
    };
    let ta = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let (color, ids, depth) = (tex(wgpu::TextureFormat::Rgba8Unorm, ta), tex(wgpu::TextureFormat::R32Uint, ta), tex(wgpu::TextureFormat::Depth32Float, ta));
    let render = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: None,
        vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[] },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::TextureFormat::Rgba8Unorm.into()), None],
        }),
        multiview_mask: None,
        cache: None,
    });
    let att = |v| {
        Some(wgpu::RenderPassColorAttachment { view: v, depth_slice: None, resolve_target: None, ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store } })
    };
    let render_pass = |enc: &mut wgpu::CommandEncoder, draw: bool| {
        let mut p = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[att(&color), att(&ids)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if draw {
            p.set_pipeline(&render);
            p.multi_draw_indirect_count(&other, 0, &other, 0, 1);
        }
    };
    let time = |k: u32, what: &dyn Fn(&mut wgpu::CommandEncoder)| -> f64 {
        let mut enc = d.create_command_encoder(&Default::default());
        for _ in 0..k {
            what(&mut enc);
        }
        let t = Instant::now();
        gpu.queue.submit([enc.finish()]);
        d.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        t.elapsed().as_secs_f64() * 1e3
    };
    let cost = |what: &dyn Fn(&mut wgpu::CommandEncoder)| -> f64 {
        time(K, what);
        let mut v: Vec<f64> = (0..TRIES).map(|_| (time(K, what) - time(0, what)) / K as f64).collect();
        v.sort_by(f64::total_cmp);
        v[TRIES / 2]
    };
    let dispatch = |p: &mut wgpu::ComputePass<'_>| {
        p.set_pipeline(&pipeline);
        p.set_bind_group(0, &bind, &[]);
        p.dispatch_workgroups(1, 1, 1);
    };
    println!("# {} at {w}x{h}: ms of GPU work per command (K = {K}, median of {TRIES})", gpu.adapter_name());
    println!("compute pass, one dispatch   {:.4}", cost(&|e| dispatch(&mut e.begin_compute_pass(&Default::default()))));
    println!(
        "dispatch in an open pass     {:.4}",
        cost(&|e| {
            let mut p = e.begin_compute_pass(&Default::default());
            for _ in 0..8 {
                dispatch(&mut p);
            }
        }) / 8.0
    );
    let bufs: Vec<(wgpu::Buffer, wgpu::BindGroup)> = (0..8)
        .map(|_| {
            let b = d.create_buffer(&wgpu::BufferDescriptor { label: None, size: 256, usage: U::STORAGE, mapped_at_creation: false });
            let g = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: b.as_entire_binding() }],
            });
            (b, g)
        })
        .collect();
    // Eight dispatches in one pass, each on a buffer of its own: workgroups
    // from the CPU (one each), or from a buffer (none).
    let over_bufs = |e: &mut wgpu::CommandEncoder, indirect: bool| {
        let mut p = e.begin_compute_pass(&Default::default());
        p.set_pipeline(&pipeline);
        for (_, g) in &bufs {
            p.set_bind_group(0, g, &[]);
            match indirect {
                false => p.dispatch_workgroups(1, 1, 1),
                true => p.dispatch_workgroups_indirect(&zero, 0),
            }
        }
    };
    println!("independent dispatch         {:.4}", cost(&|e| over_bufs(e, false)) / 8.0);
    println!("indirect dispatch of 0       {:.4}", cost(&|e| over_bufs(e, true)) / 8.0);
    println!("render pass, empty           {:.4}", cost(&|e| render_pass(e, false)));
    println!("render pass, count draw of 0 {:.4}", cost(&|e| render_pass(e, true)));
    println!("clear_buffer (256 B)         {:.4}", cost(&|e| e.clear_buffer(&data, 0, None)));
    println!("copy_buffer_to_buffer (16 B) {:.4}", cost(&|e| e.copy_buffer_to_buffer(&data, 0, &other, 0, Some(16))));
    Ok(())
}
