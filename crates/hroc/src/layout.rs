//! `#[repr(C)]` mirrors of the structs in `shaders/common.wgsl`.
//! `tests/shaders.rs` checks every size against naga's layout of the WGSL.

use bytemuck::{Pod, Zeroable};

/// One view's frame, as every culling pass reads it (`Frame` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct FrameUniform {
    /// `proj * view`, column-major.
    pub view_proj: [[f32; 4]; 4],
    /// Near-plane offsets of a pixel ray ([`crate::frustum::ViewGeometry::ray_dirs`]).
    pub ray_dirs: [[f32; 4]; 4],
    /// Origin of a pixel ray ([`crate::frustum::ViewGeometry::ray_origins`]).
    pub ray_origins: [[f32; 4]; 4],
    /// xyz: the eye in world space.
    pub eye: [f32; 4],
    /// width, height, 1/width, 1/height of the depth attachment.
    pub viewport: [f32; 4],
    /// A pixel's size `a + b × distance` ([`crate::frustum::ViewGeometry::footprint`]):
    /// (a, b) of its height, then of the larger of its width and height.
    pub footprint: [f32; 4],
    /// Frustum planes, `n·p + d >= 0` inside, plane 4 the near plane.
    pub planes: [[f32; 4]; 6],
    /// The near plane ([`crate::frustum::ViewGeometry::near_plane`]).
    pub near_plane: [f32; 4],
    /// Objects registered with the culler.
    pub object_count: u32,
    /// Nodes of the object BVH.
    pub node_count: u32,
    /// Distance from the eye to the near plane.
    pub near: f32,
    /// 1 when the host's depth is reversed (near → 1), else 0.
    pub reversed: u32,
}

/// World box of one object (`ObjectBounds` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ObjectBounds {
    /// Minimum corner.
    pub min: [f32; 3],
    /// The object's [`crate::ObjectFlags`] bits.
    pub flags: u32,
    /// Maximum corner.
    pub max: [f32; 3],
    /// Unused.
    pub _pad: u32,
}

/// An object's own box (`OrientedBounds` in WGSL): rows `x`, `y`, `z` map
/// a world point `p` to the object's frame (`dot(x.xyz, p) + x.w`, ...),
/// where the box spans `min` to `max`. `valid` 0: the object has none.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct OrientedBounds {
    /// World-to-local rows.
    pub rows: [[f32; 4]; 3],
    /// Minimum local corner.
    pub min: [f32; 3],
    /// 1 when the object has an oriented box.
    pub valid: u32,
    /// Maximum local corner.
    pub max: [f32; 3],
    /// Unused.
    pub _pad: u32,
}

/// One indexed indirect draw (`VkDrawIndexedIndirectCommand`, the layout of
/// `wgpu::util::DrawIndexedIndirectArgs`); `first_instance` is the object
/// index, so the host's vertex shader reads it as `@builtin(instance_index)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct DrawCommand {
    /// Indices to draw.
    pub index_count: u32,
    /// 1 when drawn; 0 for a command the culler emptied.
    pub instance_count: u32,
    /// First index in the host's index buffer.
    pub first_index: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// The object index.
    pub first_instance: u32,
}

/// `VkDrawIndirectCommand`, for the culler's own box draws.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct DrawArgs {
    /// Vertices per instance (36 per box).
    pub vertex_count: u32,
    /// Boxes.
    pub instance_count: u32,
    /// First vertex.
    pub first_vertex: u32,
    /// First instance (a node or object index).
    pub first_instance: u32,
}

/// Uniform of `shaders/compact.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct CompactParams {
    /// Items in the list.
    pub n: u32,
    /// Blocks of 2048 items, one workgroup each.
    pub blocks: u32,
    /// 0: every non-zero flag selects its item; else only flags equal to it.
    pub select: u32,
    /// Unused.
    pub _pad: u32,
}
