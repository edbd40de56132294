//! `#[repr(C)]` mirrors of the structs in `shaders/common.wgsl`.
//! `tests/shaders.rs` checks every size against naga's layout of the WGSL.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
    pub ray_dirs: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub light_dir: [f32; 4],
    pub viewport: [f32; 4],
    pub planes: [[f32; 4]; 6],
    pub object_count: u32,
    pub node_count: u32,
    pub near: f32,
    pub far: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ObjectData {
    pub model: [[f32; 4]; 4],
    pub color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ObjectBounds {
    pub min: [f32; 3],
    pub _pad0: u32,
    pub max: [f32; 3],
    pub _pad1: u32,
}

/// `VkDrawIndexedIndirectCommand`; `first_instance` is the object id.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct DrawCommand {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    pub base_vertex: i32,
    pub first_instance: u32,
}

/// `VkDrawIndirectCommand` (box draws).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct DrawArgs {
    pub vertex_count: u32,
    pub instance_count: u32,
    pub first_vertex: u32,
    pub first_instance: u32,
}

/// Uniform of `shaders/compact.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct CompactParams {
    pub n: u32,
    pub blocks: u32,
    pub _pad: [u32; 2],
}

/// Every (WGSL struct name, Rust size) pair the shader test checks.
pub fn mirrored_sizes() -> Vec<(&'static str, usize)> {
    use std::mem::size_of;
    vec![
        ("Frame", size_of::<FrameUniform>()),
        ("ObjectData", size_of::<ObjectData>()),
        ("ObjectBounds", size_of::<ObjectBounds>()),
        ("DrawCommand", size_of::<DrawCommand>()),
        ("DrawArgs", size_of::<DrawArgs>()),
        ("BvhNode", size_of::<crate::bvh::BvhNode>()),
    ]
}
