//! [`Culler`]: the objects, their BVH and GPU buffers, shared by every view.

use super::serving::check_limits;
use super::*;
use crate::aabb::OrientedBox;
use crate::bvh::{Bvh, BvhNode, Split, NO_LEAF};
use crate::capabilities::{Capabilities, DrawCount, Marks};
use crate::contract::PipelineCheck;
use crate::cull::{DrawList, Method, MethodContext, MethodOptions, WorkCounts};
use crate::error::{Error, Result};
use crate::gpu::Uploads;
use crate::gpu::{Gpu, GpuTimer, InvocationCounter};
use crate::id_marks::IdMarks;
use crate::layout::{DrawCommand, FrameUniform, ObjectBounds, OrientedBounds};
use crate::list_pass::ListPass;
use crate::reflect::Layout;
use crate::tally::DrawTally;
use crate::validation::{Validation, ValidationDesc, Validator};
use crate::Aabb;

/// What a culler needs of its objects before the first frame.
#[derive(Clone, Debug)]
pub struct CullerDesc<'a> {
    /// The objects, indexed 0..N in this order: the object index of every
    /// draw command the culler hands back.
    pub objects: &'a [ObjectDesc],
    /// Object slots to allocate (at least `objects.len()`): room for
    /// [`Culler::add_objects`] without reallocation. Growing past it
    /// doubles the slots and rebuilds every view (a camera cut for each).
    pub capacity: u32,
    /// BVH split strategy (HROC, IOC and the query methods walk the BVH).
    pub split: Split,
    /// Method parameters.
    pub options: MethodOptions,
    /// How the BVH follows moving, added and removed objects.
    pub motion: MotionOptions,
    /// Time every stage with GPU timestamps. Needs `TIMESTAMP_QUERY` and
    /// `TIMESTAMP_QUERY_INSIDE_ENCODERS`.
    pub timestamps: bool,
    /// Count every stage's vertex, fragment and compute shader invocations
    /// with pipeline-statistics queries ([`View::stage_invocations`]): work
    /// that does not depend on how busy the machine is. Needs
    /// [`PIPELINE_STATISTICS_FEATURES`]. The host's draws are counted when
    /// it records them with [`Draw::record`].
    pub pipeline_statistics: bool,
    /// What to run with; `None`: the most the device allows
    /// ([`Capabilities::of`] its features). Asking for more than the
    /// device has is an error.
    pub capabilities: Option<Capabilities>,
    /// Check on the GPU, without waiting, that the host's draws keep the
    /// host contract, and report a frame or two after one that did not
    /// ([`Error::Validation`] from [`View::cull`] once it has recorded its
    /// frame in full, or from [`View::validation`]; a
    /// [`crate::stats::Finding`] names the view, frame, object, phase and
    /// pixel, the mistake and its fix): targets not cleared before the
    /// frame, or cleared or drawn by other passes inside it; fragments in
    /// front of their object's box, or in a view without IDs in front of
    /// every box drawn (boxes too small, wrong transforms, depth bias
    /// toward the viewer or light); IDs out of range, naming undrawn
    /// objects, or missing where depth was drawn; and, with early-Z marks,
    /// objects drawn visibly but not marked, or marked while hidden (no
    /// forced early-Z). ID checks need a view whose method reads the ID
    /// target. Stepwise frames ([`View::steps`]) are checked as well.
    /// On by default in debug builds, off in release. Costs a few compute
    /// passes per frame, each reading at most 1,024 pixels of the host's
    /// depth and IDs (a different share each frame: a mistake that
    /// touches few pixels is found within a few frames); BENCHMARKS.md
    /// gives the cost.
    pub validation: bool,
    /// The size, in indices, of the host's index buffer: with
    /// [`CullerDesc::validation`], objects whose indices lie past it are
    /// refused ([`Culler::new`], [`Culler::add_objects`]). `None`: not
    /// checked.
    pub index_count: Option<u32>,
}

impl<'a> CullerDesc<'a> {
    /// SAH BVH, no spare slots, default parameters, no timestamps, no
    /// pipeline statistics, validation in debug builds, index ranges
    /// unchecked.
    pub fn new(objects: &'a [ObjectDesc]) -> Self {
        CullerDesc {
            objects,
            capacity: 0,
            split: Split::Sah,
            options: MethodOptions::default(),
            motion: MotionOptions::default(),
            timestamps: false,
            pipeline_statistics: false,
            capabilities: None,
            validation: cfg!(debug_assertions),
            index_count: None,
        }
    }
}

/// The objects, their BVH and their GPU buffers, on the host's device;
/// shared by every [`View`] of them.
///
/// Objects live in slots: an object's index is its slot, stable from
/// [`Culler::add_objects`] (or creation) to [`Culler::remove_objects`],
/// and a removed object's slot is reused by a later add.
pub struct Culler {
    pub(super) gpu: Gpu,
    /// Every slot's box (empty slots: a point at the origin).
    pub(super) boxes: Vec<Aabb>,
    /// Every slot's own box, where the host gave one.
    pub(super) oriented: Vec<Option<OrientedBox>>,
    pub(super) live: Vec<bool>,
    pub(super) free: std::collections::BTreeSet<u32>,
    /// Bumped by every change of objects.
    pub(super) moves: u64,
    /// Bumped by every rebuild of the BVH or of the slots.
    pub(super) generation: u64,
    pub(super) bvh: Bvh,
    pub(super) split: Split,
    pub(super) built_cost: f64,
    /// The GPU holds the boxes: set by [`Culler::set_bounds_gpu`], when
    /// `boxes` and the CPU tree's boxes are stale.
    pub(super) gpu_boxes: bool,
    /// Slots `lo..hi` whose oriented boxes the GPU has not yet: written in
    /// one range before the next frame or read ([`Culler::flush_oriented`]).
    /// Moving objects drop their boxes in [`Culler::set_bounds`] and get
    /// new ones in [`Culler::set_oriented`]: one write of the range, not two.
    pub(super) oriented_dirty: std::sync::Mutex<(u32, u32)>,
    pub(super) bvh_nodes: wgpu::Buffer,
    pub(super) leaf_of_object: wgpu::Buffer,
    pub(super) gpu_refit: Option<GpuRefit>,
    pub(super) objects: SharedObjects,
    pub(super) marks_layout: wgpu::BindGroupLayout,
    /// [`Culler::sink_marks`]: 16 bytes, which every write lands in or misses.
    pub(super) sink_marks: wgpu::BindGroup,
    pub(super) options: MethodOptions,
    pub(super) motion: MotionOptions,
    pub(super) last_update: UpdateStats,
    pub(super) timestamps: bool,
    pub(super) pipeline_statistics: bool,
    /// What the culler runs with.
    pub(super) caps: Capabilities,
    /// The ID-marks pass, with [`Marks::Ids`].
    pub(super) id_marks: Option<IdMarks>,
    /// The validation passes, when the culler validates.
    pub(super) validator: Option<Validator>,
    /// The check of the pipelines of marked draws ([`Draw::record`]).
    pub(super) pipelines: PipelineCheck,
    /// [`CullerDesc::index_count`], where the culler validates.
    pub(super) index_count: Option<u32>,
    /// The pass that packs a set's frustum lists ([`Culler::cull_views`]).
    pub(super) set_frustum: crate::set_frustum::SetFrustum,
}

impl Culler {
    /// Creates a culler on the host's device. Errors, never panics, when the
    /// device lacks the features of the capabilities asked for
    /// ([`CullerDesc::capabilities`]; at least [`crate::capabilities::REQUIRED_FEATURES`]) or
    /// a limit the culler's shared passes need (or [`TIMESTAMP_FEATURES`] when
    /// asked for timestamps, [`PIPELINE_STATISTICS_FEATURES`] when asked
    /// for pipeline statistics), when an object's box is not finite, or when the
    /// objects exceed the device's buffer limits. Objects flagged
    /// [`ObjectFlags::DYNAMIC`] are left out of the BVH.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, desc: &CullerDesc) -> Result<Culler> {
        let caps = desc.capabilities.unwrap_or_else(|| Capabilities::of(device));
        if caps.read_only_depth && !Capabilities::of(device).read_only_depth {
            return Err(Error::Arg("CullerDesc::capabilities asks for read-only depth attachments, which this backend lacks (READ_ONLY_DEPTH_STENCIL)".into()));
        }
        let mut needed = caps.features();
        if desc.timestamps {
            needed |= TIMESTAMP_FEATURES;
        }
        if desc.pipeline_statistics {
            needed |= PIPELINE_STATISTICS_FEATURES;
        }
        let missing = needed - device.features();
        if !missing.is_empty() {
            return Err(Error::MissingFeatures { what: "hroc::Culler".into(), missing });
        }
        let mut shared: Vec<Layout> = vec![Layout::Compact, Layout::FlagSplit, Layout::Tally, Layout::Refit];
        if caps.draw_count == DrawCount::Emulated {
            shared.push(Layout::Tail);
        }
        if caps.marks == Marks::Ids {
            shared.push(Layout::IdMarks);
        }
        check_limits(&device.limits(), "hroc::Culler", &shared)?;
        let gpu = Gpu::from_device(device, queue);
        let objects = desc.objects;
        for (i, o) in objects.iter().enumerate() {
            check_box(i as u32, &o.bounds)?;
            check_indices(i as u32, o, desc.index_count.filter(|_| desc.validation))?;
            check_oriented(i as u32, &o.oriented)?;
            check_flags(i as u32, o.flags)?;
        }
        let m = desc.motion;
        check_motion(&m)?;
        let capacity = (desc.capacity as u64).max(objects.len() as u64).max(1);
        check_capacity(device, capacity)?;
        let id_marks = (caps.marks == Marks::Ids).then(|| IdMarks::new(&gpu, capacity as u32));
        let n = capacity as usize;
        let mut boxes = vec![Aabb::new(glam::Vec3::ZERO, glam::Vec3::ZERO); n];
        let mut oriented = vec![None; n];
        let mut live = vec![false; n];
        let mut flags = vec![ObjectFlags::NONE; n];
        let mut commands = vec![DrawCommand::default(); n];
        for (i, o) in objects.iter().enumerate() {
            (boxes[i], oriented[i], live[i], flags[i], commands[i]) = (o.bounds, o.oriented, true, o.flags, command(o, i as u32));
        }
        let marks_layout = marks_layout(device);
        let (shared, bvh_nodes, leaf_of_object) = allocate(&gpu, capacity as u32, &commands, flags);
        let sink_buffer = gpu.buffer("hroc marks sink", 16, wgpu::BufferUsages::STORAGE);
        let sink_marks = gpu.bind_buffers(&marks_layout, &[&sink_buffer]);
        let pipelines = PipelineCheck::new(device, &sink_buffer, desc.validation);
        let set_frustum = crate::set_frustum::SetFrustum::new(&gpu, caps.draw_count == DrawCount::Emulated);
        let mut culler = Culler {
            sink_marks,
            bvh_nodes,
            leaf_of_object,
            bvh: Bvh::default(),
            split: desc.split,
            built_cost: 0.0,
            gpu_boxes: false,
            oriented_dirty: std::sync::Mutex::new((u32::MAX, 0)),
            gpu_refit: None,
            gpu,
            boxes,
            oriented,
            live,
            free: (objects.len() as u32..capacity as u32).collect(),
            moves: 0,
            generation: 0,
            objects: shared,
            marks_layout,
            options: desc.options.clone(),
            motion: m,
            last_update: UpdateStats { sah_growth: Some(1.0), ..Default::default() },
            timestamps: desc.timestamps,
            pipeline_statistics: desc.pipeline_statistics,
            caps,
            id_marks,
            validator: desc.validation.then(Validator::default),
            pipelines,
            index_count: desc.index_count.filter(|_| desc.validation),
            set_frustum,
        };
        culler.rebuild_tree()?;
        culler.upload_bounds();
        culler.upload_oriented(0..capacity as u32);
        culler.update_always();
        Ok(culler)
    }

    /// Rebuilds the BVH over the live static objects now (also done by the
    /// [`MotionOptions`] policy after changes). Views of methods that keep
    /// the tree's shape ([`Method::keeps_tree`]) start over on their next
    /// frame.
    pub fn rebuild(&mut self) -> Result<()> {
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        self.rebuild_tree()?;
        self.upload_bounds();
        self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: true, sah_growth: Some(1.0) };
        Ok(())
    }

    pub(super) fn is_dynamic(&self, i: usize) -> bool {
        self.objects.flags[i].contains(ObjectFlags::DYNAMIC)
    }

    pub(super) fn bvh_leaf(&self, i: usize) -> Option<u32> {
        self.bvh.leaf_of_object.get(i).copied().filter(|&l| l != NO_LEAF)
    }

    /// The GPU bits of slot `i`'s flags.
    pub(super) fn gpu_flags(&self, i: usize) -> u32 {
        let f = self.objects.flags[i].bits();
        if !self.live[i] {
            REMOVED
        } else if self.is_dynamic(i) || self.bvh_leaf(i).is_none() {
            f | ALONE
        } else {
            f
        }
    }

    pub(super) fn upload_bounds(&mut self) {
        let bounds: Vec<ObjectBounds> = (0..self.boxes.len()).map(|i| bounds_of(self.boxes[i], self.gpu_flags(i))).collect();
        self.objects.alone = bounds.iter().filter(|b| b.flags & ALONE != 0).count() as u32;
        self.gpu.queue.write_buffer(&self.objects.bounds, 0, bytemuck::cast_slice(&bounds));
    }

    /// Writes the changes to objects that the GPU has not yet (queue
    /// writes, applied with the next submit). [`View::cull`] does it
    /// before every frame; a host that times its frames apart from its
    /// updates calls it after them, so the writes count there.
    pub fn flush(&self) {
        self.flush_oriented();
    }

    /// Marks the oriented boxes of `slots` for the GPU: they go up with
    /// the next [`Culler::flush_oriented`].
    pub(super) fn upload_oriented(&self, slots: impl IntoIterator<Item = u32>) {
        let mut dirty = self.oriented_dirty.lock().unwrap_or_else(|p| p.into_inner());
        let (lo, hi) = slots.into_iter().fold(*dirty, |(lo, hi), i| (lo.min(i), hi.max(i + 1)));
        *dirty = (lo, hi.min(self.objects.count));
    }

    /// Writes the marked oriented boxes to the GPU in one write: the range
    /// from the lowest marked slot to the highest (a queue write per slot
    /// costs a staging copy each, and the boxes between are current too).
    /// Every frame and read of them comes after it.
    pub(super) fn flush_oriented(&self) {
        let (lo, hi) = std::mem::replace(&mut *self.oriented_dirty.lock().unwrap_or_else(|p| p.into_inner()), (u32::MAX, 0));
        if lo >= hi {
            return;
        }
        let part: Vec<OrientedBounds> = self.oriented[lo as usize..hi as usize].iter().map(|&o| oriented_of(o)).collect();
        self.gpu.queue.write_buffer(&self.objects.oriented, lo as u64 * ORIENTED_BYTES, bytemuck::cast_slice(&part));
    }

    pub(super) fn upload_commands(&mut self) {
        self.objects.commands_version += 1;
        self.gpu.queue.write_buffer(&self.objects.commands, 0, bytemuck::cast_slice(&self.objects.cpu_commands));
    }

    /// Reads the GPU's boxes and tree back after [`Culler::set_bounds_gpu`]
    /// (one wait), so that the CPU can change them again.
    pub(super) fn sync_boxes(&mut self) -> Result<()> {
        if !self.gpu_boxes {
            return Ok(());
        }
        let bounds: Vec<ObjectBounds> = self.gpu.read(&self.objects.bounds, 0, self.objects.count as u64)?;
        for (b, g) in self.boxes.iter_mut().zip(&bounds) {
            *b = Aabb::new(g.min.into(), g.max.into());
        }
        let nodes: Vec<BvhNode> = self.gpu.read(&self.bvh_nodes, 0, self.bvh.nodes.len() as u64)?;
        self.bvh.nodes = nodes;
        self.gpu_boxes = false;
        Ok(())
    }

    /// Doubles the slots (or more): new buffers, every view rebuilt.
    pub(super) fn grow(&mut self, capacity: u64) -> Result<()> {
        check_capacity(&self.gpu.device, capacity)?;
        let (old, n) = (self.objects.count as usize, capacity as usize);
        self.boxes.resize(n, Aabb::new(glam::Vec3::ZERO, glam::Vec3::ZERO));
        self.oriented.resize(n, None);
        self.live.resize(n, false);
        self.objects.cpu_commands.resize(n, DrawCommand::default());
        let mut flags = std::mem::take(&mut self.objects.flags);
        flags.resize(n, ObjectFlags::NONE);
        self.free.extend(old as u32..n as u32);
        (self.objects, self.bvh_nodes, self.leaf_of_object) = allocate(&self.gpu, n as u32, &self.objects.cpu_commands, flags);
        self.gpu_refit = None;
        self.bvh.leaf_of_object.resize(n, NO_LEAF);
        self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        self.gpu.queue.write_buffer(&self.leaf_of_object, 0, bytemuck::cast_slice(&self.bvh.leaf_of_object));
        // The new buffer is zeroed (no oriented boxes): the kept objects'
        // boxes go up again.
        self.upload_oriented(0..old as u32);
        self.generation += 1;
        Ok(())
    }

    /// Object slots (live objects plus free slots).
    pub fn object_count(&self) -> u32 {
        self.objects.count
    }

    /// True when object `i` is live (added and not removed).
    pub fn is_live(&self, i: u32) -> bool {
        self.live.get(i as usize).copied().unwrap_or(false)
    }

    /// The object BVH, as the CPU last built or refit it (after
    /// [`Culler::set_bounds_gpu`], the GPU's boxes are newer).
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The BVH nodes the views read, read back from the GPU (one wait): for
    /// tests of the GPU refit.
    #[doc(hidden)]
    pub fn read_nodes(&self) -> Result<Vec<BvhNode>> {
        self.gpu.read(&self.bvh_nodes, 0, self.bvh.nodes.len() as u64)
    }

    /// The oriented boxes the views read, read back from the GPU (one
    /// wait): for tests that they follow their objects.
    #[doc(hidden)]
    pub fn read_oriented(&self) -> Result<Vec<OrientedBounds>> {
        self.flush_oriented();
        self.gpu.read(&self.objects.oriented, 0, self.objects.count as u64)
    }

    /// Every object's draw command in object order (what `noc` draws).
    pub fn commands(&self) -> &wgpu::Buffer {
        &self.objects.commands
    }

    /// Layout of the marks bind group of every [`Draw`]: the culler's
    /// copy of [`marks_layout`] (which needs no culler).
    pub fn marks_layout(&self) -> &wgpu::BindGroupLayout {
        &self.marks_layout
    }

    /// A marks bind group that takes every write and keeps none: bind it
    /// to draw the host's own objects (not the culler's) through the same
    /// pipelines, with any `instance_index`.
    pub fn sink_marks(&self) -> &wgpu::BindGroup {
        &self.sink_marks
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
        self.serves_with(method, options)?;
        let t = Targets::new(targets, self.gpu.device.adapter_info().backend)?;
        self.check_targets(method, &t)?;
        use wgpu::BufferUsages as U;
        let frame = self.gpu.buffer("hroc frame", std::mem::size_of::<FrameUniform>() as u64, U::UNIFORM | U::COPY_DST);
        let sink_buf = self.gpu.buffer("hroc marks sink", self.objects.count as u64 * 4, U::STORAGE);
        let sink = self.gpu.bind_buffers(&self.marks_layout, &[&sink_buf]);
        let auto = self.auto_candidates(method, &t, options);
        let imp = method.create(&MethodContext { options, auto: &auto, ..self.context(&frame, &t) })?;
        let timer = self.timestamps.then(|| GpuTimer::new(&self.gpu, 64));
        let reads_ids = method.needs_ids() || (self.caps.marks == Marks::Ids && method.reads_marks()) || method == Method::Auto;
        let validation = self.validator.as_ref().map(|v| {
            let desc = ValidationDesc {
                frame: &frame,
                bounds: &self.objects.bounds,
                oriented: &self.objects.oriented,
                slots: self.objects.count,
                targets: &t,
                ids: reads_ids,
                name: format!("the {method} view of {}x{} (layer {}, mip {})", t.size.0, t.size.1, t.layer, t.mip),
            };
            Validation::new(&self.gpu, v, desc)
        });
        let counter = self.pipeline_statistics.then(|| InvocationCounter::new(&self.gpu, 64));
        Ok(View {
            method,
            options: options.clone(),
            imp,
            frame,
            targets: t,
            sink,
            split: None,
            timer,
            counter,
            last_stages: Vec::new(),
            generation: self.generation,
            slots: self.objects.count,
            last_pose: None,
            last_cut: false,
            work: WorkCounts::default(),
            shape: Default::default(),
            tally: DrawTally::new(&self.gpu, method == Method::Auto),
            uploads: Uploads::new(&self.gpu.device),
            tail: None,
            tail_pass: (self.caps.draw_count == DrawCount::Emulated).then(|| ListPass::new(&self.gpu, Layout::Tail, ("tail.wgsl", "tail"), None, &[])),
            interrupted: false,
            wants_steps: true,
            last_start: None,
            culled_by: method,
            frames: 0,
            validation,
            visibility: None,
            cutout_marks: None,
        })
    }

    pub(super) fn context<'a>(&'a self, frame: &'a wgpu::Buffer, targets: &'a Targets) -> MethodContext<'a> {
        MethodContext {
            gpu: &self.gpu,
            bvh: &self.bvh,
            bvh_nodes: &self.bvh_nodes,
            leaf_of_object: &self.leaf_of_object,
            bounds: &self.objects.bounds,
            oriented: &self.objects.oriented,
            commands: &self.objects.commands,
            object_count: self.objects.count,
            node_capacity: node_capacity(self.objects.count),
            frame,
            targets,
            marks_layout: &self.marks_layout,
            options: &self.options,
            capabilities: self.caps,
            id_marks: self.id_marks.as_ref(),
            auto: &[],
        }
    }

    /// The device wrapper the culler records with.
    #[doc(hidden)]
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }
}

pub(super) fn check_capacity(device: &wgpu::Device, n: u64) -> Result<()> {
    let limits = device.limits();
    let storage = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    for (what, need) in
        [("object boxes", n * 32), ("oriented boxes", n * ORIENTED_BYTES), ("draw commands", n * 20), ("BVH nodes", (2 * n).saturating_sub(1) * 32), ("HROC groups", 3 * n * 16)]
    {
        if need > storage {
            return Err(Error::OverDeviceLimits(format!("{what} need {need} bytes, the device allows {storage}")));
        }
    }
    if n >= 1 << 30 {
        return Err(Error::OverDeviceLimits(format!("{n} object slots exceed 2^30")));
    }
    Ok(())
}

mod objects;
