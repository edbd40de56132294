//! The objects a host registers: their flags, descriptions, GPU buffers
//! and the per-object checks.

use crate::aabb::OrientedBox;
use crate::contract::DrawList;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::layout::{DrawCommand, ObjectBounds, OrientedBounds};
use crate::Aabb;

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
    /// are handed back in [`Phase::NonOccluders`](crate::Phase::NonOccluders), after the opaque phases.
    pub const NOT_OCCLUDER: ObjectFlags = ObjectFlags(2);
    /// Moves most frames (a vehicle, a character): kept out of the BVH and
    /// tested on its own box, so that moving it costs no refit (HROC §6's
    /// hybrid). Static objects may move too; they are refit into the BVH.
    pub const DYNAMIC: ObjectFlags = ObjectFlags(4);
    /// Occludes, and its fragment shader discards (alpha-tested foliage,
    /// fences): it writes depth only where it is drawn, and cannot force
    /// early-Z. Such objects come in lists of their own
    /// ([`Draw::cutout`](crate::Draw::cutout)), right after each list of
    /// their phase: draw them with the alpha-tested pipeline, depth test
    /// and writes on (and IDs, where the view has an ID target), without
    /// `@early_depth_test(force)` and without `hroc_mark`. The culler marks
    /// them itself (from their boxes, or from the ID target with
    /// [`Marks::Ids`](crate::device::Marks::Ids)), so they occlude as
    /// any other object.
    pub const CUTOUT: ObjectFlags = ObjectFlags(8);

    /// The raw bits (`ObjectBounds::flags`, WGSL `NEVER_CULL`/`NOT_OCCLUDER`/`DYNAMIC`/`CUTOUT`).
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

/// GPU-only bits of `ObjectBounds::flags` (`ALONE`, `REMOVED` in common.wgsl).
pub(super) const ALONE: u32 = 0x4000_0000;
pub(super) const REMOVED: u32 = 0x8000_0000;

/// Object buffers shared by every view of a [`Culler`].
pub(crate) struct SharedObjects {
    /// Object slots (the culler's capacity): every per-object buffer and
    /// pass covers them; empty slots draw nothing.
    pub count: u32,
    /// Live objects tested alone (`ALONE`: DYNAMIC, or outside the BVH),
    /// as the bounds last uploaded flag them.
    pub alone: u32,
    pub bounds: wgpu::Buffer,
    /// `OrientedBounds` per slot (`valid` 0 where the host gave none).
    pub oriented: wgpu::Buffer,
    pub commands: wgpu::Buffer,
    /// Bumped by every upload of `commands`: lists packed from them
    /// before are stale.
    pub commands_version: u64,
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

/// The host sets only the flags it knows.
pub(super) fn check_flags(i: u32, f: ObjectFlags) -> Result<()> {
    let known = ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER | ObjectFlags::DYNAMIC | ObjectFlags::CUTOUT;
    match f.bits() & !known.bits() {
        0 => Ok(()),
        bad => Err(Error::InvalidObject(format!("object {i}: unknown flag bits {bad:#x}"))),
    }
}

/// An object's box must be finite and non-empty: every test and ray against
/// it assumes so.
pub(super) fn check_box(i: u32, b: &Aabb) -> Result<()> {
    if !b.min.is_finite() || !b.max.is_finite() || b.is_empty() {
        return Err(Error::InvalidObject(format!("object {i}: bounds {b:?} are not a finite non-empty box")));
    }
    Ok(())
}

/// An object's indices must lie within the host's index buffer, where the
/// host declared its size ([`crate::CullerDesc::index_count`]).
pub(super) fn check_indices(i: u32, o: &ObjectDesc, index_count: Option<u32>) -> Result<()> {
    let end = o.first_index as u64 + o.index_count as u64;
    match index_count {
        Some(n) if end > n as u64 => Err(Error::InvalidObject(format!(
            "object {i}: its indices {}..{end} lie past the host's index buffer of {n} indices (CullerDesc::index_count): give each object its own first_index and index_count within the buffer it is drawn from",
            o.first_index
        ))),
        _ => Ok(()),
    }
}

/// An oriented box must be finite, non-empty and invertible.
pub(super) fn check_oriented(i: u32, b: &Option<OrientedBox>) -> Result<()> {
    match b {
        Some(o) if o.to_local().is_none() => Err(Error::InvalidObject(format!("object {i}: oriented box {o:?} is not finite, non-empty and invertible"))),
        _ => Ok(()),
    }
}

pub(super) const ORIENTED_BYTES: u64 = std::mem::size_of::<OrientedBounds>() as u64;

pub(super) fn oriented_of(b: Option<OrientedBox>) -> OrientedBounds {
    let Some((o, inv)) = b.and_then(|o| Some((o, o.to_local()?))) else {
        return OrientedBounds::default();
    };
    let m = glam::Mat4::from(inv).transpose();
    let rows = [m.x_axis.to_array(), m.y_axis.to_array(), m.z_axis.to_array()];
    OrientedBounds { rows, min: o.local.min.to_array(), valid: 1, max: o.local.max.to_array(), _pad: 0 }
}

pub(super) fn bounds_of(b: Aabb, flags: u32) -> ObjectBounds {
    ObjectBounds { min: b.min.to_array(), flags, max: b.max.to_array(), _pad: 0 }
}

pub(super) fn command(o: &ObjectDesc, i: u32) -> DrawCommand {
    DrawCommand { index_count: o.index_count, instance_count: 1, first_index: o.first_index, base_vertex: o.base_vertex, first_instance: i }
}

/// Nodes a tree over `slots` objects can have.
pub(crate) fn node_capacity(slots: u32) -> u32 {
    (2 * slots).saturating_sub(1).max(1)
}

/// The shared buffers of `slots` object slots.
pub(crate) fn allocate(gpu: &Gpu, slots: u32, commands: &[DrawCommand], flags: Vec<ObjectFlags>) -> (SharedObjects, wgpu::Buffer, wgpu::Buffer) {
    use wgpu::BufferUsages as U;
    let n = slots as u64;
    let shared = SharedObjects {
        count: slots,
        alone: 0,
        bounds: gpu.buffer("hroc object boxes", n * 32, U::STORAGE | U::COPY_DST | U::COPY_SRC),
        oriented: gpu.buffer("hroc oriented boxes", n * ORIENTED_BYTES, U::STORAGE | U::COPY_DST | U::COPY_SRC),
        commands: gpu.buffer_init("hroc commands", bytemuck::cast_slice(commands), U::STORAGE | U::INDIRECT | U::COPY_SRC | U::COPY_DST),
        commands_version: 0,
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
