//! A street of cubes behind a wall, and a host of a few lines that draws
//! it: one pipeline writing depth and `object + 1`, marking its object.

use glam::{Mat4, Vec3};
use hroc::device::DrawCount;
use hroc::{Aabb, Culler, DepthRange, Draw, FrameInput, ObjectDesc, ObjectFlags, View, ViewDesc, ViewTargets};
use wgpu::util::DeviceExt;

/// Width and height of the targets.
pub const SIZE: u32 = 64;

/// Boxes: a wall across the street, cubes before and behind it, and a
/// large box the camera enters.
pub fn boxes() -> Vec<Aabb> {
    let mut b = vec![Aabb::new(Vec3::new(-10.0, 0.0, -6.5), Vec3::new(10.0, 4.0, -6.0))];
    for x in (-8i32..=8).step_by(2) {
        for z in (-20..=0).step_by(3) {
            b.push(Aabb::new(Vec3::new(x as f32 - 0.5, 0.0, z as f32 - 0.5), Vec3::new(x as f32 + 0.5, 1.0 + (x + z).rem_euclid(3) as f32, z as f32 + 0.5)));
        }
    }
    b.push(Aabb::new(Vec3::new(-2.0, 0.0, 1.0), Vec3::new(2.0, 3.0, 4.0)));
    b
}

/// The cube of `b`: 8 corners, 12 triangles facing out.
pub fn cube(b: &Aabb) -> ([[f32; 3]; 8], [u32; 36]) {
    let c = |i: u32| [if i & 1 != 0 { b.max.x } else { b.min.x }, if i & 2 != 0 { b.max.y } else { b.min.y }, if i & 4 != 0 { b.max.z } else { b.min.z }];
    let idx = [0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5];
    ((0..8).map(c).collect::<Vec<_>>().try_into().unwrap(), idx)
}

/// The host's depth target: its format, layers and mips, and the layer
/// and mip the host draws into (that mip is `SIZE` × `SIZE`), and its depth
/// convention.
#[derive(Clone, Copy, Debug)]
pub struct Depth {
    pub format: wgpu::TextureFormat,
    pub range: DepthRange,
    /// The host's depth bias (a shadow pass's).
    pub bias: wgpu::DepthBiasState,
    /// The host clamps depth rather than clip it at the near plane.
    pub unclipped: bool,
    pub layers: u32,
    pub mips: u32,
    pub layer: u32,
    pub mip: u32,
    /// Samples per pixel (MSAA above 1: the ID target is then `Rg16Uint`).
    pub samples: u32,
}

impl Depth {
    /// The ID target's format: `Rg16Uint` multisampled (every backend can),
    /// else `R32Uint`.
    pub fn ids_format(&self) -> wgpu::TextureFormat {
        if self.samples > 1 {
            wgpu::TextureFormat::Rg16Uint
        } else {
            wgpu::TextureFormat::R32Uint
        }
    }
}

impl Default for Depth {
    fn default() -> Depth {
        Depth {
            format: wgpu::TextureFormat::Depth32Float,
            range: DepthRange::Standard,
            bias: Default::default(),
            unclipped: false,
            layers: 1,
            mips: 1,
            layer: 0,
            mip: 0,
            samples: 1,
        }
    }
}

/// The host: pipelines writing depth and `object + 1`, one of them marking
/// its object.
pub struct Host {
    pub(super) at: Depth,
    marking: Option<wgpu::RenderPipeline>,
    plain: wgpu::RenderPipeline,
    /// For CUTOUT lists: discards a checkerboard, no early-Z, no mark.
    cutout: wgpu::RenderPipeline,
    pub(super) camera: wgpu::Buffer,
    camera_bind: wgpu::BindGroup,
    pub(super) vertices: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    depth: wgpu::Texture,
    ids: wgpu::Texture,
}

impl Host {
    pub fn new(device: &wgpu::Device, vertices: &[[f32; 3]], indices: &[u32]) -> Host {
        Host::with_depth(device, vertices, indices, Depth::default())
    }

    /// The host drawing into `at`.
    pub fn with_depth(device: &wgpu::Device, vertices: &[[f32; 3]], indices: &[u32], at: Depth) -> Host {
        // The marking pipeline where the device forces early-Z; the plain
        // one for draws that need no mark (Marks::Ids, or nothing read).
        let marking = device.features().contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST).then(|| super::host_pipeline_on(device, true, true, &at).0);
        let (plain, camera_layout) = super::host_pipeline_on(device, true, false, &at);
        let cutout = super::host_pipeline_with(device, &super::Shader { ids: Some("in.object + 1u"), early_z: false, mark: false, marks_group: true, discard: true }, &at).0;
        let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let camera = init("camera", &[0u8; 64], wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let camera_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &camera_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() }],
        });
        use wgpu::TextureUsages as U;
        let ids = super::texture(device, at.ids_format(), (SIZE, SIZE, 1), 1, at.samples, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC);
        let depth = super::texture(device, at.format, (SIZE << at.mip, SIZE << at.mip, at.layers), at.mips, at.samples, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING);
        Host {
            at,
            marking,
            plain,
            cutout,
            camera,
            camera_bind,
            vertices: init("vertices", bytemuck::cast_slice(vertices), wgpu::BufferUsages::VERTEX),
            indices: init("indices", bytemuck::cast_slice(indices), wgpu::BufferUsages::INDEX),
            depth,
            ids,
        }
    }

    pub fn targets(&self) -> ViewTargets<'_> {
        ViewTargets::new(&self.depth, self.at.range).with_ids(&self.ids).at(self.at.layer, self.at.mip)
    }

    pub(super) fn pass<'e>(&self, enc: &'e mut wgpu::CommandEncoder, clear: bool) -> wgpu::RenderPass<'e> {
        let depth = self.depth.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_mip_level: self.at.mip,
            mip_level_count: Some(1),
            base_array_layer: self.at.layer,
            array_layer_count: Some(1),
            ..Default::default()
        });
        let ids = self.ids.create_view(&Default::default());
        let load = |c| if clear { wgpu::LoadOp::Clear(c) } else { wgpu::LoadOp::Load };
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &ids,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: if clear { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load }, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations { load: load(if self.at.range == DepthRange::Standard { 1.0 } else { 0.0 }), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Records one frame of `view` into `enc`: the camera, a clear, the
    /// cull and every list's draw. Everything is recorded in `enc` (no
    /// queue writes), so frames may share an encoder. Returns the lists.
    pub fn record(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        culler: &Culler,
        view: &mut View,
        desc: ViewDesc,
        cut: bool,
    ) -> Vec<(wgpu::Buffer, wgpu::Buffer, u32, DrawCount)> {
        let camera = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera upload"),
            contents: bytemuck::bytes_of(&(desc.proj * desc.view)),
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        enc.copy_buffer_to_buffer(&camera, 0, &self.camera, 0, 64);
        drop(self.pass(enc, true));
        let mut lists = Vec::new();
        view.cull(culler, enc, &FrameInput { view: desc, cut, time: 0.0 }, &mut |enc: &mut wgpu::CommandEncoder, draw: &Draw| {
            let mut pass = self.pass(enc, false);
            pass.set_bind_group(0, &self.camera_bind, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            let pipeline = match (draw.cutout, draw.mark) {
                (true, _) => &self.cutout,
                (false, true) => self.marking.as_ref().expect("a mark asked for without early-Z"),
                (false, false) => &self.plain,
            };
            draw.record(&mut pass, pipeline, 1);
            lists.push((draw.commands.clone(), draw.count.clone(), draw.max_count, draw.draw_count));
        })
        .unwrap();
        lists
    }

    /// One frame of `view`, submitted. Returns the objects the lists drew:
    /// with an emulated count, every command up to the bound that has an
    /// instance (and none past the GPU's count may have one).
    pub fn frame(&self, device: &wgpu::Device, queue: &wgpu::Queue, culler: &Culler, view: &mut View, desc: ViewDesc, cut: bool) -> Vec<u32> {
        let mut enc = device.create_command_encoder(&Default::default());
        let lists = self.record(device, &mut enc, culler, view, desc, cut);
        queue.submit([enc.finish()]);
        let gpu = hroc::testing::gpu::Gpu::from_device(device, queue);
        let mut drawn = Vec::new();
        for (commands, count, max_count, draw_count) in &lists {
            let within = gpu.read_list(commands, count, *max_count).unwrap();
            let drawn_commands = match draw_count {
                DrawCount::Indirect => within,
                DrawCount::Emulated => {
                    let all: Vec<hroc::testing::layout::DrawCommand> = gpu.read(commands, 0, *max_count as u64).unwrap();
                    assert!(all[within.len()..].iter().all(|c| c.instance_count == 0), "an emulated count drew a command past the GPU's count");
                    all
                }
            };
            drawn.extend(drawn_commands.iter().filter(|c| c.instance_count > 0 && c.index_count > 0).map(|c| c.first_instance));
        }
        drawn.sort_unstable();
        drawn.dedup();
        drawn
    }

    /// The objects `noc` shows at each view of `path` (a `noc` view of
    /// `culler` drawn along it).
    pub fn visible_along(&self, device: &wgpu::Device, queue: &wgpu::Queue, culler: &Culler, path: &[(ViewDesc, bool)]) -> Vec<Vec<u32>> {
        let mut truth = culler.view(hroc::Method::Noc, &self.targets()).unwrap();
        path.iter()
            .map(|&(desc, cut)| {
                self.frame(device, queue, culler, &mut truth, desc, cut);
                self.visible(device, queue)
            })
            .collect()
    }

    /// Draws `view` along `path`, asserting that each frame draws every
    /// object of `visible` (from [`Host::visible_along`]); returns how many
    /// objects it culled over the path. `label` names the run.
    #[allow(clippy::too_many_arguments)]
    pub fn draws_visible_along(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        culler: &Culler,
        view: &mut View,
        path: &[(ViewDesc, bool)],
        visible: &[Vec<u32>],
        label: &str,
    ) -> usize {
        let mut culled = 0;
        for (k, &(desc, cut)) in path.iter().enumerate() {
            let drawn = self.frame(device, queue, culler, view, desc, cut);
            let missed: Vec<u32> = visible[k].iter().copied().filter(|o| drawn.binary_search(o).is_err()).collect();
            assert!(missed.is_empty(), "{label} frame {k}: visible objects {missed:?} not drawn");
            culled += culler.object_count() as usize - drawn.len();
        }
        // The last frames' validation findings, if the culler validates.
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        view.validation(culler).unwrap_or_else(|e| panic!("{label}: {e}"));
        culled
    }

    /// Records into `enc` a copy of the object-ID image as it stands there.
    pub fn copy_ids(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) -> wgpu::Buffer {
        let buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: (SIZE * SIZE * 4) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        enc.copy_texture_to_buffer(
            self.ids.as_image_copy(),
            wgpu::TexelCopyBufferInfo { buffer: &buf, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(SIZE * 4), rows_per_image: None } },
            wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
        );
        buf
    }

    /// The object-ID image now: `object + 1` per pixel (per sample, each
    /// pixel's in turn), 0 where nothing is.
    pub fn ids(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<u32> {
        hroc_readback::read_ids(device, queue, &self.ids).unwrap()
    }

    /// The objects that own a pixel of the ID image.
    pub fn visible(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<u32> {
        let mut v: Vec<u32> = self.ids(device, queue).into_iter().filter(|&i| i > 0).map(|i| i - 1).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// Reads an ID image copied by [`Host::copy_ids`] (submitted).
pub fn read_ids(device: &wgpu::Device, queue: &wgpu::Queue, buf: &wgpu::Buffer) -> Vec<u32> {
    hroc_readback::read(device, queue, buf, 0, (SIZE * SIZE) as u64).unwrap()
}

/// The street's objects and a host holding its cubes.
pub fn street(device: &wgpu::Device) -> (Host, Vec<ObjectDesc>) {
    street_on(device, Depth::default())
}

/// [`street`], the host drawing into `at`.
pub fn street_on(device: &wgpu::Device, at: Depth) -> (Host, Vec<ObjectDesc>) {
    let boxes = boxes();
    let (mut vertices, mut indices, mut objects) = (Vec::new(), Vec::new(), Vec::new());
    for (i, b) in boxes.iter().enumerate() {
        let (v, idx) = cube(b);
        let base = vertices.len() as u32;
        vertices.extend(v);
        indices.extend(idx.map(|k| k + base));
        objects.push(ObjectDesc { bounds: *b, index_count: 36, first_index: 36 * i as u32, base_vertex: 0, flags: ObjectFlags::NONE, oriented: None });
    }
    (Host::with_depth(device, &vertices, &indices, at), objects)
}

/// A view from `eye` towards `target` with a standard-depth projection.
pub fn look(eye: Vec3, target: Vec3) -> ViewDesc {
    ViewDesc { view: Mat4::look_at_rh(eye, target, Vec3::Y), proj: Mat4::perspective_rh(1.1, 1.0, 0.1, 200.0), unclipped_depth: false }
}
