//! A host that builds its pipelines before the culler exists
//! ([`hroc::device::marks_layout`] from the device alone), draws the culler's lists
//! through them and its own object through the same pipeline with
//! [`hroc::Culler::sink_marks`], on lavapipe. wgpu panics on a validation
//! error, so a layout the culler's bind groups do not fit fails the test;
//! the marks the host's fragment shader leaves must reach the culler, and
//! the view's [`hroc::stats::FrameStats`] count what the host drew.

use glam::{Mat4, Vec3};
use hroc::stats::Stat;
use hroc::{Aabb, Culler, CullerDesc, DepthRange, Draw, FrameInput, Method, ObjectDesc, ObjectFlags, ViewDesc, ViewTargets};
use wgpu::util::DeviceExt;

mod common;

const SIZE: u32 = 64;

/// Two unit quads facing the eye (+z): object 0 at z = 0, object 1 behind
/// it at z = -4; and the host's own quad (not the culler's) at z = -8.
fn quad(z: f32) -> [[f32; 3]; 4] {
    [[-1.0, -1.0, z], [1.0, -1.0, z], [1.0, 1.0, z], [-1.0, 1.0, z]]
}

/// A depth-only pass of the host on `depth`.
fn pass<'e>(encoder: &'e mut wgpu::CommandEncoder, depth: &wgpu::TextureView, load: wgpu::LoadOp<f32>) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("host"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations { load, store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

#[test]
fn pipelines_built_before_the_culler_draw_its_lists_and_the_hosts_own() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    // The host's pipeline first: camera at group 0, hroc's marks at group 1.
    let (pipeline, camera_layout) = common::host_pipeline(&device, false, true);

    // Geometry, targets and camera.
    let vertices: Vec<[f32; 3]> = [0.0, -4.0, -8.0].iter().flat_map(|&z| quad(z)).collect();
    let indices: Vec<u32> = (0..3u32).flat_map(|q| [0, 1, 2, 0, 2, 3].map(|i| 4 * q + i)).collect();
    let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
    let vertex_buf = init("vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
    let index_buf = init("indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
    let view = ViewDesc { view: Mat4::look_at_rh(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y), proj: Mat4::perspective_rh(1.2, 1.0, 0.1, 100.0), unclipped_depth: false };
    let camera_buf = init("camera", bytemuck::bytes_of(&(view.proj * view.view)), wgpu::BufferUsages::UNIFORM);
    let camera = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &camera_layout,
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: camera_buf.as_entire_binding() }],
    });
    let depth = common::depth_texture(&device, SIZE);
    let depth_view = depth.create_view(&Default::default());

    // Then the culler, over the first two quads.
    let object = |k: u32, z: f32| ObjectDesc {
        bounds: Aabb::new(Vec3::new(-1.0, -1.0, z), Vec3::new(1.0, 1.0, z)),
        index_count: 6,
        first_index: 6 * k,
        base_vertex: 0,
        flags: ObjectFlags::NONE,
        oriented: None,
    };
    let objects = [object(0, 0.0), object(1, -4.0)];
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    let targets = ViewTargets::new(&depth, DepthRange::Standard);
    let mut v = culler.view(Method::Hroc(hroc::options::Variant::NA), &targets).unwrap();
    for frame in 0..3 {
        let mut encoder = device.create_command_encoder(&Default::default());
        drop(pass(&mut encoder, &depth_view, wgpu::LoadOp::Clear(1.0)));
        let input = FrameInput { view, cut: false, time: frame as f32 };
        v.cull(&culler, &mut encoder, &input, &mut |enc: &mut wgpu::CommandEncoder, draw: &Draw| {
            let mut pass = pass(enc, &depth_view, wgpu::LoadOp::Load);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_vertex_buffer(0, vertex_buf.slice(..));
            pass.set_index_buffer(index_buf.slice(..), wgpu::IndexFormat::Uint32);
            draw.record(&mut pass, &pipeline, 1);
        })
        .unwrap();
        // The host's own quad, through the same pipeline, marking nothing.
        let mut pass = pass(&mut encoder, &depth_view, wgpu::LoadOp::Load);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, culler.sink_marks(), &[]);
        pass.set_vertex_buffer(0, vertex_buf.slice(..));
        pass.set_index_buffer(index_buf.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(12..18, 0, 7..8);
        drop(pass);
        queue.submit([encoder.finish()]);
        // The host's fragments marked object 0 (in front) as an occluder;
        // object 1, behind it, was not drawn after the first frame.
        let stats = v.stats(&culler).unwrap();
        let stat = |s: Stat| stats.iter().find(|x| x.0 == s).map(|x| x.1);
        if frame > 0 {
            assert_eq!(stat(Stat::O), Some(1.0), "frame {frame}: {stats:?}");
            assert_eq!(stat(Stat::D), Some(0.0), "frame {frame}: {stats:?}");
        }
    }
    // The statistics every method shares come back without a wait, tagged:
    // frame 2's were mapped once its encoder was submitted and done. Frame
    // 2 drew object 0 alone (two triangles).
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let s = v.frame_stats(&culler).expect("frame 2's statistics");
    assert_eq!((s.frame, s.objects, s.triangles, s.cut, s.waits), (2, 1, 2, false, 0), "{s:?}");
}
