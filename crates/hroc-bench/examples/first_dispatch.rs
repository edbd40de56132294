//! What a compute pipeline's first dispatch costs on this device, and
//! whether a dispatch of zero workgroups before it (what
//! `CullMethod::warm` records) takes that cost away. llvmpipe compiles a
//! pipeline's code on its first dispatch, not when it is created.
//!
//! Per try, three fresh pipelines (each of its own shader, so none shares
//! compiled code): one dispatched cold, one after a zero-workgroup
//! dispatch, one after a one-workgroup dispatch; each then twice for real.
//! Times are the CPU's, from recording to the device's completion.
//!
//! `cargo run --release -p hroc-bench --example first_dispatch`

use hroc_bench::gpu::Headless;

const SHADER: &str = r#"
@group(0) @binding(0) var<storage, read_write> data: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&data)) { return; }
    var v = data[id.x];
    for (var i = 0u; i < 4u; i++) {
        v = vec4<f32>(v.y * SCALE + sin(v.x), v.z + cos(v.w), v.x * v.y, v.w + 1.0);
        if (v.x > 3.0) { v = v * 0.25; }
        v = normalize(v + vec4<f32>(1.0));
    }
    data[id.x] = v;
}
"#;

const GROUPS: u32 = 1024;

fn main() -> hroc_bench::Result<()> {
    let gpu = Headless::new()?;
    let d = &gpu.device;
    let size = GROUPS as u64 * 64 * 16;
    let data = d.create_buffer(&wgpu::BufferDescriptor { label: Some("data"), size, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
    println!("# {}", gpu.adapter_name());
    println!("| before | that dispatch, ms | first real dispatch, ms | second, ms |");
    println!("|---|---|---|---|");
    let mut shader = 0;
    for _ in 0..3 {
        for before in [None, Some(0), Some(1)] {
            // A shader of its own: a different constant is a different module.
            shader += 1;
            let source = SHADER.replace("SCALE", &format!("{:.6}", 0.5 + shader as f32 * 1e-3));
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("first dispatch"), source: wgpu::ShaderSource::Wgsl(source.into()) });
            let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("first dispatch"),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("first dispatch"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: data.as_entire_binding() }],
            });
            let dispatch = |groups: u32| -> hroc_bench::Result<f64> {
                let start = std::time::Instant::now();
                let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("first dispatch") });
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("first dispatch"), timestamp_writes: None });
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    pass.dispatch_workgroups(groups, 1, 1);
                }
                gpu.queue.submit([enc.finish()]);
                gpu.wait()?;
                Ok(start.elapsed().as_secs_f64() * 1e3)
            };
            let warm = before.map(dispatch).transpose()?;
            let (first, second) = (dispatch(GROUPS)?, dispatch(GROUPS)?);
            let what = before.map_or("nothing".to_string(), |g| format!("{g} workgroups"));
            println!("| {what} | {} | {first:.2} | {second:.2} |", warm.map_or("—".to_string(), |ms| format!("{ms:.2}")));
        }
    }
    Ok(())
}
