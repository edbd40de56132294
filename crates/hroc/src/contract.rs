//! The host contract's types: the device features, the marks snippet and
//! its layout, the phases, the draws handed to the host, and its targets.

use crate::capabilities::DrawCount;
use crate::error::{Error, Result};
use crate::frustum::DepthRange;
use crate::gpu::PassCount;
use std::future::Future;

/// The features [`CullerDesc::timestamps`](crate::CullerDesc::timestamps) needs.
pub const TIMESTAMP_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// The features [`CullerDesc::pipeline_statistics`](crate::CullerDesc::pipeline_statistics) needs.
pub const PIPELINE_STATISTICS_FEATURES: wgpu::Features = wgpu::Features::PIPELINE_STATISTICS_QUERY;

/// The layout of every [`Draw::marks`] bind group, from the device alone:
/// one `array<u32>` storage buffer at binding 0, fragment stage, as
/// [`marks_wgsl`] declares it. Put it in the host's pipeline layout at the
/// group [`marks_wgsl`] names; pipelines can so be built before the
/// [`Culler`](crate::Culler), and take the bind groups of every culler on the device
/// (wgpu treats layouts with the same entries as one).
pub fn marks_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("hroc marks"), entries: &[marks_entry()] })
}

pub(super) fn marks_entry() -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: false }, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

/// The WGSL the host's fragment shader includes to mark its object as
/// drawn, with the marks buffer at `@group(group) @binding(0)`:
///
/// ```wgsl
/// @group(G) @binding(0) var<storage, read_write> hroc_marks: array<u32>;
/// fn hroc_mark(object: u32) { hroc_marks[object] = 1u; }
/// ```
///
/// Call `hroc_mark(object)` from a fragment entry point declared
/// `@early_depth_test(force)` when [`Draw::mark`] is set (or always: an
/// unmarked [`Draw`] binds a sink). `object` is the draw's
/// `@builtin(instance_index)`, passed flat from the vertex stage.
pub fn marks_wgsl(group: u32) -> String {
    format!(
        "// hroc: marks an object as drawn (a fragment passed forced early-Z).\n\
         @group({group}) @binding(0) var<storage, read_write> hroc_marks: array<u32>;\n\
         fn hroc_mark(object: u32) {{\n    hroc_marks[object] = 1u;\n}}\n"
    )
}

/// Which part of a method's frame a [`Draw`] belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Phase {
    /// Objects the culler draws whatever the method decides
    /// ([`ObjectFlags::NEVER_CULL`](crate::ObjectFlags::NEVER_CULL)); first in every frame.
    Always,
    /// A method's single list (`noc`, `vfc`, `ref`, `woc`).
    Visible,
    /// The early pass: last frame's visible set, which builds the occlusion
    /// map the test reads (HROC §3.1, ROC, HZB).
    Occluders,
    /// The late pass: the objects that passed the occlusion test (HROC §3.4).
    Occludees,
    /// A list drawn between occlusion queries (`oq`, `soq`, `chc++`): each
    /// must be drawn before the culler's next pass.
    Interleaved,
    /// Objects flagged [`ObjectFlags::NOT_OCCLUDER`](crate::ObjectFlags::NOT_OCCLUDER) that passed, last in the
    /// frame, against the final depth: draw them with blending, depth test
    /// on and depth writes off, and without writing the ID target.
    NonOccluders,
}

impl Phase {
    /// True for the phases whose objects occlude: they must write depth (and
    /// the object-ID target, when the view has one).
    pub fn occludes(self) -> bool {
        self != Phase::NonOccluders
    }
}

/// One list for the host to draw, with its own pipelines, now, into the
/// view's depth attachment (and whatever colour targets it likes).
pub struct Draw<'a> {
    /// Which phase this is.
    pub phase: Phase,
    /// `DrawIndexedIndirectArgs` (20 bytes each), in object order (query
    /// methods: front-to-back traversal order), with
    /// `first_instance` the object index. Commands may have
    /// `instance_count` 0.
    pub commands: &'a wgpu::Buffer,
    /// One u32 at offset 0: commands to draw.
    pub count: &'a wgpu::Buffer,
    /// Upper bound for `multi_draw_indexed_indirect_count`.
    pub max_count: u32,
    /// How to draw up to the GPU's count: with [`DrawCount::Emulated`],
    /// `multi_draw_indexed_indirect(commands, 0, max_count)`, the commands
    /// past the count having `instance_count` 0.
    pub draw_count: DrawCount,
    /// Bind at the host's marks group ([`marks_wgsl`]).
    pub marks: &'a wgpu::BindGroup,
    /// True when the method reads the marks: the fragment shader must call
    /// `hroc_mark`. False: `marks` is a sink, and the host may skip marking
    /// (always false with [`crate::capabilities::Marks::Ids`], where the culler reads the
    /// ID target instead).
    pub mark: bool,
    /// True for a list of [`ObjectFlags::CUTOUT`](crate::ObjectFlags::CUTOUT)
    /// objects (handed right after the list of their phase they were taken
    /// from): draw it with the alpha-tested pipeline, without forced
    /// early-Z and without marking (`mark` is false).
    pub cutout: bool,
    /// The pipeline-statistics slot of this draw, if the view counts.
    pub(crate) statistics: PassCount,
    /// Where [`Draw::record`] checks the host's pipelines.
    pub(crate) pipelines: &'a PipelineCheck,
}

impl Draw<'_> {
    /// Records the draw with the host's `pipeline` into a render pass whose
    /// vertex and index buffers and other bind groups the host has set;
    /// binds the marks at `marks_group`. With validation
    /// ([`CullerDesc::validation`](crate::CullerDesc::validation)), where the draw is marked
    /// ([`Draw::mark`]), a pipeline whose layout has no marks group at
    /// `marks_group` ([`device::marks_layout`](crate::device::marks_layout))
    /// is refused: nothing is recorded, and [`View::cull`](crate::View::cull)
    /// fails with the reason (checked once per pipeline). With
    /// [`CullerDesc::pipeline_statistics`](crate::CullerDesc::pipeline_statistics), the draw
    /// is counted in its stage (a host that records the commands itself
    /// goes uncounted).
    pub fn record(&self, pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, marks_group: u32) {
        if self.mark && !self.pipelines.accepts(pipeline, marks_group, self.phase) {
            return;
        }
        pass.set_pipeline(pipeline);
        self.statistics.around(pass, |pass| {
            pass.set_bind_group(marks_group, self.marks, &[]);
            match self.draw_count {
                DrawCount::Indirect => pass.multi_draw_indexed_indirect_count(self.commands, 0, self.count, 0, self.max_count),
                DrawCount::Emulated => pass.multi_draw_indexed_indirect(self.commands, 0, self.max_count),
            }
        });
    }
}

/// The culler's check that a marked draw's pipeline has the marks group
/// ([`Draw::record`]): each pipeline and group once, under a validation
/// error scope.
pub(crate) struct PipelineCheck {
    /// The culler validates ([`crate::CullerDesc::validation`]): checks run.
    enabled: bool,
    device: wgpu::Device,
    /// A buffer a marks bind group can hold.
    sink: wgpu::Buffer,
    checked: std::sync::Mutex<std::collections::HashMap<(wgpu::RenderPipeline, u32), bool>>,
    /// The reason the last refused pipeline was refused, until the frame takes it.
    refused: std::sync::Mutex<Option<String>>,
}

impl PipelineCheck {
    pub(crate) fn new(device: &wgpu::Device, sink: &wgpu::Buffer, enabled: bool) -> PipelineCheck {
        PipelineCheck { enabled, device: device.clone(), sink: sink.clone(), checked: Default::default(), refused: Default::default() }
    }

    /// True when `pipeline`'s layout takes a marks bind group at `group`.
    fn accepts(&self, pipeline: &wgpu::RenderPipeline, group: u32, phase: Phase) -> bool {
        if !self.enabled {
            return true;
        }
        let mut checked = self.checked.lock().unwrap_or_else(|p| p.into_inner());
        let ok = *checked.entry((pipeline.clone(), group)).or_insert_with(|| {
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let layout = pipeline.get_bind_group_layout(group);
            let _ = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hroc marks layout check"),
                layout: &layout,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: self.sink.as_entire_binding() }],
            });
            // Native error scopes are ready when popped; a backend whose
            // scope is not yet could not be checked, and is accepted.
            let mut popped = std::pin::pin!(scope.pop());
            let mut cx = std::task::Context::from_waker(std::task::Waker::noop());
            !matches!(popped.as_mut().poll(&mut cx), std::task::Poll::Ready(Some(_)))
        });
        if !ok {
            *self.refused.lock().unwrap_or_else(|p| p.into_inner()) = Some(format!(
                "the host's pipeline for the {phase:?} phase has no marks group at group {group} (Draw::record's marks_group), and the culler reads this phase's marks: put hroc::device::marks_layout(device) at that group of its layout, and call hroc_mark from its fragment shader (hroc::device::marks_wgsl)"
            ));
        }
        ok
    }

    /// The reason a pipeline was refused since the last call, if one was.
    pub(crate) fn take_refusal(&self) -> Option<String> {
        self.refused.lock().unwrap_or_else(|p| p.into_inner()).take()
    }
}

/// The host's side of a frame: draws the lists the culler hands it.
pub trait DrawHost {
    /// Draws `draw` into `encoder` with the host's pipelines. Called in
    /// phase order; each call must be recorded before returning.
    fn draw(&mut self, encoder: &mut wgpu::CommandEncoder, draw: &Draw<'_>);
}

impl<F: FnMut(&mut wgpu::CommandEncoder, &Draw<'_>)> DrawHost for F {
    fn draw(&mut self, encoder: &mut wgpu::CommandEncoder, draw: &Draw<'_>) {
        self(encoder, draw)
    }
}

/// The host's render targets of one view.
#[derive(Clone, Copy, Debug)]
pub struct ViewTargets<'a> {
    /// The depth texture the host draws into: usage `RENDER_ATTACHMENT |
    /// TEXTURE_BINDING`, a depth format, one sample or several (MSAA; an
    /// MSAA array needs `Features::MULTISAMPLE_ARRAY`; wgpu's GL backend
    /// samples neither, nor a layer other than 0). The view uses one
    /// layer and one mip of it ([`ViewTargets::layer`], [`ViewTargets::mip`]).
    pub depth: &'a wgpu::Texture,
    /// Which end of `depth` is near.
    pub depth_range: DepthRange,
    /// The object-ID target: usage `TEXTURE_BINDING`, the size of the depth
    /// mip the view uses and the depth's sample count; the host writes
    /// `object index + 1` for every occluding fragment and clears it to 0
    /// each frame. `R32Uint` holds the index + 1 whole; `Rg16Uint`, which
    /// wgpu can multisample on every backend (`R32Uint` only where the
    /// adapter allows it), its low 16 bits in r and its high 16 in g.
    /// Needed by HROC with OF, and with [`crate::capabilities::Marks::Ids`] by every
    /// method that reads marks. The culler reads its layer 0, mip 0, every
    /// sample.
    pub ids: Option<&'a wgpu::Texture>,
    /// The array layer (or cube face) of `depth` the view draws into.
    pub layer: u32,
    /// The mip level of `depth` the view draws into; the view's size is
    /// that mip's.
    pub mip: u32,
}

impl<'a> ViewTargets<'a> {
    /// Layer 0, mip 0 of `depth`, without an ID target.
    pub fn new(depth: &'a wgpu::Texture, depth_range: DepthRange) -> ViewTargets<'a> {
        ViewTargets { depth, depth_range, ids: None, layer: 0, mip: 0 }
    }

    /// These targets with the object-ID target `ids`.
    pub fn with_ids(self, ids: &'a wgpu::Texture) -> ViewTargets<'a> {
        ViewTargets { ids: Some(ids), ..self }
    }

    /// These targets on `layer` and `mip` of the depth texture.
    pub fn at(self, layer: u32, mip: u32) -> ViewTargets<'a> {
        ViewTargets { layer, mip, ..self }
    }
}

/// A view's targets as the methods bind them.
pub struct Targets {
    /// The depth attachment, for the culler's own box passes.
    pub depth_attachment: wgpu::TextureView,
    /// The depth aspect, for sampling in compute and fragment passes.
    pub depth_sampled: wgpu::TextureView,
    /// The depth attachment's format.
    pub depth_format: wgpu::TextureFormat,
    /// Samples per pixel of the depth (and ID) target.
    pub samples: u32,
    /// Which end of the depth range is near.
    pub depth: DepthRange,
    /// The object-ID target, when the host has one.
    pub ids: Option<wgpu::TextureView>,
    /// Width and height of the depth mip the view uses.
    pub size: (u32, u32),
    pub(super) depth_id: wgpu::Texture,
    pub(super) ids_id: Option<wgpu::Texture>,
    pub(crate) layer: u32,
    pub(crate) mip: u32,
}

impl Targets {
    /// The targets `t` describes, on a device of `backend`. (A multisampled
    /// array needs `Features::MULTISAMPLE_ARRAY`: wgpu refuses to create
    /// one without it.)
    pub(super) fn new(t: &ViewTargets, backend: wgpu::Backend) -> Result<Targets> {
        use wgpu::TextureUsages as U;
        let d = t.depth;
        let bad = |m: String| Err(Error::InvalidTargets(m));
        if !d.format().is_depth_stencil_format() || !d.format().has_depth_aspect() {
            return bad(format!("depth target format {:?} has no depth aspect", d.format()));
        }
        if !d.usage().contains(U::RENDER_ATTACHMENT | U::TEXTURE_BINDING) {
            return bad(format!("depth target usage {:?} lacks RENDER_ATTACHMENT | TEXTURE_BINDING (the culler samples it)", d.usage()));
        }
        if d.dimension() != wgpu::TextureDimension::D2 {
            return bad(format!("depth target is {:?}; views draw into 2D textures (a layer of an array or cube)", d.dimension()));
        }
        let samples = d.sample_count();
        if backend == wgpu::Backend::Gl && samples > 1 {
            return bad(format!(
                "depth target has {samples} samples: wgpu's GL backend cannot sample multisampled textures (it allocates them as TEXTURE_2D; gfx-rs/wgpu#6084), so no method can load it there"
            ));
        }
        if backend == wgpu::Backend::Gl && t.layer > 0 {
            return bad(format!(
                "layer {} of the depth target: wgpu's GL backend samples only layer 0 of an array (its views cannot start at another layer); draw this view into a texture of its own",
                t.layer
            ));
        }
        if t.layer >= d.depth_or_array_layers() || t.mip >= d.mip_level_count() {
            return bad(format!("layer {} mip {} is outside the depth target ({} layers, {} mips)", t.layer, t.mip, d.depth_or_array_layers(), d.mip_level_count()));
        }
        let mip = d.size().mip_level_size(t.mip, d.dimension());
        let size = (mip.width, mip.height);
        if let Some(ids) = t.ids {
            let format = matches!(ids.format(), wgpu::TextureFormat::R32Uint | wgpu::TextureFormat::Rg16Uint);
            if !format || !ids.usage().contains(U::TEXTURE_BINDING) || (ids.width(), ids.height()) != size || ids.sample_count() != samples {
                return bad(format!(
                    "ID target must be R32Uint or Rg16Uint with TEXTURE_BINDING, the depth target's size {}x{} and its {samples} sample(s) (got {:?}, {:?}, {}x{}, {} sample(s))",
                    size.0,
                    size.1,
                    ids.format(),
                    ids.usage(),
                    ids.width(),
                    ids.height(),
                    ids.sample_count()
                ));
            }
        }
        Ok(Targets {
            depth_attachment: d.create_view(&subresource(wgpu::TextureAspect::All, t.layer, t.mip)),
            depth_sampled: d.create_view(&subresource(wgpu::TextureAspect::DepthOnly, t.layer, t.mip)),
            depth_format: d.format(),
            samples,
            depth: t.depth_range,
            ids: t.ids.map(|i| i.create_view(&subresource(wgpu::TextureAspect::All, 0, 0))),
            size,
            depth_id: d.clone(),
            ids_id: t.ids.cloned(),
            layer: t.layer,
            mip: t.mip,
        })
    }

    /// The host's targets these were made from.
    pub(super) fn desc(&self) -> ViewTargets<'_> {
        ViewTargets { depth: &self.depth_id, depth_range: self.depth, ids: self.ids_id.as_ref(), layer: self.layer, mip: self.mip }
    }
}

/// A 2D view of one layer and one mip (a depth array, a cube or a mipped
/// target works).
pub(super) fn subresource(aspect: wgpu::TextureAspect, layer: u32, mip: u32) -> wgpu::TextureViewDescriptor<'static> {
    wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect,
        base_mip_level: mip,
        mip_level_count: Some(1),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    }
}

/// A packed list of draw commands and the GPU count the draw reads.
/// `max_count` bounds the count (N, or a read-back count with CR).
#[derive(Clone, Debug)]
pub struct DrawList {
    /// [`crate::layout::DrawCommand`]s, object order kept.
    pub commands: wgpu::Buffer,
    /// One u32: how many commands to draw.
    pub count: wgpu::Buffer,
    /// Upper bound on the count.
    pub max_count: u32,
}
