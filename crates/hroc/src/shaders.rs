//! Every WGSL pass of the culler. Each is compiled with `common.wgsl`
//! prepended. Depth is bound as `texture_2d<f32>` (unfilterable float, which
//! wgpu accepts for depth views; `texture_multisampled_2d<f32>` for MSAA
//! targets): naga's GLSL back end cannot load from a `texture_depth_2d`. `tests/shaders.rs` validates each with naga and checks the
//! Rust mirrors in [`crate::layout`] against the WGSL structs.

use crate::frustum::DepthRange;
use crate::gpu::shape::EncoderShape;
use crate::gpu::Gpu;

/// Every pass, by file name.
pub const SHADERS: &[(&str, &str)] = &[
    ("compact.wgsl", include_str!("../shaders/compact.wgsl")),
    ("split.wgsl", include_str!("../shaders/split.wgsl")),
    ("refit.wgsl", include_str!("../shaders/refit.wgsl")),
    ("vfc.wgsl", include_str!("../shaders/vfc.wgsl")),
    ("set_frustum.wgsl", include_str!("../shaders/set_frustum.wgsl")),
    ("hroc_seed.wgsl", include_str!("../shaders/hroc_seed.wgsl")),
    ("hroc_groups.wgsl", include_str!("../shaders/hroc_groups.wgsl")),
    ("hroc_test.wgsl", include_str!("../shaders/hroc_test.wgsl")),
    ("hroc_next.wgsl", include_str!("../shaders/hroc_next.wgsl")),
    ("hroc_yield.wgsl", include_str!("../shaders/hroc_yield.wgsl")),
    ("overflow.wgsl", include_str!("../shaders/overflow.wgsl")),
    ("roc_boxes.wgsl", include_str!("../shaders/roc_boxes.wgsl")),
    ("roc.wgsl", include_str!("../shaders/roc.wgsl")),
    ("ioc.wgsl", include_str!("../shaders/ioc.wgsl")),
    ("hzb_pyramid.wgsl", include_str!("../shaders/hzb_pyramid.wgsl")),
    ("hzb_test.wgsl", include_str!("../shaders/hzb_test.wgsl")),
    ("woc_warp.wgsl", include_str!("../shaders/woc_warp.wgsl")),
    ("tally.wgsl", include_str!("../shaders/tally.wgsl")),
    ("tail.wgsl", include_str!("../shaders/tail.wgsl")),
    ("visibility.wgsl", include_str!("../shaders/visibility.wgsl")),
    ("id_marks.wgsl", include_str!("../shaders/id_marks.wgsl")),
    ("validate.wgsl", include_str!("../shaders/validate.wgsl")),
];

/// The shared header: the `Frame` uniform, object boxes, BVH nodes, draw
/// commands and the box helpers.
pub const COMMON_WGSL: &str = include_str!("../shaders/common.wgsl");

/// Entries of the BVH traversal stacks (`STACK` in the WGSL, a
/// function-scope array size, which cannot be an override constant): a
/// depth-first walk that pushes both children holds at most depth + 2.
pub const STACK: u32 = 64;

/// Slots the occlusion test spreads its ray counters over (`STAT_SLOTS`),
/// against atomic contention.
pub const STAT_SLOTS: u32 = 64;

/// The constants the WGSL shares with Rust, written from the Rust ones, and
/// the host's targets as the passes that load them declare them, for
/// targets of `samples` samples per pixel: `HostDepth` and `HostIds` are
/// `texture_2d` (loaded at mip 0) or `texture_multisampled_2d` (loaded per
/// sample), and `HOST_SAMPLES` their sample count.
fn prelude(samples: u32) -> String {
    let kind = if samples > 1 { "texture_multisampled_2d" } else { "texture_2d" };
    format!(
        "const STACK: u32 = {STACK}u;\nconst STAT_SLOTS: u32 = {STAT_SLOTS}u;\nconst HOST_SAMPLES: u32 = {samples}u;\n\
         alias HostDepth = {kind}<f32>;\nalias HostIds = {kind}<u32>;\n"
    )
}

/// The full source of a pass over single-sample targets: the constants
/// shared with Rust, the shared header, then the pass. Panics on a name not
/// in [`SHADERS`] (a programming error, caught by the tests).
pub fn source(name: &str) -> String {
    source_for(name, 1)
}

/// [`source`] for host targets of `samples` samples per pixel (1, or an
/// MSAA count): what the passes that load the host's depth or IDs compile.
pub fn source_for(name: &str, samples: u32) -> String {
    let body = SHADERS.iter().find(|(n, _)| *n == name).map(|(_, s)| *s).unwrap_or_else(|| panic!("no shader {name}"));
    format!("{}{COMMON_WGSL}\n{body}", prelude(samples))
}

/// The raster occlusion test's pipeline, shared by every box-testing
/// method: 36 vertices per box from `box_vs` (no vertex buffers), front
/// faces only (a box clear of the near plane is entered through them by
/// every ray that reaches what it bounds), depth test "nearer or equal"
/// (`LessEqual`, or `GreaterEqual` for reversed depth) with a small bias
/// toward the camera so a face lying on the surface it bounds passes, no
/// depth or colour writes, at the attachment's sample count (exact per
/// sample). `depth`: the attachment's format, convention and samples per
/// pixel. `fragment`: the entry point that records a
/// passing fragment (forced early-Z), or `None` for a depth-only pass
/// counted by occlusion queries. `constants`: override constants of both
/// stages (HROC's `TEST_SCALE`).
pub fn box_test_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment: Option<&str>,
    depth: (wgpu::TextureFormat, DepthRange, u32),
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    box_pipeline(gpu, label, layout, module, ("box_vs", fragment), depth, BoxDepth::Test, constants)
}

/// What a box pipeline does with depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxDepth {
    /// [`box_test_pipeline`]'s test: nearer or equal, biased toward the camera, no writes.
    Test,
    /// Writes the nearest box depth (`Less`, or `Greater` reversed), no bias.
    Write,
    /// No depth attachment: the fragment stage makes [`BoxDepth::Test`]'s
    /// comparison itself (HROC's `MANUAL_DEPTH`). A render pass needs an
    /// attachment, so the pass has one colour target of
    /// [`MANUAL_TARGET`] that nothing writes.
    Manual,
}

/// The format of the colour target a [`BoxDepth::Manual`] pass binds in
/// place of the depth attachment (never written).
pub const MANUAL_TARGET: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// What a box-test pass renders into: the depth it tests against, attached
/// read-only ([`BoxDepth::Test`]), or, where the culler runs without
/// early-Z marks, or its test samples the depth it would attach without
/// read-only depth attachments ([`crate::capabilities::Capabilities::read_only_depth`]),
/// a colour target of [`MANUAL_TARGET`] that nothing writes
/// ([`BoxDepth::Manual`]).
pub struct BoxTarget(Option<wgpu::TextureView>);

fn manual_target(gpu: &Gpu, size: (u32, u32), samples: u32) -> wgpu::TextureView {
    gpu.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("hroc box test target"),
            size: wgpu::Extent3d { width: size.0.max(1), height: size.1.max(1), depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: MANUAL_TARGET,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

impl BoxTarget {
    /// The target of box tests over `size` pixels of `samples` samples
    /// with `caps`, by whether they sample the depth they test against
    /// ([`crate::capabilities::Capabilities`]).
    pub fn new(gpu: &Gpu, caps: crate::capabilities::Capabilities, samples_depth: bool, (size, samples): ((u32, u32), u32)) -> BoxTarget {
        BoxTarget((!caps.attached_box_tests(&gpu.device, samples_depth)).then(|| manual_target(gpu, size, samples)))
    }

    /// How the pass's pipelines treat depth.
    pub fn mode(&self) -> BoxDepth {
        if self.0.is_some() {
            BoxDepth::Manual
        } else {
            BoxDepth::Test
        }
    }

    /// The value of the WGSL override `MANUAL_DEPTH`.
    pub fn manual_depth(&self) -> f64 {
        self.0.is_some() as u32 as f64
    }

    /// A colour target of [`MANUAL_TARGET`] of `size` pixels, one sample:
    /// box tests that load the depth they compare against, rasterized at
    /// a size of their own.
    pub fn manual(gpu: &Gpu, size: (u32, u32)) -> BoxTarget {
        BoxTarget(Some(manual_target(gpu, size, 1)))
    }

    /// Begins the box-test pass `label` against `depth`, attached with
    /// `depth_ops` (the pass's first draw writes what it tests against).
    pub fn begin_writing<'e>(&self, enc: &'e mut wgpu::CommandEncoder, label: &str, depth: wgpu::RenderPassDepthStencilAttachment<'_>) -> wgpu::RenderPass<'e> {
        debug_assert!(self.0.is_none(), "a pass that writes depth has it attached");
        enc.counted_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[],
            depth_stencil_attachment: Some(depth),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Begins the box-test pass `label` against `depth` (attached
    /// read-only, or left to the fragment stage to load).
    pub fn begin<'e>(&self, enc: &'e mut wgpu::CommandEncoder, label: &str, depth: &wgpu::TextureView) -> wgpu::RenderPass<'e> {
        let manual = self.0.as_ref().map(|view| wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Discard },
        });
        enc.counted_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: if manual.is_some() { std::slice::from_ref(&manual) } else { &[] },
            depth_stencil_attachment: match manual {
                Some(_) => None,
                None => Some(wgpu::RenderPassDepthStencilAttachment { view: depth, depth_ops: None, stencil_ops: None }),
            },
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// [`box_test_pipeline`] with other entry points (`stages`: vertex,
/// fragment) or, with [`BoxDepth::Write`], a pass that writes box depth.
#[allow(clippy::too_many_arguments)]
pub fn box_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    (vertex, fragment): (&str, Option<&str>),
    depth: (wgpu::TextureFormat, DepthRange, u32),
    mode: BoxDepth,
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    let options = || wgpu::PipelineCompilationOptions { constants, ..Default::default() };
    let (compare, bias) = match (depth.1, mode) {
        (DepthRange::Standard, BoxDepth::Test | BoxDepth::Manual) => (wgpu::CompareFunction::LessEqual, -16),
        (DepthRange::Reversed, BoxDepth::Test | BoxDepth::Manual) => (wgpu::CompareFunction::GreaterEqual, 16),
        (DepthRange::Standard, BoxDepth::Write) => (wgpu::CompareFunction::Less, 0),
        (DepthRange::Reversed, BoxDepth::Write) => (wgpu::CompareFunction::Greater, 0),
    };
    let manual = [Some(wgpu::ColorTargetState { format: MANUAL_TARGET, blend: None, write_mask: wgpu::ColorWrites::empty() })];
    let key = crate::gpu::RenderKey {
        label: label.to_owned(),
        layout: layout.clone(),
        module: module.clone(),
        entries: (vertex.to_owned(), fragment.map(str::to_owned)),
        constants: crate::gpu::constants_key(constants),
        depth: (mode != BoxDepth::Manual).then_some((depth.0, compare, bias, mode == BoxDepth::Write)),
        samples: depth.2,
        targets: if mode == BoxDepth::Manual { vec![MANUAL_TARGET] } else { Vec::new() },
    };
    gpu.cache.render(key, || {
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState { module, entry_point: Some(vertex), compilation_options: options(), buffers: &[] },
            primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), front_face: wgpu::FrontFace::Ccw, ..Default::default() },
            depth_stencil: (mode != BoxDepth::Manual).then(|| wgpu::DepthStencilState {
                format: depth.0,
                depth_write_enabled: Some(mode == BoxDepth::Write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState { constant: bias, slope_scale: 0.0, clamp: 0.0 },
            }),
            multisample: wgpu::MultisampleState { count: depth.2, ..Default::default() },
            fragment: fragment.map(|entry| wgpu::FragmentState {
                module,
                entry_point: Some(entry),
                compilation_options: options(),
                targets: if mode == BoxDepth::Manual { &manual } else { &[] },
            }),
            multiview_mask: None,
            cache: None,
        })
    })
}

/// Every (WGSL struct name, Rust size) pair the shader test checks.
pub fn mirrored_sizes() -> Vec<(&'static str, usize)> {
    use std::mem::size_of;
    vec![
        ("Frame", size_of::<crate::layout::FrameUniform>()),
        ("ObjectBounds", size_of::<crate::layout::ObjectBounds>()),
        ("OrientedBounds", size_of::<crate::layout::OrientedBounds>()),
        ("DrawCommand", size_of::<crate::layout::DrawCommand>()),
        ("DrawArgs", size_of::<crate::layout::DrawArgs>()),
        ("BvhNode", size_of::<crate::bvh::BvhNode>()),
        ("Params", size_of::<crate::layout::CompactParams>()),
    ]
}
