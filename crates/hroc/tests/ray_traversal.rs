//! HROC's ray traversal (`cast_ray` in `hroc_test.wgsl`) run on its own
//! on the GPU (a compute probe appended to the pass's source), on a tiny
//! tree and on nodes read as zeros.
//!
//! Zeros are what llvmpipe hands a fragment lane that failed coverage or
//! the early depth test for every storage load, while it runs the lane's
//! loops beside the live ones. Following node 0's "children" cycled
//! there until the driver's loop limiter stopped it at 65,535 iterations,
//! and the whole block of lanes waited: HROC's occlusion test took 40×
//! its time on frames where group boxes covered the world origin (radial
//! city with 10 % of its buildings moving, BENCHMARKS.md). The probe
//! counts the traversal's steps, so the test fails on that count, not on
//! a time.

use glam::{Mat4, Vec3};
use hroc::bvh::{BvhNode, LEAF_BIT, NO_PARENT};
use hroc::testing::layout::FrameUniform;
use hroc::ViewDesc;
use wgpu::util::DeviceExt;

mod common;

const SIZE: u32 = 64;

const PROBE: &str = "
@group(1) @binding(0) var<storage, read_write> probe: array<u32>;

// One ray through the centre of the target, into the subtree of node 0.
@compute @workgroup_size(1)
fn probe_cast() {
    probe[0] = cast_ray(0u, block_ray(frame.viewport.xy * 0.5 / f32(TEST_SCALE)));
}
";

/// Steps of the probe's ray and the occludee marks it left, for `nodes`
/// (padded with zeroed nodes past the tree) over a map cleared to the far plane.
fn cast(device: &wgpu::Device, queue: &wgpu::Queue, nodes: &[BvhNode], objects: u32, scale: u32) -> (u32, Vec<u32>) {
    let view = ViewDesc { view: Mat4::look_at_rh(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y), proj: Mat4::perspective_rh(1.0, 1.0, 0.1, 100.0), unclipped_depth: false };
    let frame: FrameUniform = view.geometry().unwrap().uniform((SIZE, SIZE), objects, nodes.len() as u32);
    let mut padded = nodes.to_vec();
    padded.resize(nodes.len() + 8, node([0.0; 3], [0.0; 3], 0, 0));
    let buffer = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let frame_buf = buffer("frame", bytemuck::bytes_of(&frame), wgpu::BufferUsages::UNIFORM);
    let nodes_buf = buffer("nodes", bytemuck::cast_slice(&padded), storage);
    let occludees = buffer("occludees", &vec![0u8; 4 * objects as usize], storage);
    let visited = buffer("visited", &vec![0u8; 4 * padded.len()], storage);
    // No object has an oriented box (`valid` 0): 64 bytes each.
    let oriented = buffer("oriented", &vec![0u8; 64 * objects as usize], storage);
    let probe = buffer("probe", &[0u8; 4], storage);
    let map = common::depth_texture(device, SIZE);
    let map_view = map.create_view(&Default::default());
    let source = format!("{}\n{PROBE}", hroc::testing::shaders::source("hroc_test.wgsl"));
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("probe"), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let constants = [("TEST_SCALE", scale as f64)];
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("probe_cast"),
        layout: None,
        module: &module,
        entry_point: Some("probe_cast"),
        compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
        cache: None,
    });
    let bind = |group: u32, entries: &[(u32, wgpu::BindingResource)]| {
        let entries: Vec<wgpu::BindGroupEntry> = entries.iter().map(|(binding, resource)| wgpu::BindGroupEntry { binding: *binding, resource: resource.clone() }).collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &pipeline.get_bind_group_layout(group), entries: &entries })
    };
    let scene = bind(
        0,
        &[
            (0, frame_buf.as_entire_binding()),
            (1, nodes_buf.as_entire_binding()),
            (2, occludees.as_entire_binding()),
            (3, visited.as_entire_binding()),
            (4, wgpu::BindingResource::TextureView(&map_view)),
            (15, oriented.as_entire_binding()),
        ],
    );
    let out = bind(1, &[(0, probe.as_entire_binding())]);
    let mut enc = device.create_command_encoder(&Default::default());
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear map"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &map_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &scene, &[]);
        pass.set_bind_group(1, &out, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    queue.submit([enc.finish()]);
    let gpu = hroc::testing::gpu::Gpu::from_device(device, queue);
    let steps = gpu.read::<u32>(&probe, 0, 1).unwrap()[0];
    let marks = gpu.read::<u32>(&occludees, 0, objects as u64).unwrap();
    (steps, marks)
}

fn node(min: [f32; 3], max: [f32; 3], child: u32, parent: u32) -> BvhNode {
    BvhNode { min, child, max, parent }
}

#[test]
fn cast_ray_ends_on_zeroed_nodes_and_marks_what_it_enters() {
    // The pass's fragment entry points force early depth tests.
    let (device, queue) = common::device(wgpu::Features::SHADER_EARLY_DEPTH_TEST);
    for scale in [1, 2] {
        // Every node read as zeros: node 0 names child 0, whose box (at the
        // origin, on the ray) is entered in front of the far map.
        let (steps, marks) = cast(&device, &queue, &[node([0.0; 3], [0.0; 3], 0, 0); 3], 2, scale);
        assert_eq!((steps, marks.as_slice()), (0, [0, 0].as_slice()), "scale {scale}: a ray into zeroed nodes must end at once");
        // A root over two leaves: the ray through the origin enters object
        // 0's box, not object 1's, and visits both leaves once.
        let tree = [
            node([-1.0, -1.0, -1.0], [11.0, 1.0, 1.0], 1, NO_PARENT),
            node([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5], LEAF_BIT, 0),
            node([9.5, -0.5, -0.5], [10.5, 0.5, 0.5], LEAF_BIT | 1, 0),
        ];
        let (steps, marks) = cast(&device, &queue, &tree, 2, scale);
        assert_eq!((steps, marks.as_slice()), (2, [1, 0].as_slice()), "scale {scale}");
    }
}
