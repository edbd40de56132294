// Shared layouts, prepended to every pass (src/render/layout.rs mirrors them;
// tests/shaders.rs checks the sizes).

struct Frame {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,          // xyz: camera position
    light_dir: vec4<f32>,    // xyz: direction towards the light
    viewport: vec4<f32>,     // width, height, 1/width, 1/height
    planes: array<vec4<f32>, 6>, // frustum planes, n·p + d >= 0 inside
    object_count: u32,
    node_count: u32,
    near: f32,
    far: f32,
}

struct ObjectData {
    model: mat4x4<f32>,
    color: vec4<f32>,
}

struct ObjectBounds {
    min: vec3<f32>,
    _pad0: u32,
    max: vec3<f32>,
    _pad1: u32,
}

// Object-level BVH node (src/bvh): children of an interior node sit at
// child and child + 1; a leaf has LEAF_BIT set and the object in the rest.
struct BvhNode {
    min: vec3<f32>,
    child: u32,
    max: vec3<f32>,
    parent: u32,
}

const LEAF_BIT: u32 = 0x80000000u;

// VkDrawIndexedIndirectCommand; first_instance carries the object id.
struct DrawCommand {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

// Flat invocation index of a 1D launch spread over a 2D grid of workgroups
// (gpu::dispatch_size), so more than 65535 * 256 items fit.
fn flat_id(wid: vec3<u32>, nwg: vec3<u32>, lid: u32, size: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * size + lid;
}

// Conservative box-vs-frustum test (positive vertex per plane).
fn box_in_frustum(planes: array<vec4<f32>, 6>, bmin: vec3<f32>, bmax: vec3<f32>) -> bool {
    for (var i = 0u; i < 6u; i++) {
        let p = planes[i];
        let v = select(bmin, bmax, p.xyz >= vec3<f32>(0.0));
        if dot(p.xyz, v) + p.w < 0.0 {
            return false;
        }
    }
    return true;
}
