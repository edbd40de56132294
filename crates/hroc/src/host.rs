//! The host contract: what a renderer hands the culler, what it gets back.
//! The crate docs state the preconditions once; this module implements them.

use crate::bvh::{Bvh, Split};
use crate::cull::{compact::Compactor, CullMethod, DrawList, Frame, FrameBody, Method, MethodContext, MethodOptions, Stage, Stat};
use crate::error::{Error, Result};
use crate::frustum::{DepthRange, ViewDesc};
use crate::gpu::{dispatch_size, Gpu, GpuTimer};
use crate::layout::{DrawCommand, FrameUniform, ObjectBounds};
use crate::{shaders, Aabb};

/// Per-object flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ObjectFlags(u32);

impl ObjectFlags {
    /// An ordinary object: culled, and an occluder when drawn.
    pub const NONE: ObjectFlags = ObjectFlags(0);
    /// Drawn every frame whatever the method decides (a skybox, a
    /// first-person weapon). Its box must still be finite.
    pub const NEVER_CULL: ObjectFlags = ObjectFlags(1);
    /// Culled, but never in the occlusion map: the object does not write
    /// depth or the ID target (alpha-blended glass, particles). Such objects
    /// are handed back in [`Phase::NonOccluders`], after the opaque phases.
    pub const NOT_OCCLUDER: ObjectFlags = ObjectFlags(2);

    /// The raw bits (`ObjectBounds::flags`, WGSL `NEVER_CULL`/`NOT_OCCLUDER`).
    pub fn bits(self) -> u32 {
        self.0
    }
    /// True when every flag of `other` is set.
    pub fn contains(self, other: ObjectFlags) -> bool {
        self.0 & other.0 == other.0
    }
}

impl std::ops::BitOr for ObjectFlags {
    type Output = ObjectFlags;
    fn bitor(self, o: ObjectFlags) -> ObjectFlags {
        ObjectFlags(self.0 | o.0)
    }
}

/// One object the host draws: its world box and its own indexed draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectDesc {
    /// World-space bounds of everything the draw can rasterize.
    pub bounds: Aabb,
    /// Indices to draw from the host's index buffer.
    pub index_count: u32,
    /// First index.
    pub first_index: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// Flags.
    pub flags: ObjectFlags,
}

/// What a culler needs of its objects before the first frame.
#[derive(Clone, Debug)]
pub struct CullerDesc<'a> {
    /// The objects, indexed 0..N in this order: the object index of every
    /// draw command the culler hands back.
    pub objects: &'a [ObjectDesc],
    /// BVH split strategy (HROC, IOC and the query methods walk the BVH).
    pub split: Split,
    /// Method parameters.
    pub options: MethodOptions,
    /// Time every stage with GPU timestamps. Needs `TIMESTAMP_QUERY` and
    /// `TIMESTAMP_QUERY_INSIDE_ENCODERS`.
    pub timestamps: bool,
}

impl<'a> CullerDesc<'a> {
    /// SAH BVH, default parameters, no timestamps.
    pub fn new(objects: &'a [ObjectDesc]) -> Self {
        CullerDesc { objects, split: Split::Sah, options: MethodOptions::default(), timestamps: false }
    }
}

/// The device features every method needs.
pub const REQUIRED_FEATURES: wgpu::Features =
    wgpu::Features::MULTI_DRAW_INDIRECT_COUNT.union(wgpu::Features::INDIRECT_FIRST_INSTANCE).union(wgpu::Features::SHADER_EARLY_DEPTH_TEST);

/// The features [`CullerDesc::timestamps`] needs.
pub const TIMESTAMP_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// Object buffers shared by every view of a [`Culler`].
pub(crate) struct SharedObjects {
    pub count: u32,
    pub bounds: wgpu::Buffer,
    pub commands: wgpu::Buffer,
    pub all_count: wgpu::Buffer,
    pub flags: Vec<ObjectFlags>,
    pub cpu_commands: Vec<DrawCommand>,
    /// NEVER_CULL objects that occlude, drawn first every frame.
    pub always: Option<DrawList>,
    /// 1 for NEVER_CULL + NOT_OCCLUDER objects: where each frame's list of
    /// non-occluders starts.
    pub always_deferred: wgpu::Buffer,
}

impl SharedObjects {
    pub fn all(&self) -> DrawList {
        DrawList { commands: self.commands.clone(), count: self.all_count.clone(), max_count: self.count }
    }
}

/// The objects, their BVH and their GPU buffers, on the host's device;
/// shared by every [`View`] of them.
pub struct Culler {
    gpu: Gpu,
    boxes: Vec<Aabb>,
    /// Bumped by every [`Culler::set_bounds`].
    moves: u64,
    bvh: Bvh,
    bvh_nodes: wgpu::Buffer,
    leaf_of_object: wgpu::Buffer,
    objects: SharedObjects,
    marks_layout: wgpu::BindGroupLayout,
    options: MethodOptions,
    timestamps: bool,
}

impl Culler {
    /// Creates a culler on the host's device. Errors, never panics, when the
    /// device lacks [`REQUIRED_FEATURES`] (or [`TIMESTAMP_FEATURES`] when
    /// asked for timestamps), when an object's box is not finite, or when the
    /// objects exceed the device's buffer limits.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, desc: &CullerDesc) -> Result<Culler> {
        let mut needed = REQUIRED_FEATURES;
        if desc.timestamps {
            needed |= TIMESTAMP_FEATURES;
        }
        let missing = needed - device.features();
        if !missing.is_empty() {
            return Err(Error::MissingFeatures { what: "hroc::Culler".into(), missing });
        }
        let gpu = Gpu::from_device(device, queue);
        let objects = desc.objects;
        let n = objects.len() as u64;
        for (i, o) in objects.iter().enumerate() {
            check_box(i as u32, &o.bounds)?;
        }
        let limits = device.limits();
        let storage = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        for (what, need) in [("object boxes", n * 32), ("draw commands", n * 20), ("BVH nodes", (2 * n).saturating_sub(1) * 32)] {
            if need > storage {
                return Err(Error::OverDeviceLimits(format!("{what} need {need} bytes, the device allows {storage}")));
            }
        }
        if n >= 1 << 31 {
            return Err(Error::OverDeviceLimits(format!("{n} objects exceed 2^31")));
        }
        let boxes: Vec<Aabb> = objects.iter().map(|o| o.bounds).collect();
        let bvh = Bvh::build(&boxes, desc.split);
        use wgpu::BufferUsages as U;
        let bounds: Vec<ObjectBounds> = objects.iter().map(|o| bounds_of(o.bounds, o.flags)).collect();
        let commands: Vec<DrawCommand> = objects.iter().enumerate().map(|(i, o)| command(o, i as u32)).collect();
        let marks_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("hroc marks"), entries: &[marks_entry()] });
        let shared = SharedObjects {
            count: n as u32,
            bounds: gpu.buffer_init("hroc object boxes", bytemuck::cast_slice(&bounds), U::STORAGE | U::COPY_DST),
            commands: gpu.buffer_init("hroc commands", bytemuck::cast_slice(&commands), U::STORAGE | U::INDIRECT | U::COPY_SRC | U::COPY_DST),
            all_count: gpu.buffer_init("hroc all count", bytemuck::bytes_of(&(n as u32)), U::STORAGE | U::INDIRECT | U::COPY_SRC),
            flags: objects.iter().map(|o| o.flags).collect(),
            cpu_commands: commands.clone(),
            always: None,
            always_deferred: gpu.buffer("hroc never-culled non-occluders", n * 4, U::STORAGE | U::COPY_SRC | U::COPY_DST),
        };
        let mut culler = Culler {
            bvh_nodes: gpu.buffer_init("hroc bvh nodes", bytemuck::cast_slice(&bvh.nodes), U::STORAGE | U::COPY_DST),
            leaf_of_object: gpu.buffer_init("hroc leaf of object", bytemuck::cast_slice(&bvh.leaf_of_object), U::STORAGE),
            bvh,
            gpu,
            boxes,
            moves: 0,
            objects: shared,
            marks_layout,
            options: desc.options.clone(),
            timestamps: desc.timestamps,
        };
        culler.update_always();
        Ok(culler)
    }

    /// Moves objects: `(object, new world box)` pairs, taking effect from
    /// the next frame of every view. The BVH is refit on the CPU
    /// ([`Bvh::refit`]) and the boxes and nodes are uploaded. Errors on an
    /// object out of range or a box that is not finite; nothing changes then.
    /// Views of methods that cannot follow motion ([`Method::takes_motion`])
    /// refuse their next frame.
    pub fn set_bounds(&mut self, moves: &[(u32, Aabb)]) -> Result<()> {
        for &(i, b) in moves {
            self.check_object(i)?;
            check_box(i, &b)?;
        }
        if moves.is_empty() {
            return Ok(());
        }
        for &(i, b) in moves {
            self.boxes[i as usize] = b;
        }
        self.bvh.refit(&self.boxes);
        let bounds: Vec<ObjectBounds> = self.boxes.iter().zip(&self.objects.flags).map(|(b, f)| bounds_of(*b, *f)).collect();
        self.gpu.queue.write_buffer(&self.objects.bounds, 0, bytemuck::cast_slice(&bounds));
        self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        self.moves += 1;
        Ok(())
    }

    /// Registered objects.
    pub fn object_count(&self) -> u32 {
        self.objects.count
    }

    /// The object BVH.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Every object's draw command in object order (what `noc` draws).
    pub fn commands(&self) -> &wgpu::Buffer {
        &self.objects.commands
    }

    /// Layout of the marks bind group of every [`Draw`]: one
    /// `array<u32>` storage buffer at binding 0, fragment stage. Put it in
    /// the host's pipeline layout at the group [`marks_wgsl`] names.
    pub fn marks_layout(&self) -> &wgpu::BindGroupLayout {
        &self.marks_layout
    }

    /// The flags of object `i`; `None` out of range.
    pub fn flags(&self, i: u32) -> Option<ObjectFlags> {
        self.objects.flags.get(i as usize).copied()
    }

    fn check_object(&self, i: u32) -> Result<()> {
        match i < self.objects.count {
            true => Ok(()),
            false => Err(Error::InvalidObject(format!("object {i} out of range 0..{}", self.objects.count))),
        }
    }

    /// Sets the flags of object `i` (an object that turns transparent, a
    /// skybox): takes effect from the next frame of every view.
    pub fn set_flags(&mut self, i: u32, flags: ObjectFlags) -> Result<()> {
        self.check_object(i)?;
        self.objects.flags[i as usize] = flags;
        self.gpu.queue.write_buffer(&self.objects.bounds, i as u64 * 32 + 12, bytemuck::bytes_of(&flags.bits()));
        self.update_always();
        Ok(())
    }

    /// Rebuilds the never-culled list and the never-culled non-occluders.
    fn update_always(&mut self) {
        let o = &mut self.objects;
        let never = |f: &ObjectFlags| f.contains(ObjectFlags::NEVER_CULL);
        let list: Vec<DrawCommand> = o.flags.iter().zip(&o.cpu_commands).filter(|(f, _)| never(f) && !f.contains(ObjectFlags::NOT_OCCLUDER)).map(|(_, c)| *c).collect();
        let deferred: Vec<u32> = o.flags.iter().map(|f| (never(f) && f.contains(ObjectFlags::NOT_OCCLUDER)) as u32).collect();
        if !deferred.is_empty() {
            self.gpu.queue.write_buffer(&o.always_deferred, 0, bytemuck::cast_slice(&deferred));
        }
        o.always = (!list.is_empty()).then(|| {
            use wgpu::BufferUsages as U;
            DrawList {
                commands: self.gpu.buffer_init("hroc never-culled", bytemuck::cast_slice(&list), U::STORAGE | U::INDIRECT | U::COPY_SRC),
                count: self.gpu.buffer_init("hroc never-culled count", bytemuck::bytes_of(&(list.len() as u32)), U::STORAGE | U::INDIRECT | U::COPY_SRC),
                max_count: list.len() as u32,
            }
        });
    }

    /// A view of the objects culled by `method`, drawing into `targets`.
    /// Each view keeps its own temporal state (last frame's visible set).
    /// Errors when the method needs what the targets lack (an ID target for
    /// HROC's occluder filtering), or when a target has the wrong usage or
    /// format. A `ref` view (benchmark only) draws nothing until it is handed
    /// `noc`'s visible set with [`View::set_oracle`] before each frame.
    pub fn view(&self, method: Method, targets: &ViewTargets) -> Result<View> {
        self.view_with(method, targets, &self.options)
    }

    /// [`Culler::view`] with method parameters other than the culler's.
    pub fn view_with(&self, method: Method, targets: &ViewTargets, options: &MethodOptions) -> Result<View> {
        let t = Targets::new(targets)?;
        if method.needs_ids() && t.ids.is_none() {
            return Err(Error::InvalidTargets(format!("{method} filters occluders by the object-ID target (OF, HROC §4.2): pass ViewTargets::ids, or use hroc-cr / hroc-na")));
        }
        if t.depth == DepthRange::Reversed && !method.supports_reversed_depth() {
            return Err(Error::InvalidTargets(format!("{method} supports standard depth only")));
        }
        use wgpu::BufferUsages as U;
        let frame = self.gpu.buffer("hroc frame", std::mem::size_of::<FrameUniform>() as u64, U::UNIFORM | U::COPY_DST);
        let sink_buf = self.gpu.buffer("hroc marks sink", self.objects.count as u64 * 4, U::STORAGE);
        let sink = self.gpu.bind_buffers(&self.marks_layout, &[&sink_buf]);
        let mut cx = self.context(&frame, &t);
        cx.options = options;
        let imp = method.create(&cx)?;
        let timer = self.timestamps.then(|| GpuTimer::new(&self.gpu, 64));
        Ok(View { method, options: options.clone(), imp, frame, targets: t, sink, split: None, timer, last_stages: Vec::new() })
    }

    fn context<'a>(&'a self, frame: &'a wgpu::Buffer, targets: &'a Targets) -> MethodContext<'a> {
        MethodContext {
            gpu: &self.gpu,
            bvh: &self.bvh,
            bvh_nodes: &self.bvh_nodes,
            leaf_of_object: &self.leaf_of_object,
            bounds: &self.objects.bounds,
            commands: &self.objects.commands,
            object_count: self.objects.count,
            frame,
            targets,
            marks_layout: &self.marks_layout,
            options: &self.options,
        }
    }

    /// The device wrapper the culler records with.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }
}

/// An object's box must be finite and non-empty: every test and ray against
/// it assumes so.
fn check_box(i: u32, b: &Aabb) -> Result<()> {
    if !b.min.is_finite() || !b.max.is_finite() || b.is_empty() {
        return Err(Error::InvalidObject(format!("object {i}: bounds {b:?} are not a finite non-empty box")));
    }
    Ok(())
}

fn bounds_of(b: Aabb, flags: ObjectFlags) -> ObjectBounds {
    ObjectBounds { min: b.min.to_array(), flags: flags.bits(), max: b.max.to_array(), _pad: 0 }
}

fn command(o: &ObjectDesc, i: u32) -> DrawCommand {
    DrawCommand { index_count: o.index_count, instance_count: 1, first_index: o.first_index, base_vertex: o.base_vertex, first_instance: i }
}

fn marks_entry() -> wgpu::BindGroupLayoutEntry {
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
    /// ([`ObjectFlags::NEVER_CULL`]); first in every frame.
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
    /// Objects flagged [`ObjectFlags::NOT_OCCLUDER`] that passed, last in the
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
    /// Bind at the host's marks group ([`marks_wgsl`]).
    pub marks: &'a wgpu::BindGroup,
    /// True when the method reads the marks: the fragment shader must call
    /// `hroc_mark`. False: `marks` is a sink, and the host may skip marking.
    pub mark: bool,
}

impl Draw<'_> {
    /// Records the draw into a render pass whose pipeline, vertex and index
    /// buffers and other bind groups the host has set; binds the marks at
    /// `marks_group`.
    pub fn record(&self, pass: &mut wgpu::RenderPass<'_>, marks_group: u32) {
        pass.set_bind_group(marks_group, self.marks, &[]);
        pass.multi_draw_indexed_indirect_count(self.commands, 0, self.count, 0, self.max_count);
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
    /// The depth attachment the host draws into: usage `RENDER_ATTACHMENT |
    /// TEXTURE_BINDING`, one sample, a depth format.
    pub depth: &'a wgpu::Texture,
    /// Which end of `depth` is near.
    pub depth_range: DepthRange,
    /// The object-ID target: `R32Uint`, usage `TEXTURE_BINDING`, same size;
    /// the host writes `object index + 1` for every occluding fragment and
    /// clears it to 0 each frame. Needed by HROC with OF.
    pub ids: Option<&'a wgpu::Texture>,
}

/// A view's targets as the methods bind them.
pub struct Targets {
    /// The depth attachment, for the culler's own box passes.
    pub depth_attachment: wgpu::TextureView,
    /// The depth aspect, for sampling in compute and fragment passes.
    pub depth_sampled: wgpu::TextureView,
    /// The depth attachment's format.
    pub depth_format: wgpu::TextureFormat,
    /// Which end of the depth range is near.
    pub depth: DepthRange,
    /// The object-ID target, when the host has one.
    pub ids: Option<wgpu::TextureView>,
    /// Width and height.
    pub size: (u32, u32),
    depth_id: wgpu::Texture,
    ids_id: Option<wgpu::Texture>,
}

impl Targets {
    fn new(t: &ViewTargets) -> Result<Targets> {
        use wgpu::TextureUsages as U;
        let d = t.depth;
        let bad = |m: String| Err(Error::InvalidTargets(m));
        if !d.format().is_depth_stencil_format() || !d.format().has_depth_aspect() {
            return bad(format!("depth target format {:?} has no depth aspect", d.format()));
        }
        if !d.usage().contains(U::RENDER_ATTACHMENT | U::TEXTURE_BINDING) {
            return bad(format!("depth target usage {:?} lacks RENDER_ATTACHMENT | TEXTURE_BINDING (the culler samples it)", d.usage()));
        }
        if d.sample_count() != 1 || d.dimension() != wgpu::TextureDimension::D2 {
            return bad("depth target must be 2D with one sample (resolve MSAA depth first)".into());
        }
        // Layer 0, mip 0 is what the culler reads and draws against.
        let size = (d.width(), d.height());
        if let Some(ids) = t.ids {
            if ids.format() != wgpu::TextureFormat::R32Uint || !ids.usage().contains(U::TEXTURE_BINDING) || (ids.width(), ids.height()) != size {
                return bad(format!(
                    "ID target must be R32Uint with TEXTURE_BINDING and the depth target's size {}x{} (got {:?}, {:?}, {}x{})",
                    size.0,
                    size.1,
                    ids.format(),
                    ids.usage(),
                    ids.width(),
                    ids.height()
                ));
            }
        }
        Ok(Targets {
            depth_attachment: d.create_view(&one_layer(wgpu::TextureAspect::All)),
            depth_sampled: d.create_view(&one_layer(wgpu::TextureAspect::DepthOnly)),
            depth_format: d.format(),
            depth: t.depth_range,
            ids: t.ids.map(|i| i.create_view(&one_layer(wgpu::TextureAspect::All))),
            size,
            depth_id: d.clone(),
            ids_id: t.ids.cloned(),
        })
    }

    fn same(&self, t: &ViewTargets) -> bool {
        self.depth_id == *t.depth && self.ids_id.as_ref() == t.ids && self.depth == t.depth_range
    }
}

/// A 2D view of layer 0, mip 0 (a depth array or a mipped target works).
fn one_layer(aspect: wgpu::TextureAspect) -> wgpu::TextureViewDescriptor<'static> {
    wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect,
        base_mip_level: 0,
        mip_level_count: Some(1),
        base_array_layer: 0,
        array_layer_count: Some(1),
        ..Default::default()
    }
}

/// What the host hands in per frame of a view.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    /// The view and projection of this frame.
    pub view: ViewDesc,
    /// The targets the host draws this frame into. When they differ from the
    /// last frame's (a resize), the view is rebuilt and starts over as after
    /// a camera cut: keep one depth texture per view.
    pub targets: ViewTargets<'a>,
    /// A camera cut: last frame's visibility says nothing about this one.
    pub cut: bool,
    /// Seconds on the host's clock (`soq` expires statistics with it).
    pub time: f32,
}

/// One view of a [`Culler`]'s objects: a method and its temporal state.
pub struct View {
    method: Method,
    options: MethodOptions,
    imp: Box<dyn CullMethod>,
    frame: wgpu::Buffer,
    targets: Targets,
    sink: wgpu::BindGroup,
    split: Option<FlagSplit>,
    timer: Option<GpuTimer>,
    last_stages: Vec<(Stage, f64)>,
}

impl View {
    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// Culls one frame: writes the view's uniform, records the method's
    /// passes into `encoder` and hands `host` every list to draw, in phase
    /// order. The host has cleared its targets before; it submits
    /// `encoder` after. Methods with counter read-back (`hroc`, `hroc-cr`,
    /// `ioc`, the query methods) submit `encoder` mid-frame and continue in
    /// a new one, which this call leaves in `*encoder`.
    pub fn cull(&mut self, culler: &Culler, encoder: &mut wgpu::CommandEncoder, input: &FrameInput, host: &mut dyn DrawHost) -> Result<()> {
        self.record(culler, encoder, input, host, None)
    }

    /// [`View::cull`] with `body` recorded in place of the method's frame:
    /// for tests of a method's building blocks (`cull::queries::QueryRenderer`).
    #[doc(hidden)]
    pub fn cull_with(&mut self, culler: &Culler, encoder: &mut wgpu::CommandEncoder, input: &FrameInput, host: &mut dyn DrawHost, body: FrameBody) -> Result<()> {
        self.record(culler, encoder, input, host, Some(body))
    }

    /// What this view's methods are built from (with [`View::cull_with`]).
    #[doc(hidden)]
    pub fn method_context<'a>(&'a self, culler: &'a Culler) -> MethodContext<'a> {
        let mut cx = culler.context(&self.frame, &self.targets);
        cx.options = &self.options;
        cx
    }

    fn record(&mut self, culler: &Culler, encoder: &mut wgpu::CommandEncoder, input: &FrameInput, host: &mut dyn DrawHost, body: Option<FrameBody>) -> Result<()> {
        if !self.targets.same(&input.targets) {
            let fresh = culler.view_with(self.method, &input.targets, &self.options)?;
            *self = fresh;
        }
        if culler.moves > 0 && !self.method.takes_motion() {
            return Err(Error::InvalidScene(format!("{} keeps its own copy of the BVH and takes static scenes only; objects have moved", self.method)));
        }
        if input.view.depth != self.targets.depth {
            return Err(Error::InvalidView(format!("view depth {:?} differs from the targets' {:?}", input.view.depth, self.targets.depth)));
        }
        let g = input.view.geometry()?;
        let uniform = g.uniform(self.targets.size, culler.objects.count, culler.bvh.nodes.len() as u32, self.targets.depth);
        culler.gpu.queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&uniform));
        if input.cut {
            self.imp.reset(encoder);
        }
        if let Some(t) = self.timer.as_mut() {
            t.begin_frame();
        }
        // Flags cost nothing until some object has one.
        if self.split.is_none() && culler.objects.flags.iter().any(|f| *f != ObjectFlags::NONE) {
            self.split = Some(FlagSplit::new(&culler.gpu, &culler.objects));
        }
        if let Some(s) = self.split.as_mut() {
            s.begin(encoder, &culler.objects);
        }
        let mut f = Frame {
            gpu: &culler.gpu,
            geometry: g,
            uniform,
            time: input.time,
            objects: &culler.objects,
            targets: &self.targets,
            encoder,
            host,
            timer: self.timer.as_mut(),
            split: self.split.as_mut(),
            sink: &self.sink,
        };
        if let Some(always) = culler.objects.always.as_ref() {
            f.stage(Stage::FlaggedObjects);
            let d = Draw { phase: Phase::Always, commands: &always.commands, count: &always.count, max_count: always.max_count, marks: f.sink, mark: false };
            f.host.draw(f.encoder, &d);
        }
        match body {
            Some(body) => body(&mut f)?,
            None => self.imp.frame(&mut f)?,
        }
        if let Some(s) = f.split.take() {
            f.stage(Stage::FlaggedObjects);
            let list = s.finish(f.encoder);
            let d = Draw { phase: Phase::NonOccluders, commands: &list.commands, count: &list.count, max_count: list.max_count, marks: f.sink, mark: false };
            f.host.draw(f.encoder, &d);
        }
        if let Some(t) = f.timer.take() {
            t.end(f.encoder);
        }
        Ok(())
    }

    /// Per-stage GPU ms of the last frame, in stage order; empty without
    /// timestamps. Reads back: call after the frame's work was submitted.
    pub fn stage_ms(&mut self, culler: &Culler) -> Result<&[(Stage, f64)]> {
        self.last_stages = match self.timer.as_ref() {
            Some(t) => t.read(&culler.gpu)?,
            None => Vec::new(),
        };
        Ok(&self.last_stages)
    }

    /// The method's statistics of the last frame (set sizes, rays, ...).
    /// Reads back: call after the frame's work was submitted.
    pub fn stats(&mut self, culler: &Culler) -> Result<Vec<(Stat, f64)>> {
        self.imp.stats(&culler.gpu)
    }

    /// BVH nodes whose boxes the method tested last frame, if it tests boxes.
    pub fn tested_nodes(&self, culler: &Culler) -> Result<Option<Vec<u32>>> {
        self.imp.tested_nodes(&culler.gpu)
    }

    /// `ref` only (benchmark): the objects visible in `noc`'s ID target this frame.
    pub fn set_oracle(&mut self, culler: &Culler, visible: &[u32]) -> Result<()> {
        self.imp.set_oracle(&culler.gpu, visible)
    }

    /// The method's own state, for its debug read-backs (e.g.
    /// `view.method_state::<hroc::cull::hroc::Hroc>()`).
    pub fn method_state<T: 'static>(&self) -> Option<&T> {
        (&*self.imp as &dyn std::any::Any).downcast_ref::<T>()
    }

    /// True for `ref`, which needs [`View::set_oracle`] before each frame.
    pub fn wants_oracle(&self) -> bool {
        self.method.is_benchmark_only()
    }

    /// [`View::method_state`], mutable (debug switches of a method).
    pub fn method_state_mut<T: 'static>(&mut self) -> Option<&mut T> {
        (&mut *self.imp as &mut dyn std::any::Any).downcast_mut::<T>()
    }
}

/// Splits every list a method hands the host by object flags: commands of
/// flagged objects are emptied (instance_count 0, order kept); the
/// NOT_OCCLUDER ones are collected and handed back together at the end of
/// the frame. Only built when some object has a flag, so scenes without
/// flags pay nothing.
pub(crate) struct FlagSplit {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    deferred: wgpu::Buffer,
    /// Per list split this frame: its output commands and its bound.
    pool: Vec<(wgpu::Buffer, wgpu::Buffer)>,
    used: usize,
    compactor: Compactor,
    list: DrawList,
    job: crate::cull::compact::CompactJob,
}

impl FlagSplit {
    fn new(gpu: &Gpu, objects: &SharedObjects) -> Self {
        let n = objects.count;
        use crate::cull::compact::storage_entry;
        use wgpu::BufferUsages as U;
        let layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hroc flag split"),
            entries: &[
                storage_entry(0, true),
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, false),
                storage_entry(4, false),
                crate::cull::compact::uniform_entry(5),
            ],
        });
        let pl = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("hroc flag split"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module = gpu.shader("split.wgsl", &shaders::source("split.wgsl"));
        let deferred = gpu.buffer("hroc non-occluders", n as u64 * 4, U::STORAGE | U::COPY_DST);
        let compactor = Compactor::new(gpu, n);
        let (list, job) = compactor.packed_list(gpu, "hroc non-occluders list", &deferred, &objects.commands);
        FlagSplit { pipeline: gpu.compute_pipeline(&module, "split", Some(&pl), &[]), layout, deferred, pool: Vec::new(), used: 0, list, compactor, job }
    }

    fn begin(&mut self, enc: &mut wgpu::CommandEncoder, objects: &SharedObjects) {
        self.used = 0;
        enc.copy_buffer_to_buffer(&objects.always_deferred, 0, &self.deferred, 0, objects.count as u64 * 4);
    }

    pub(crate) fn split(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, bounds: &wgpu::Buffer, list: &DrawList) -> DrawList {
        use wgpu::BufferUsages as U;
        let need = (list.commands.size() / 20).max(1) * 20;
        if self.used == self.pool.len() {
            self.pool.push((gpu.buffer("hroc split list", need, U::STORAGE | U::INDIRECT | U::COPY_SRC), gpu.buffer("hroc split bound", 16, U::UNIFORM | U::COPY_DST)));
        } else if self.pool[self.used].0.size() < need {
            self.pool[self.used].0 = gpu.buffer("hroc split list", need, U::STORAGE | U::INDIRECT | U::COPY_SRC);
        }
        let (dst, bound) = self.pool[self.used].clone();
        self.used += 1;
        // Written before the submit that runs this dispatch; each slot once a frame.
        gpu.queue.write_buffer(&bound, 0, bytemuck::cast_slice(&[list.max_count, 0, 0, 0]));
        let bind = gpu.bind_buffers(&self.layout, &[bounds, &list.commands, &list.count, &dst, &self.deferred, &bound]);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc flag split"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        let (x, y) = dispatch_size(list.max_count, 256);
        pass.dispatch_workgroups(x, y, 1);
        DrawList { commands: dst, count: list.count.clone(), max_count: list.max_count }
    }

    /// Non-occluders the method drew this frame, plus the never-culled ones, packed.
    fn finish(&mut self, enc: &mut wgpu::CommandEncoder) -> DrawList {
        self.compactor.record(enc, &self.job);
        self.list.clone()
    }
}
