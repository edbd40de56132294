//! Validation (`CullerDesc::validation`), on lavapipe: each host mistake
//! that makes a view cull what it must draw, made by a host of a few
//! lines drawing the street (with an ID target, or depth only, as shadow
//! maps are drawn), gives an error naming it and its fix within 3 frames
//! with validation on, and changes nothing with it off; the frame that
//! reports a finding draws what it draws without validation; the same
//! host without mistakes raises none.

use common::street::{boxes, cube, look, Depth, SIZE};
use glam::{Mat4, Vec3};
use hroc::device::{Capabilities, Marks};
use hroc::{Aabb, Culler, CullerDesc, DepthRange, Draw, Error, FrameInput, Method, ObjectDesc, ObjectFlags, View, ViewDesc, ViewTargets};
use wgpu::util::DeviceExt;

mod common;

/// What the host gets wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mistake {
    None,
    /// Depth and IDs cleared in every draw's pass (`LoadOp::Clear`).
    ClearInDraw,
    /// Depth bias toward the viewer (constant −2000, slope −4), as a
    /// shadow pass biased the wrong way.
    BiasTowardViewer,
    /// An occluding fragment shader without `hroc_mark` and without
    /// `@early_depth_test(force)`.
    NoMark,
    /// `hroc_mark` without `@early_depth_test(force)`.
    MarkWithoutEarlyZ,
    /// IDs written as the object index, not index + 1.
    IndexForId,
    /// A marking pipeline whose layout has no marks group.
    NoMarksGroup,
    /// Object 20's box 10 % smaller than what it draws, as it moves.
    SmallBoxMoving,
    /// Depth only: constant depth bias toward the light (−300000: about a
    /// metre here) in an orthographic cascade.
    BiasConstantNoIds,
    /// Depth only: slope-scaled depth bias toward the light (−4).
    BiasSlopeNoIds,
    /// Depth only: the wall's box 15 % smaller than the wall.
    SmallBoxNoIds,
    /// The targets are never cleared.
    NeverCleared,
    /// No mistake: depth only, in the orthographic cascade.
    CascadeNoIds,
    /// No mistake: depth only, along the street.
    StreetNoIds,
}

impl Mistake {
    /// The host draws depth only (no ID target), as shadow passes do.
    fn depth_only(self) -> bool {
        matches!(self, Mistake::BiasConstantNoIds | Mistake::BiasSlopeNoIds | Mistake::SmallBoxNoIds | Mistake::CascadeNoIds | Mistake::StreetNoIds)
    }
}

/// The wall: object 0.
const WALL: usize = 0;

/// The moving object of [`Mistake::SmallBoxMoving`].
const MOVER: usize = 20;

/// A host that draws the street with one pipeline for every draw, made
/// with `mistake`.
struct Host {
    mistake: Mistake,
    pipeline: wgpu::RenderPipeline,
    camera: wgpu::Buffer,
    camera_bind: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    corners: Vec<[f32; 3]>,
    depth: wgpu::Texture,
    ids: wgpu::Texture,
}

impl Host {
    fn new(device: &wgpu::Device, mistake: Mistake) -> (Host, Vec<ObjectDesc>) {
        let (mut corners, mut indices, mut objects) = (Vec::new(), Vec::new(), Vec::new());
        for (i, b) in boxes().iter().enumerate() {
            let (v, idx) = cube(b);
            let base = corners.len() as u32;
            corners.extend(v);
            indices.extend(idx.map(|k| k + base));
            let bounds = match (mistake, i) {
                (Mistake::SmallBoxNoIds, WALL) => Aabb::new(b.min + 0.075 * (b.max - b.min), b.max - 0.075 * (b.max - b.min)),
                _ => *b,
            };
            objects.push(ObjectDesc { bounds, index_count: 36, first_index: 36 * i as u32, base_vertex: 0, flags: ObjectFlags::NONE, oriented: None });
        }
        let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let (pipeline, camera_layout) = pipeline(device, mistake);
        let camera = init("camera", &[0u8; 64], wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let camera_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &camera_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() }],
        });
        use wgpu::TextureUsages as U;
        let host = Host {
            mistake,
            pipeline,
            camera,
            camera_bind,
            vertices: init("vertices", bytemuck::cast_slice(&corners), wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST),
            indices: init("indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
            corners,
            depth: common::texture(device, wgpu::TextureFormat::Depth32Float, (SIZE, SIZE, 1), 1, 1, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC),
            ids: common::texture(device, wgpu::TextureFormat::R32Uint, (SIZE, SIZE, 1), 1, 1, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING),
        };
        (host, objects)
    }

    fn targets(&self) -> ViewTargets<'_> {
        let depth = ViewTargets::new(&self.depth, DepthRange::Standard);
        if self.mistake.depth_only() {
            depth
        } else {
            depth.with_ids(&self.ids)
        }
    }

    fn pass<'e>(&self, enc: &'e mut wgpu::CommandEncoder, clear: bool) -> wgpu::RenderPass<'e> {
        let (depth, ids) = (self.depth.create_view(&Default::default()), self.ids.create_view(&Default::default()));
        fn ops<T>(clear: bool, c: T) -> wgpu::Operations<T> {
            wgpu::Operations { load: if clear { wgpu::LoadOp::Clear(c) } else { wgpu::LoadOp::Load }, store: wgpu::StoreOp::Store }
        }
        let ids = Some(wgpu::RenderPassColorAttachment { view: &ids, depth_slice: None, resolve_target: None, ops: ops(clear, wgpu::Color::TRANSPARENT) });
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host"),
            color_attachments: if self.mistake.depth_only() { &[] } else { std::slice::from_ref(&ids) },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment { view: &depth, depth_ops: Some(ops(clear, 1.0)), stencil_ops: None }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Frame `k` of `view` seen from `desc`, submitted and waited for: the
    /// cull's result.
    fn frame(&self, device: &wgpu::Device, queue: &wgpu::Queue, culler: &mut Culler, view: &mut View, desc: ViewDesc, k: usize) -> hroc::Result<()> {
        let mut enc = device.create_command_encoder(&Default::default());
        if self.mistake == Mistake::SmallBoxMoving {
            // The mover slides along the street; its box is 10 % too small.
            let shift = Vec3::new(0.3 * k as f32, 0.0, 0.0);
            let moved: Vec<[f32; 3]> = self.corners[8 * MOVER..8 * MOVER + 8].iter().map(|&c| (Vec3::from(c) + shift).to_array()).collect();
            let staging = device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: None, contents: bytemuck::cast_slice(&moved), usage: wgpu::BufferUsages::COPY_SRC });
            enc.copy_buffer_to_buffer(&staging, 0, &self.vertices, (8 * MOVER * 12) as u64, 96);
            let b = boxes()[MOVER];
            let (centre, half) = ((b.min + b.max) * 0.5 + shift, (b.max - b.min) * 0.45);
            culler.set_bounds(&[(MOVER as u32, Aabb::new(centre - half, centre + half))]).unwrap();
        }
        let camera = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::bytes_of(&(desc.proj * desc.view)),
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        enc.copy_buffer_to_buffer(&camera, 0, &self.camera, 0, 64);
        if self.mistake != Mistake::NeverCleared {
            drop(self.pass(&mut enc, true));
        }
        let result = view.cull(culler, &mut enc, &FrameInput { view: desc, cut: false, time: k as f32 }, &mut |enc: &mut wgpu::CommandEncoder, draw: &Draw| {
            let mut pass = self.pass(enc, self.mistake == Mistake::ClearInDraw);
            pass.set_bind_group(0, &self.camera_bind, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            draw.record(&mut pass, &self.pipeline, 1);
        });
        queue.submit([enc.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        result
    }

    /// The depth target, read back.
    fn read_depth(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<f32> {
        let row = SIZE * 4;
        let buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: (row * SIZE) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = device.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo { texture: &self.depth, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::DepthOnly },
            wgpu::TexelCopyBufferInfo { buffer: &buf, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row.max(256)), rows_per_image: None } },
            wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
        );
        queue.submit([enc.finish()]);
        buf.slice(..).map_async(wgpu::MapMode::Read, |_| ());
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let depth = buf.slice(..).get_mapped_range().unwrap().chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        depth
    }
}

/// The host's pipeline with `mistake`: positions at location 0,
/// `view_proj` at group 0, hroc's marks at group 1, depth and the ID
/// target written.
fn pipeline(device: &wgpu::Device, mistake: Mistake) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    let shader = common::Shader {
        ids: (!mistake.depth_only()).then_some(if mistake == Mistake::IndexForId { "in.object" } else { "in.object + 1u" }),
        early_z: !matches!(mistake, Mistake::NoMark | Mistake::MarkWithoutEarlyZ | Mistake::NoMarksGroup),
        mark: !matches!(mistake, Mistake::NoMark | Mistake::NoMarksGroup),
        marks_group: mistake != Mistake::NoMarksGroup,
        discard: false,
    };
    let bias = match mistake {
        Mistake::BiasTowardViewer => wgpu::DepthBiasState { constant: -2000, slope_scale: -4.0, clamp: 0.0 },
        Mistake::BiasConstantNoIds => wgpu::DepthBiasState { constant: -300_000, slope_scale: 0.0, clamp: 0.0 },
        Mistake::BiasSlopeNoIds => wgpu::DepthBiasState { constant: 0, slope_scale: -4.0, clamp: 0.0 },
        _ => Default::default(),
    };
    common::host_pipeline_with(device, &shader, &Depth { bias, ..Depth::default() })
}

/// The views: a walk along the street, or (for the biased shadow pass) a
/// directional light's orthographic cascade looking down the street.
fn path(mistake: Mistake, k: usize) -> ViewDesc {
    match mistake {
        Mistake::BiasTowardViewer | Mistake::BiasConstantNoIds | Mistake::BiasSlopeNoIds | Mistake::CascadeNoIds => {
            let light = Vec3::new(0.3 + 0.02 * k as f32, 0.6, 1.0).normalize();
            let target = Vec3::new(0.0, 0.0, -8.0);
            ViewDesc { view: Mat4::look_at_rh(target + 30.0 * light, target, Vec3::Y), proj: Mat4::orthographic_rh(-16.0, 16.0, -16.0, 16.0, 1.0, 60.0), unclipped_depth: false }
        }
        _ => look(Vec3::new(-3.0 + 0.25 * k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)),
    }
}

/// A frame's result, and the host's depth after it (f32 per pixel).
type Frame = (hroc::Result<()>, Vec<f32>);

/// The first 6 frames of `method` culling for a host making `mistake`
/// on a culler of `caps`: each cull's result, and the depth it left.
fn run_on(caps: Capabilities, mistake: Mistake, method: Method, validation: bool) -> Vec<Frame> {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = Host::new(&device, mistake);
    let mut culler = Culler::new(&device, &queue, &CullerDesc { validation, capabilities: Some(caps), ..CullerDesc::new(&objects) }).unwrap();
    let mut view = culler.view(method, &host.targets()).unwrap();
    (0..6).map(|k| (host.frame(&device, &queue, &mut culler, &mut view, path(mistake, k), k), host.read_depth(&device, &queue))).collect()
}

/// [`run_on`] on the full tier: each cull's result.
fn run(mistake: Mistake, method: Method, validation: bool) -> Vec<hroc::Result<()>> {
    run_on(Capabilities::FULL, mistake, method, validation).into_iter().map(|(r, _)| r).collect()
}

/// With validation, an error within 3 frames whose message has `words`;
/// without, every frame culls as before.
fn caught(mistake: Mistake, method: Method, words: &[&str]) {
    caught_on(Capabilities::FULL, mistake, method, words);
}

/// [`caught`] on a culler of `caps`; returns the first finding, if the
/// error was one (a refused pipeline is not). Every frame, findings or
/// not, leaves the depth it leaves without validation.
fn caught_on(caps: Capabilities, mistake: Mistake, method: Method, words: &[&str]) -> Option<hroc::stats::Finding> {
    let on = run_on(caps, mistake, method, true);
    let first = on.iter().position(|(r, _)| r.is_err());
    assert!(first.is_some_and(|k| k < 3), "{mistake:?} ({method}): no error within 3 frames: {:?}", on.iter().map(|(r, _)| r).collect::<Vec<_>>());
    let error = on[first.unwrap()].0.as_ref().unwrap_err();
    let message = error.to_string();
    for w in words {
        assert!(message.contains(w), "{mistake:?} ({method}): the error does not say {w:?}: {message}");
    }
    let off = run_on(caps, mistake, method, false);
    assert!(off.iter().all(|(r, _)| r.is_ok()), "{mistake:?} ({method}) without validation: {:?}", off.iter().map(|(r, _)| r).collect::<Vec<_>>());
    // A finding costs no frame (a refused pipeline draws nothing).
    for (k, ((r, a), (_, b))) in on.iter().zip(&off).enumerate() {
        assert!(a == b || matches!(r, Err(Error::InvalidPipeline(_))), "{mistake:?} ({method}): frame {k} drew other depth with validation on");
    }
    match error {
        Error::Validation(finding) => Some(finding.clone()),
        _ => None,
    }
}

/// The tiers a depth-only view is tested on: full, and portable with
/// box marks (its ID marks need an ID target).
const DEPTH_ONLY_TIERS: [Capabilities; 2] = [Capabilities::FULL, Capabilities { marks: Marks::Boxes, ..Capabilities::PORTABLE }];

/// The methods of views without an ID target.
const DEPTH_ONLY_METHODS: [Method; 2] = [Method::Hroc(hroc::options::Variant::SF), Method::Hzb];

#[test]
fn a_host_that_keeps_the_contract_raises_no_alarm() {
    for method in [Method::HROC, Method::Hroc(hroc::options::Variant::NA), Method::Hzb, Method::Roc, Method::Noc, Method::Auto] {
        let results = run(Mistake::None, method, true);
        assert!(results.iter().all(|r| r.is_ok()), "{method}: {results:?}");
    }
}

#[test]
fn a_depth_only_host_that_keeps_the_contract_raises_no_alarm() {
    for caps in DEPTH_ONLY_TIERS {
        for (method, clean) in DEPTH_ONLY_METHODS.into_iter().flat_map(|m| [(m, Mistake::CascadeNoIds), (m, Mistake::StreetNoIds)]) {
            let results: Vec<_> = run_on(caps, clean, method, true).into_iter().map(|(r, _)| r).collect();
            assert!(results.iter().all(|r| r.is_ok()), "{clean:?} ({method}, {caps:?}): {results:?}");
        }
    }
}

#[test]
fn depth_bias_toward_the_light_without_ids_is_caught() {
    for caps in DEPTH_ONLY_TIERS {
        for method in DEPTH_ONLY_METHODS {
            for mistake in [Mistake::BiasConstantNoIds, Mistake::BiasSlopeNoIds] {
                caught_on(caps, mistake, method, &["in front of every box", "bias depth only away from the viewer or light", "DepthBiasState"]);
            }
        }
    }
}

#[test]
fn a_box_too_small_in_a_depth_only_view_is_caught() {
    for caps in DEPTH_ONLY_TIERS {
        for method in DEPTH_ONLY_METHODS {
            let finding = caught_on(caps, Mistake::SmallBoxNoIds, method, &["in front of every box", "Culler::set_bounds"]).expect("a finding");
            assert_eq!(finding.object, Some(WALL as u32), "{method}: the suspect is the wall, whose box is small: {finding}");
        }
    }
}

#[test]
fn targets_never_cleared_are_named_as_the_cause() {
    for method in [Method::HROC, Method::Hzb] {
        let finding = caught_on(Capabilities::FULL, Mistake::NeverCleared, method, &["not cleared", "before View::cull"]).expect("a finding");
        eprintln!("{finding}");
        assert!(finding.cause.contains("not cleared"), "{method}: the cause is the missing clear: {finding}");
    }
}

#[test]
fn a_clear_inside_the_frame_is_caught() {
    caught(Mistake::ClearInDraw, Method::HROC, &["cleared", "LoadOp::Load"]);
    caught(Mistake::ClearInDraw, Method::Hzb, &["cleared"]);
}

#[test]
fn depth_bias_toward_the_light_is_caught() {
    caught(Mistake::BiasTowardViewer, Method::HROC, &["in front of its box", "bias depth only away"]);
}

#[test]
fn a_shader_that_does_not_mark_is_caught() {
    caught(Mistake::NoMark, Method::HROC, &["not marked", "hroc_mark"]);
    caught(Mistake::NoMark, Method::Roc, &["hroc_mark"]);
}

#[test]
fn marks_without_forced_early_z_are_caught() {
    caught(Mistake::MarkWithoutEarlyZ, Method::HROC, &["failed the depth test", "@early_depth_test(force)"]);
}

#[test]
fn ids_written_as_the_index_are_caught() {
    caught(Mistake::IndexForId, Method::HROC, &["index + 1"]);
}

#[test]
fn a_pipeline_without_the_marks_group_is_refused() {
    caught(Mistake::NoMarksGroup, Method::HROC, &["no marks group at group 1", "marks_layout"]);
    let on = run(Mistake::NoMarksGroup, Method::HROC, true);
    assert!(matches!(on[0], Err(Error::InvalidPipeline(_))), "refused on the first frame, before the draw: {on:?}");
}

#[test]
fn a_box_too_small_around_a_moving_object_is_caught() {
    caught(Mistake::SmallBoxMoving, Method::HROC, &[&format!("object {MOVER}"), "in front of its box", "set_bounds"]);
}

#[test]
fn index_ranges_past_the_declared_buffer_are_refused() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (_, mut objects) = Host::new(&device, Mistake::None);
    let indices = objects.len() as u32 * 36;
    objects[3].first_index = 1_000_000;
    let declared = |objects, validation| CullerDesc { index_count: Some(indices), validation, ..CullerDesc::new(objects) };
    let refused = Culler::new(&device, &queue, &declared(&objects, true)).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(refused.contains("object 3") && refused.contains("CullerDesc::index_count"), "{refused}");
    // Added later, too; without validation, as before.
    let (_, good) = Host::new(&device, Mistake::None);
    let mut culler = Culler::new(&device, &queue, &declared(&good, true)).unwrap();
    assert!(culler.add_objects(&objects[3..4]).is_err());
    assert!(Culler::new(&device, &queue, &declared(&objects, false)).is_ok());
    assert!(Culler::new(&device, &queue, &declared(&good, false)).unwrap().add_objects(&objects[3..4]).is_ok());
}
