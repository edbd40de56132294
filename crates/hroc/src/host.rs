//! The host contract: what a renderer hands the culler, what it gets back.
//! The crate docs state the preconditions once; this module implements them.

use crate::bvh::{Bvh, BvhNode, Split, NO_LEAF};
use crate::cull::{compact::Compactor, CullMethod, DrawList, Frame, FrameBody, Method, MethodContext, MethodOptions, Stage, Stat, WorkCounts};
use crate::error::{Error, Result};
use crate::frustum::{DepthRange, ViewDesc};
use crate::gpu::{dispatch_size, Gpu, GpuTimer, InvocationCounter, Invocations, PassCount};
use crate::layout::{DrawCommand, FrameUniform, ObjectBounds, OrientedBounds};
use crate::tally::{DrawTally, FrameStats};
use crate::{shaders, Aabb, OrientedBox};

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
    /// Moves most frames (a vehicle, a character): kept out of the BVH and
    /// tested on its own box, so that moving it costs no refit (HROC §6's
    /// hybrid). Static objects may move too; they are refit into the BVH.
    pub const DYNAMIC: ObjectFlags = ObjectFlags(4);

    /// The raw bits (`ObjectBounds::flags`, WGSL `NEVER_CULL`/`NOT_OCCLUDER`/`DYNAMIC`).
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
    /// Optionally, a box in the object's own frame that also holds
    /// everything the draw can rasterize. HROC tests an object against
    /// where both boxes meet: for rotated panels, rings and beams, far less
    /// than the world box alone.
    pub oriented: Option<OrientedBox>,
}

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
}

impl<'a> CullerDesc<'a> {
    /// SAH BVH, no spare slots, default parameters, no timestamps, no
    /// pipeline statistics.
    pub fn new(objects: &'a [ObjectDesc]) -> Self {
        CullerDesc { objects, capacity: 0, split: Split::Sah, options: MethodOptions::default(), motion: MotionOptions::default(), timestamps: false, pipeline_statistics: false }
    }
}

/// Where the BVH is refit after objects move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refit {
    /// On the CPU, then the boxes and nodes are uploaded (the default:
    /// measured cheaper here, see BENCHMARKS.md).
    #[default]
    Cpu,
    /// On the GPU: only the moved boxes are uploaded (`refit.wgsl`).
    Gpu,
}

/// How the BVH follows motion (HROC §6 names the static hierarchy as the
/// method's main limit). Static objects that move are refit into the tree;
/// [`ObjectFlags::DYNAMIC`] objects and objects added since the last build
/// are tested on their own (the paper's hybrid); a rebuild folds the
/// latter back in when the tree has degraded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionOptions {
    /// Where refits run.
    pub refit: Refit,
    /// Rebuild when the refit tree's SAH cost exceeds this multiple of its
    /// cost as built ([`Bvh::sah_cost`]); `f64::INFINITY` never does.
    pub rebuild_sah_growth: f64,
    /// Rebuild when more than this fraction of the live objects are out of
    /// step with the tree: static objects outside it (added since the last
    /// build, or turned static without a leaf), each a group of its own
    /// until then, plus frozen leaves (objects turned DYNAMIC or removed),
    /// which rays still walk into.
    pub rebuild_outside: f64,
}

impl Default for MotionOptions {
    fn default() -> Self {
        MotionOptions { refit: Refit::Cpu, rebuild_sah_growth: 2.0, rebuild_outside: 0.05 }
    }
}

/// What the last change of objects cost the culler ([`Culler::last_update`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateStats {
    /// CPU ms in the culler: boxes, refit or rebuild, uploads queued.
    pub cpu_ms: f64,
    /// True when the change rebuilt the BVH.
    pub rebuilt: bool,
    /// SAH cost of the tree over its cost as last built (1 when fresh);
    /// `None` after a GPU refit, whose boxes the CPU does not see.
    pub sah_growth: Option<f64>,
}

/// The device features every method needs.
pub const REQUIRED_FEATURES: wgpu::Features =
    wgpu::Features::MULTI_DRAW_INDIRECT_COUNT.union(wgpu::Features::INDIRECT_FIRST_INSTANCE).union(wgpu::Features::SHADER_EARLY_DEPTH_TEST);

/// The features [`CullerDesc::timestamps`] needs.
pub const TIMESTAMP_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// The features [`CullerDesc::pipeline_statistics`] needs.
pub const PIPELINE_STATISTICS_FEATURES: wgpu::Features = wgpu::Features::PIPELINE_STATISTICS_QUERY;

/// GPU-only bits of `ObjectBounds::flags` (`ALONE`, `REMOVED` in common.wgsl).
const ALONE: u32 = 0x4000_0000;
const REMOVED: u32 = 0x8000_0000;

/// Object buffers shared by every view of a [`Culler`].
pub(crate) struct SharedObjects {
    /// Object slots (the culler's capacity): every per-object buffer and
    /// pass covers them; empty slots draw nothing.
    pub count: u32,
    pub bounds: wgpu::Buffer,
    /// `OrientedBounds` per slot (`valid` 0 where the host gave none).
    pub oriented: wgpu::Buffer,
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
///
/// Objects live in slots: an object's index is its slot, stable from
/// [`Culler::add_objects`] (or creation) to [`Culler::remove_objects`],
/// and a removed object's slot is reused by a later add.
pub struct Culler {
    gpu: Gpu,
    /// Every slot's box (empty slots: a point at the origin).
    boxes: Vec<Aabb>,
    /// Every slot's own box, where the host gave one.
    oriented: Vec<Option<OrientedBox>>,
    live: Vec<bool>,
    free: std::collections::BTreeSet<u32>,
    /// Bumped by every change of objects.
    moves: u64,
    /// Bumped by every rebuild of the BVH or of the slots.
    generation: u64,
    bvh: Bvh,
    split: Split,
    built_cost: f64,
    /// The GPU holds the boxes: set by [`Culler::set_bounds_gpu`], when
    /// `boxes` and the CPU tree's boxes are stale.
    gpu_boxes: bool,
    /// Slots `lo..hi` whose oriented boxes the GPU has not yet: written in
    /// one range before the next frame or read ([`Culler::flush_oriented`]).
    /// Moving objects drop their boxes in [`Culler::set_bounds`] and get
    /// new ones in [`Culler::set_oriented`]: one write of the range, not two.
    oriented_dirty: std::cell::Cell<(u32, u32)>,
    bvh_nodes: wgpu::Buffer,
    leaf_of_object: wgpu::Buffer,
    gpu_refit: Option<GpuRefit>,
    objects: SharedObjects,
    marks_layout: wgpu::BindGroupLayout,
    /// [`Culler::sink_marks`]: 16 bytes, which every write lands in or misses.
    sink_marks: wgpu::BindGroup,
    options: MethodOptions,
    motion: MotionOptions,
    last_update: UpdateStats,
    timestamps: bool,
    pipeline_statistics: bool,
}

impl Culler {
    /// Creates a culler on the host's device. Errors, never panics, when the
    /// device lacks [`REQUIRED_FEATURES`] (or [`TIMESTAMP_FEATURES`] when
    /// asked for timestamps, [`PIPELINE_STATISTICS_FEATURES`] when asked
    /// for pipeline statistics), when an object's box is not finite, or when the
    /// objects exceed the device's buffer limits. Objects flagged
    /// [`ObjectFlags::DYNAMIC`] are left out of the BVH.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, desc: &CullerDesc) -> Result<Culler> {
        let mut needed = REQUIRED_FEATURES;
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
        let gpu = Gpu::from_device(device, queue);
        let objects = desc.objects;
        for (i, o) in objects.iter().enumerate() {
            check_box(i as u32, &o.bounds)?;
            check_oriented(i as u32, &o.oriented)?;
            check_flags(i as u32, o.flags)?;
        }
        let m = desc.motion;
        check_motion(&m)?;
        let capacity = (desc.capacity as u64).max(objects.len() as u64).max(1);
        check_capacity(device, capacity)?;
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
        let sink_marks = gpu.bind_buffers(&marks_layout, &[&gpu.buffer("hroc marks sink", 16, wgpu::BufferUsages::STORAGE)]);
        let mut culler = Culler {
            sink_marks,
            bvh_nodes,
            leaf_of_object,
            bvh: Bvh::default(),
            split: desc.split,
            built_cost: 0.0,
            gpu_boxes: false,
            oriented_dirty: std::cell::Cell::new((u32::MAX, 0)),
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
        };
        culler.rebuild_tree()?;
        culler.upload_bounds();
        culler.upload_oriented(0..capacity as u32);
        culler.update_always();
        Ok(culler)
    }

    /// Moves objects: `(object, new world box)` pairs, taking effect from
    /// the next frame of every view. Static objects are refit into the BVH
    /// ([`MotionOptions::refit`]), which is rebuilt when the policy says
    /// so; [`ObjectFlags::DYNAMIC`] objects only change their own box.
    /// A moved object's [`OrientedBox`] is dropped: give the new one with
    /// [`Culler::set_oriented`].
    /// Errors on an object that is not live or a box that is not finite;
    /// nothing changes then. Views of methods that cannot follow motion
    /// ([`Method::takes_motion`]) refuse their next frame.
    pub fn set_bounds(&mut self, moves: &[(u32, Aabb)]) -> Result<()> {
        for &(i, b) in moves {
            self.check_live(i)?;
            check_box(i, &b)?;
        }
        if moves.is_empty() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        let mut dropped = Vec::new();
        for &(i, b) in moves {
            self.boxes[i as usize] = b;
            if self.oriented[i as usize].take().is_some() {
                dropped.push(i);
            }
        }
        self.upload_oriented(dropped);
        self.moves += 1;
        // Only objects outside the tree moved (HROC §6's hybrid): their
        // boxes are all that changes, with no refit and no policy check.
        if moves.iter().all(|&(i, _)| self.is_dynamic(i as usize) || self.bvh_leaf(i as usize).is_none()) {
            self.upload_bounds();
            self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, ..self.last_update };
            return Ok(());
        }
        self.changed(t)
    }

    /// Moves every object at once from a buffer the host fills on the GPU
    /// (from its own transforms): two `vec4<f32>` per slot, `(min.xyz, _)`
    /// then `(max.xyz, _)`, `32 * capacity` bytes at least, usage `STORAGE`.
    /// Removed slots are ignored. A box that is not finite and ordered is
    /// taken as one around everything (the object is then never culled).
    /// Records the copy and a GPU refit of the static objects into
    /// `encoder`, which the host submits after filling `boxes` and before
    /// the next frame. The CPU's copy of the boxes goes stale: a later
    /// rebuild, or [`Culler::set_bounds`], first reads the GPU's back.
    /// Every [`OrientedBox`] is dropped, as any object may have moved.
    pub fn set_bounds_gpu(&mut self, encoder: &mut wgpu::CommandEncoder, boxes: &wgpu::Buffer) -> Result<()> {
        let need = self.objects.count as u64 * 32;
        if boxes.size() < need || !boxes.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(Error::InvalidObject(format!("bounds buffer of {} bytes, usage {:?}: needs {need} bytes and STORAGE", boxes.size(), boxes.usage())));
        }
        let t = std::time::Instant::now();
        if self.oriented.iter().any(Option::is_some) {
            self.oriented.iter_mut().for_each(|o| *o = None);
            self.upload_oriented(0..self.objects.count);
        }
        self.refit_on_gpu(encoder, Some(boxes));
        self.gpu_boxes = true;
        self.moves += 1;
        self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, sah_growth: None };
        Ok(())
    }

    /// Adds objects, taking effect from the next frame of every view, and
    /// returns their indices (free slots, lowest first, then new ones). An
    /// object that reuses the slot of a removed one enters the BVH by a
    /// refit; others are tested on their own until the next rebuild.
    /// `first_instance` of each object's command is its index. Errors on a
    /// box that is not finite; nothing changes then.
    pub fn add_objects(&mut self, objects: &[ObjectDesc]) -> Result<Vec<u32>> {
        for (k, o) in objects.iter().enumerate() {
            check_box(k as u32, &o.bounds)?;
            check_oriented(k as u32, &o.oriented)?;
            check_flags(k as u32, o.flags)?;
        }
        if objects.is_empty() {
            return Ok(Vec::new());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        let live = self.live.iter().filter(|&&l| l).count() as u64;
        if live + objects.len() as u64 > self.objects.count as u64 {
            self.grow((live + objects.len() as u64).next_power_of_two())?;
        }
        let mut ids = Vec::with_capacity(objects.len());
        for o in objects {
            let i = self.free.pop_first().expect("grown to fit");
            let s = i as usize;
            (self.boxes[s], self.oriented[s], self.live[s], self.objects.flags[s]) = (o.bounds, o.oriented, true, o.flags);
            self.objects.cpu_commands[s] = command(o, i);
            ids.push(i);
        }
        self.upload_oriented(ids.iter().copied());
        self.upload_commands();
        self.moves += 1;
        self.update_always();
        self.changed(t)?;
        Ok(ids)
    }

    /// Removes objects, taking effect from the next frame of every view:
    /// their commands draw nothing and their slots are free for
    /// [`Culler::add_objects`]. Errors on an object that is not live, or
    /// listed twice; nothing changes then.
    pub fn remove_objects(&mut self, objects: &[u32]) -> Result<()> {
        let mut seen = std::collections::HashSet::new();
        for &i in objects {
            self.check_live(i)?;
            if !seen.insert(i) {
                return Err(Error::InvalidObject(format!("object {i} listed twice")));
            }
        }
        if objects.is_empty() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        for &i in objects {
            let s = i as usize;
            (self.live[s], self.objects.flags[s], self.oriented[s]) = (false, ObjectFlags::NONE, None);
            self.objects.cpu_commands[s] = DrawCommand::default();
            self.free.insert(i);
        }
        self.upload_oriented(objects.iter().copied());
        self.upload_commands();
        self.moves += 1;
        self.update_always();
        self.changed(t)
    }

    /// Gives objects an [`OrientedBox`] (`Some`) or takes it away (`None`),
    /// from the next frame of every view; their world boxes stay as they
    /// are. Errors on an object that is not live, or a box that is not
    /// finite and invertible; nothing changes then.
    pub fn set_oriented(&mut self, boxes: &[(u32, Option<OrientedBox>)]) -> Result<()> {
        for (i, b) in boxes {
            self.check_live(*i)?;
            check_oriented(*i, b)?;
        }
        for &(i, b) in boxes {
            self.oriented[i as usize] = b;
        }
        self.upload_oriented(boxes.iter().map(|b| b.0));
        Ok(())
    }

    /// The object's [`OrientedBox`], if it has one.
    pub fn oriented(&self, i: u32) -> Option<OrientedBox> {
        self.oriented.get(i as usize).copied().flatten()
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

    /// Changes how the BVH follows motion from the next change on.
    pub fn set_motion(&mut self, motion: MotionOptions) -> Result<()> {
        check_motion(&motion)?;
        self.motion = motion;
        Ok(())
    }

    /// The motion options in use.
    pub fn motion(&self) -> MotionOptions {
        self.motion
    }

    /// What the last change of objects cost ([`UpdateStats`]).
    pub fn last_update(&self) -> UpdateStats {
        self.last_update
    }

    /// After boxes, flags or slots changed: refit (or rebuild) and upload.
    fn changed(&mut self, t: std::time::Instant) -> Result<()> {
        let mut rebuilt = false;
        let out_of_step = (0..self.objects.count as usize)
            .filter(|&i| {
                let static_live = self.live[i] && !self.is_dynamic(i);
                static_live != self.bvh_leaf(i).is_some()
            })
            .count();
        let live = self.live.iter().filter(|&&l| l).count().max(1);
        let mut growth = 1.0;
        if out_of_step as f64 > self.motion.rebuild_outside * live as f64 {
            self.rebuild_tree()?;
            rebuilt = true;
        } else if self.motion.refit == Refit::Gpu {
            // The GPU refits from the uploaded boxes; the CPU tree keeps its
            // boxes for nothing but the policy, so it is refit too only when
            // the policy needs it: never here (growth unknown).
            self.upload_bounds();
            let mut enc = self.gpu.device.create_command_encoder(&Default::default());
            self.refit_on_gpu(&mut enc, None);
            self.gpu.queue.submit([enc.finish()]);
            self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, sah_growth: None };
            return Ok(());
        } else {
            self.refit_cpu();
            growth = self.sah_growth();
            if growth > self.motion.rebuild_sah_growth {
                self.rebuild_tree()?;
                (rebuilt, growth) = (true, 1.0);
            }
        }
        self.upload_bounds();
        if !rebuilt {
            self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        }
        self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt, sah_growth: Some(growth) };
        Ok(())
    }

    fn is_dynamic(&self, i: usize) -> bool {
        self.objects.flags[i].contains(ObjectFlags::DYNAMIC)
    }

    fn bvh_leaf(&self, i: usize) -> Option<u32> {
        self.bvh.leaf_of_object.get(i).copied().filter(|&l| l != NO_LEAF)
    }

    /// Refits the CPU tree: live static leaves take their boxes, the
    /// others stay frozen.
    fn refit_cpu(&mut self) {
        let (boxes, live, flags) = (&self.boxes, &self.live, &self.objects.flags);
        self.bvh.refit_with(|o| {
            let o = o as usize;
            (live[o] && !flags[o].contains(ObjectFlags::DYNAMIC)).then_some(boxes[o])
        });
    }

    fn sah_growth(&self) -> f64 {
        if self.built_cost > 0.0 {
            self.bvh.sah_cost() / self.built_cost
        } else {
            1.0
        }
    }

    /// Builds the tree over the live static objects and uploads it. A tree
    /// deeper than HROC's stacks is built again with equal-count splits.
    fn rebuild_tree(&mut self) -> Result<()> {
        let members: Vec<u32> = (0..self.objects.count).filter(|&i| self.live[i as usize] && !self.is_dynamic(i as usize)).collect();
        let mut bvh = Bvh::build_subset(&self.boxes, &members, self.split);
        if bvh.depth() > crate::cull::hroc::MAX_DEPTH {
            bvh = Bvh::build_subset(&self.boxes, &members, Split::Eq);
        }
        self.built_cost = bvh.sah_cost();
        self.bvh = bvh;
        self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        self.gpu.queue.write_buffer(&self.leaf_of_object, 0, bytemuck::cast_slice(&self.bvh.leaf_of_object));
        self.generation += 1;
        Ok(())
    }

    /// The GPU bits of slot `i`'s flags.
    fn gpu_flags(&self, i: usize) -> u32 {
        let f = self.objects.flags[i].bits();
        if !self.live[i] {
            REMOVED
        } else if self.is_dynamic(i) || self.bvh_leaf(i).is_none() {
            f | ALONE
        } else {
            f
        }
    }

    fn upload_bounds(&mut self) {
        let bounds: Vec<ObjectBounds> = (0..self.boxes.len()).map(|i| bounds_of(self.boxes[i], self.gpu_flags(i))).collect();
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
    fn upload_oriented(&self, slots: impl IntoIterator<Item = u32>) {
        let (lo, hi) = slots.into_iter().fold(self.oriented_dirty.get(), |(lo, hi), i| (lo.min(i), hi.max(i + 1)));
        self.oriented_dirty.set((lo, hi.min(self.objects.count)));
    }

    /// Writes the marked oriented boxes to the GPU in one write: the range
    /// from the lowest marked slot to the highest (a queue write per slot
    /// costs a staging copy each, and the boxes between are current too).
    /// Every frame and read of them comes after it.
    fn flush_oriented(&self) {
        let (lo, hi) = self.oriented_dirty.replace((u32::MAX, 0));
        if lo >= hi {
            return;
        }
        let part: Vec<OrientedBounds> = self.oriented[lo as usize..hi as usize].iter().map(|&o| oriented_of(o)).collect();
        self.gpu.queue.write_buffer(&self.objects.oriented, lo as u64 * ORIENTED_BYTES, bytemuck::cast_slice(&part));
    }

    fn upload_commands(&mut self) {
        self.gpu.queue.write_buffer(&self.objects.commands, 0, bytemuck::cast_slice(&self.objects.cpu_commands));
    }

    /// Reads the GPU's boxes and tree back after [`Culler::set_bounds_gpu`]
    /// (one wait), so that the CPU can change them again.
    fn sync_boxes(&mut self) -> Result<()> {
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

    /// Records the GPU refit (`refit.wgsl`), from `host` boxes when given.
    fn refit_on_gpu(&mut self, enc: &mut wgpu::CommandEncoder, host: Option<&wgpu::Buffer>) {
        let nodes = self.bvh.nodes.len() as u32;
        let r = self.gpu_refit.get_or_insert_with(|| GpuRefit::new(&self.gpu, self.objects.count));
        r.record(&self.gpu, enc, [self.objects.count, nodes, host.is_some() as u32, 0], host, &self.objects.bounds, &self.bvh_nodes, &self.leaf_of_object);
    }

    /// Doubles the slots (or more): new buffers, every view rebuilt.
    fn grow(&mut self, capacity: u64) -> Result<()> {
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
    pub fn read_nodes(&self) -> Result<Vec<BvhNode>> {
        self.gpu.read(&self.bvh_nodes, 0, self.bvh.nodes.len() as u64)
    }

    /// The oriented boxes the views read, read back from the GPU (one
    /// wait): for tests that they follow their objects.
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

    /// The flags of object `i`; `None` when it is not live.
    pub fn flags(&self, i: u32) -> Option<ObjectFlags> {
        self.is_live(i).then(|| self.objects.flags[i as usize])
    }

    fn check_live(&self, i: u32) -> Result<()> {
        match self.is_live(i) {
            true => Ok(()),
            false if i < self.objects.count => Err(Error::InvalidObject(format!("object {i} was removed (or never added)"))),
            false => Err(Error::InvalidObject(format!("object {i} out of range 0..{}", self.objects.count))),
        }
    }

    /// Sets the flags of object `i` (an object that turns transparent, a
    /// door that starts to move): takes effect from the next frame of every
    /// view. An object turned [`ObjectFlags::DYNAMIC`] leaves the tree's
    /// boxes as they were; one turned static again is refit into its leaf,
    /// or tested on its own until the next rebuild when it has none.
    pub fn set_flags(&mut self, i: u32, flags: ObjectFlags) -> Result<()> {
        self.set_many_flags(&[(i, flags)])
    }

    /// [`Culler::set_flags`] for many objects at once: one refit and one
    /// upload for all of them. Errors on an object that is not live or an
    /// unknown flag; nothing changes then.
    pub fn set_many_flags(&mut self, changes: &[(u32, ObjectFlags)]) -> Result<()> {
        for &(i, f) in changes {
            self.check_live(i)?;
            check_flags(i, f)?;
        }
        let mut motion = false;
        for &(i, f) in changes {
            let was = std::mem::replace(&mut self.objects.flags[i as usize], f);
            motion |= was.contains(ObjectFlags::DYNAMIC) != f.contains(ObjectFlags::DYNAMIC);
        }
        self.update_always();
        if motion {
            let t = std::time::Instant::now();
            self.sync_boxes()?;
            self.moves += 1;
            return self.changed(t);
        }
        for &(i, _) in changes {
            self.gpu.queue.write_buffer(&self.objects.bounds, i as u64 * 32 + 12, bytemuck::bytes_of(&self.gpu_flags(i as usize)));
        }
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
            tally: DrawTally::new(&self.gpu),
            frames: 0,
        })
    }

    fn context<'a>(&'a self, frame: &'a wgpu::Buffer, targets: &'a Targets) -> MethodContext<'a> {
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
        }
    }

    /// The device wrapper the culler records with.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }
}

/// Nodes a tree over `slots` objects can have.
fn node_capacity(slots: u32) -> u32 {
    (2 * slots).saturating_sub(1).max(1)
}

/// The shared buffers of `slots` object slots.
fn allocate(gpu: &Gpu, slots: u32, commands: &[DrawCommand], flags: Vec<ObjectFlags>) -> (SharedObjects, wgpu::Buffer, wgpu::Buffer) {
    use wgpu::BufferUsages as U;
    let n = slots as u64;
    let shared = SharedObjects {
        count: slots,
        bounds: gpu.buffer("hroc object boxes", n * 32, U::STORAGE | U::COPY_DST | U::COPY_SRC),
        oriented: gpu.buffer("hroc oriented boxes", n * ORIENTED_BYTES, U::STORAGE | U::COPY_DST | U::COPY_SRC),
        commands: gpu.buffer_init("hroc commands", bytemuck::cast_slice(commands), U::STORAGE | U::INDIRECT | U::COPY_SRC | U::COPY_DST),
        all_count: gpu.buffer_init("hroc all count", bytemuck::bytes_of(&slots), U::STORAGE | U::INDIRECT | U::COPY_SRC),
        flags,
        cpu_commands: commands.to_vec(),
        always: None,
        always_deferred: gpu.buffer("hroc never-culled non-occluders", n * 4, U::STORAGE | U::COPY_SRC | U::COPY_DST),
    };
    let nodes = gpu.buffer("hroc bvh nodes", node_capacity(slots) as u64 * 32, U::STORAGE | U::COPY_DST | U::COPY_SRC);
    let leaves = gpu.buffer("hroc leaf of object", n * 4, U::STORAGE | U::COPY_DST);
    (shared, nodes, leaves)
}

fn check_capacity(device: &wgpu::Device, n: u64) -> Result<()> {
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

fn check_motion(m: &MotionOptions) -> Result<()> {
    if m.rebuild_sah_growth.is_nan() || m.rebuild_sah_growth < 1.0 || !(0.0..=1.0).contains(&m.rebuild_outside) {
        return Err(Error::InvalidScene(format!("motion options {m:?}: rebuild_sah_growth must be at least 1 and rebuild_outside a fraction")));
    }
    Ok(())
}

/// The host sets only the flags it knows.
fn check_flags(i: u32, f: ObjectFlags) -> Result<()> {
    let known = ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER | ObjectFlags::DYNAMIC;
    match f.bits() & !known.bits() {
        0 => Ok(()),
        bad => Err(Error::InvalidObject(format!("object {i}: unknown flag bits {bad:#x}"))),
    }
}

/// The GPU refit's pipelines and scratch (`refit.wgsl`).
struct GpuRefit {
    layout: wgpu::BindGroupLayout,
    clear: wgpu::ComputePipeline,
    leaves: wgpu::ComputePipeline,
    decode: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    scratch: wgpu::Buffer,
    no_host: wgpu::Buffer,
}

impl GpuRefit {
    fn new(gpu: &Gpu, slots: u32) -> GpuRefit {
        use crate::cull::compact::{storage_entry, uniform_entry};
        use wgpu::BufferUsages as U;
        let layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hroc refit"),
            entries: &[uniform_entry(0), storage_entry(1, true), storage_entry(2, false), storage_entry(3, false), storage_entry(4, true), storage_entry(5, false)],
        });
        let pl = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("hroc refit"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module = gpu.shader("refit.wgsl", &shaders::source("refit.wgsl"));
        GpuRefit {
            clear: gpu.compute_pipeline(&module, "clear", Some(&pl), &[]),
            leaves: gpu.compute_pipeline(&module, "leaves", Some(&pl), &[]),
            decode: gpu.compute_pipeline(&module, "decode", Some(&pl), &[]),
            layout,
            params: gpu.buffer("hroc refit params", 16, U::UNIFORM | U::COPY_DST),
            scratch: gpu.buffer("hroc refit scratch", node_capacity(slots) as u64 * 24, U::STORAGE),
            no_host: gpu.buffer("hroc refit no host boxes", 32, U::STORAGE),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn record(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, params: [u32; 4], host: Option<&wgpu::Buffer>, bounds: &wgpu::Buffer, nodes: &wgpu::Buffer, leaves: &wgpu::Buffer) {
        // Written before the submit that runs these passes.
        gpu.queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&params));
        let bind = gpu.bind_buffers(&self.layout, &[&self.params, host.unwrap_or(&self.no_host), bounds, nodes, leaves, &self.scratch]);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc refit"), timestamp_writes: None });
        pass.set_bind_group(0, &bind, &[]);
        for (p, items) in [(&self.clear, params[1]), (&self.leaves, params[0]), (&self.decode, params[1])] {
            pass.set_pipeline(p);
            let (x, y) = dispatch_size(items.max(1), 256);
            pass.dispatch_workgroups(x, y, 1);
        }
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

/// An oriented box must be finite, non-empty and invertible.
fn check_oriented(i: u32, b: &Option<OrientedBox>) -> Result<()> {
    match b {
        Some(o) if o.to_local().is_none() => Err(Error::InvalidObject(format!("object {i}: oriented box {o:?} is not finite, non-empty and invertible"))),
        _ => Ok(()),
    }
}

const ORIENTED_BYTES: u64 = std::mem::size_of::<OrientedBounds>() as u64;

fn oriented_of(b: Option<OrientedBox>) -> OrientedBounds {
    let Some((o, inv)) = b.and_then(|o| Some((o, o.to_local()?))) else {
        return OrientedBounds::default();
    };
    let m = glam::Mat4::from(inv).transpose();
    let rows = [m.x_axis.to_array(), m.y_axis.to_array(), m.z_axis.to_array()];
    OrientedBounds { rows, min: o.local.min.to_array(), valid: 1, max: o.local.max.to_array(), _pad: 0 }
}

fn bounds_of(b: Aabb, flags: u32) -> ObjectBounds {
    ObjectBounds { min: b.min.to_array(), flags, max: b.max.to_array(), _pad: 0 }
}

fn command(o: &ObjectDesc, i: u32) -> DrawCommand {
    DrawCommand { index_count: o.index_count, instance_count: 1, first_index: o.first_index, base_vertex: o.base_vertex, first_instance: i }
}

/// The layout of every [`Draw::marks`] bind group, from the device alone:
/// one `array<u32>` storage buffer at binding 0, fragment stage, as
/// [`marks_wgsl`] declares it. Put it in the host's pipeline layout at the
/// group [`marks_wgsl`] names; pipelines can so be built before the
/// [`Culler`], and take the bind groups of every culler on the device
/// (wgpu treats layouts with the same entries as one).
pub fn marks_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("hroc marks"), entries: &[marks_entry()] })
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
    /// The pipeline-statistics slot of this draw, if the view counts.
    pub(crate) statistics: PassCount,
}

impl Draw<'_> {
    /// Records the draw into a render pass whose pipeline, vertex and index
    /// buffers and other bind groups the host has set; binds the marks at
    /// `marks_group`. With [`CullerDesc::pipeline_statistics`], the draw
    /// is counted in its stage (a host that records the commands itself
    /// goes uncounted).
    pub fn record(&self, pass: &mut wgpu::RenderPass<'_>, marks_group: u32) {
        self.statistics.around(pass, |pass| {
            pass.set_bind_group(marks_group, self.marks, &[]);
            pass.multi_draw_indexed_indirect_count(self.commands, 0, self.count, 0, self.max_count);
        });
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
    counter: Option<InvocationCounter>,
    last_stages: Vec<(Stage, f64)>,
    /// The culler's BVH generation and slots when this view was built.
    generation: u64,
    slots: u32,
    /// Last frame's eye and view direction, for cut detection.
    last_pose: Option<(glam::Vec3, glam::Vec3)>,
    /// The last frame was culled as after a cut.
    last_cut: bool,
    /// The last frame's submits, waits and bytes read back.
    work: WorkCounts,
    /// Objects and triangles drawn, per frame, read back without waiting.
    tally: DrawTally,
    /// Frames culled so far.
    frames: u64,
}

impl View {
    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// Culls one frame: writes the view's uniform, records the method's
    /// passes into `encoder` and hands `host` every list to draw, in phase
    /// order. The host has cleared its targets before (the crate docs'
    /// clearing rule); it submits `encoder` after. Methods with counter
    /// read-back (`hroc-cr`, `hroc-cr+of`, `ioc`, `oq`, `soq`, `chc++`)
    /// submit `encoder` mid-frame and continue in a new one, which this
    /// call leaves in `*encoder`; the default `hroc` never submits or waits.
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
        let regrown = self.slots != culler.objects.count;
        let rebuilt = self.generation != culler.generation && self.method.keeps_tree();
        if !self.targets.same(&input.targets) || regrown || rebuilt {
            let fresh = culler.view_with(self.method, &input.targets, &self.options)?;
            // Frames keep their numbers across the rebuild.
            *self = View { frames: self.frames, ..fresh };
        }
        if culler.moves > 0 && !self.method.takes_motion() {
            return Err(Error::InvalidScene(format!("{} keeps its own copy of the BVH and takes static scenes only; objects have moved", self.method)));
        }
        if !self.method.takes_dynamic() {
            let outside = (0..culler.objects.count as usize).find(|&i| culler.live[i] && (culler.is_dynamic(i) || culler.bvh_leaf(i).is_none()));
            if let Some(i) = outside {
                return Err(Error::InvalidScene(format!(
                    "{} culls through the BVH alone, and object {i} is outside it (DYNAMIC, or added since the last build): call Culler::rebuild, or use hroc",
                    self.method
                )));
            }
        }
        if input.view.depth != self.targets.depth {
            return Err(Error::InvalidView(format!("view depth {:?} differs from the targets' {:?}", input.view.depth, self.targets.depth)));
        }
        let g = input.view.geometry()?;
        culler.flush_oriented();
        let uniform = g.uniform(self.targets.size, culler.objects.count, culler.bvh.nodes.len() as u32, self.targets.depth);
        culler.gpu.queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&uniform));
        let cut = self.detect_cut(culler, &input.view) || input.cut;
        if cut {
            self.imp.reset(encoder);
        }
        self.last_cut = cut;
        if let Some(t) = self.timer.as_mut() {
            t.begin_frame();
        }
        if let Some(c) = self.counter.as_mut() {
            c.begin_frame();
        }
        // Flags cost nothing until some object has one.
        let split_flags = ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER;
        if self.split.is_none() && culler.objects.flags.iter().any(|f| f.bits() & split_flags.bits() != 0) {
            self.split = Some(FlagSplit::new(&culler.gpu, &culler.objects));
        }
        if let Some(s) = self.split.as_mut() {
            s.begin(encoder, &culler.objects);
        }
        self.work = WorkCounts::default();
        self.tally.begin(&culler.gpu, encoder);
        let mut f = Frame {
            tally: &mut self.tally,
            group_open: false,
            work: &mut self.work,
            gpu: &culler.gpu,
            geometry: g,
            uniform,
            time: input.time,
            objects: &culler.objects,
            targets: &self.targets,
            encoder,
            host,
            timer: self.timer.as_mut(),
            counter: self.counter.as_mut(),
            current: Stage::Draw,
            split: self.split.as_mut(),
            sink: &self.sink,
        };
        if let Some(always) = culler.objects.always.as_ref() {
            f.stage(Stage::FlaggedObjects);
            let statistics = f.pass_count();
            let d = Draw { phase: Phase::Always, commands: &always.commands, count: &always.count, max_count: always.max_count, marks: f.sink, mark: false, statistics };
            f.host.draw(f.encoder, &d);
            f.tally.count(f.gpu, f.encoder, always);
        }
        let recorded = match body {
            Some(body) => body(&mut f),
            None => self.imp.frame(&mut f),
        };
        if let Err(e) = recorded {
            // Leave the host's encoder balanced.
            f.end_group();
            return Err(e);
        }
        if let Some(s) = f.split.take() {
            f.stage(Stage::FlaggedObjects);
            let (enc, q) = f.counted();
            let list = s.finish(enc, &q);
            let statistics = f.pass_count();
            let d = Draw { phase: Phase::NonOccluders, commands: &list.commands, count: &list.count, max_count: list.max_count, marks: f.sink, mark: false, statistics };
            f.host.draw(f.encoder, &d);
            f.tally.count(f.gpu, f.encoder, &list);
        }
        if let Some(t) = f.timer.take() {
            t.end(f.encoder);
        }
        if let Some(c) = f.counter.take() {
            c.end(f.encoder);
        }
        f.end_group();
        let w = *f.work;
        let stats = FrameStats { frame: self.frames, cut, submits: w.submits, waits: w.waits, bytes_read: w.bytes_read, ..Default::default() };
        f.tally.end(f.gpu, f.encoder, stats);
        self.frames += 1;
        Ok(())
    }

    /// The statistics every method shares ([`FrameStats`]: objects and
    /// triangles drawn, cut, submits, waits, bytes read back) of the
    /// newest frame whose counts have come back, without waiting: a
    /// frame's arrive a frame or more after it, tagged with its number.
    /// `None` before the first arrives.
    pub fn frame_stats(&mut self, culler: &Culler) -> Option<FrameStats> {
        self.tally.latest(&culler.gpu)
    }

    /// True when the view turned or moved past the options' cut thresholds
    /// ([`MethodOptions::cut_turn_deg`], [`MethodOptions::cut_move`]) since
    /// the last frame: last frame's visibility says little about this one.
    fn detect_cut(&mut self, culler: &Culler, view: &ViewDesc) -> bool {
        let inv = view.view.inverse();
        let pose = (inv.w_axis.truncate(), -inv.z_axis.truncate().normalize_or_zero());
        let Some((eye, dir)) = self.last_pose.replace(pose) else { return false };
        let turn = dir.dot(pose.1).clamp(-1.0, 1.0).acos().to_degrees();
        let diagonal = if culler.bvh.nodes.is_empty() { f32::INFINITY } else { culler.bvh.aabb(0).extent().length() };
        turn > self.options.cut_turn_deg || eye.distance(pose.0) > self.options.cut_move * diagonal
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

    /// Shader invocations per stage of the last frame, in stage order; empty
    /// without [`CullerDesc::pipeline_statistics`]. Reads back: call after
    /// the frame's work was submitted.
    pub fn stage_invocations(&self, culler: &Culler) -> Result<Vec<(Stage, Invocations)>> {
        let mut v = match self.counter.as_ref() {
            Some(c) => c.read(&culler.gpu)?,
            None => Vec::new(),
        };
        v.sort_by_key(|(s, _)| *s);
        Ok(v)
    }

    /// The method's own statistics of the last frame (set sizes, rays,
    /// ...), for benchmarks and debugging: reads back with a wait, so call
    /// it after the frame's work was submitted. What every method shares
    /// comes without a wait from [`View::frame_stats`].
    pub fn stats(&mut self, culler: &Culler) -> Result<Vec<(Stat, f64)>> {
        let mut s = self.imp.stats(&culler.gpu)?;
        s.push((Stat::Cut, self.last_cut as u32 as f64));
        let w = self.work;
        s.extend([(Stat::Submits, w.submits as f64), (Stat::Waits, w.waits as f64), (Stat::BytesRead, w.bytes_read as f64)]);
        Ok(s)
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

    pub(crate) fn split(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, bounds: &wgpu::Buffer, list: &DrawList, count: &PassCount) -> DrawList {
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
        let (x, y) = dispatch_size(list.max_count, 256);
        count.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(x, y, 1);
        });
        drop(pass);
        DrawList { commands: dst, count: list.count.clone(), max_count: list.max_count }
    }

    /// Non-occluders the method drew this frame, plus the never-culled ones, packed.
    fn finish(&mut self, enc: &mut wgpu::CommandEncoder, count: &PassCount) -> DrawList {
        self.compactor.record(enc, count, &self.job);
        self.list.clone()
    }
}
