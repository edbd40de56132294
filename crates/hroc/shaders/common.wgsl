// STACK, STAT_SLOTS and HOST_SAMPLES come before this header, written from
// their Rust constants, with the aliases HostDepth and HostIds: the host's
// targets, one sample per pixel (texture_2d) or several
// (texture_multisampled_2d) (src/shaders.rs).
// Shared layouts, prepended to every pass (src/layout.rs mirrors them;
// tests/shaders.rs checks the sizes).

struct Frame {
    view_proj: mat4x4<f32>,
    // Columns x, y, z: the near-plane offsets of a pixel ray (dir =
    // ray_dirs * (ndc.x, ndc.y, 1, 0) reaches the near plane at t = 1),
    // built from the camera basis: unprojecting through the inverse
    // view-projection loses the direction to cancellation.
    ray_dirs: mat4x4<f32>,
    // Origin of the pixel ray through NDC (x, y): ray_origins * (x, y, 0, 1);
    // the eye for a perspective view, a point on a plane for an
    // orthographic one.
    ray_origins: mat4x4<f32>,
    eye: vec4<f32>,          // xyz: camera position
    viewport: vec4<f32>,     // width, height, 1/width, 1/height
    // A pixel's size at distance d from the eye is a + b d: (a, b) of its
    // height, then of the larger of its width and height (perspective:
    // a = 0; orthographic: b = 0).
    footprint: vec4<f32>,
    planes: array<vec4<f32>, 6>, // frustum planes, n·p + d >= 0 inside
    // The near plane (planes[4], but for unclipped depth, where planes[4]
    // culls nothing): boxes reaching it are drawn untested.
    near_plane: vec4<f32>,
    object_count: u32,
    node_count: u32,
    near: f32,
    reversed: u32,           // 1: the host's depth is reversed (near 1, far 0)
}

// The passes compare depth in standard form (near 0, far 1): a reversed
// depth d reads as 1 - d. Rounding keeps the order, so every comparison
// stays conservative.
fn std_depth(f: Frame, d: f32) -> f32 {
    return select(d, 1.0 - d, f.reversed != 0u);
}

// What a depth computed in a shader (a box corner's, a ray's, projected
// through the view-projection in f32) may lie behind the rasterizer's depth
// of the same point: several ulps of standard depth near 1, where a far
// object can stand one ulp in front of the ground behind it (measured:
// hzb culled a kiosk 3 km away on radial-city's hard path without it).
// Added to the occlusion map's depth, it keeps the tests conservative at
// the precision limit on every path measured; it is a measured margin (8
// ulps at 1), not a bound derived for every coordinate range.
const DEPTH_SLACK: f32 = 4e-7;

// The farthest of the host depth's samples at pixel p, in standard form
// (`reversed`: the texture holds reversed depth). Whatever reduces or
// compares against the host's depth keeps a pixel's farthest sample: what
// lies in front of it lies in front of every sample. One sample: mip 0.
fn farthest_host_depth(t: HostDepth, p: vec2<i32>, reversed: u32) -> f32 {
    var far = 0.0;
    for (var s = 0; s < i32(HOST_SAMPLES); s++) {
        let d = textureLoad(t, p, s).r;
        far = max(far, select(d, 1.0 - d, reversed != 0u));
    }
    return far;
}

// The object at sample s of pixel p of the ID target: its index + 1, 0
// where nothing was drawn. `R32Uint` holds it in r; `Rg16Uint` (which
// every backend can multisample) in r, the low 16 bits, and g, the high.
fn host_id(t: HostIds, p: vec2<i32>, s: i32) -> u32 {
    let v = textureLoad(t, p, s);
    return v.r | (v.g << 16u);
}

struct ObjectBounds {
    min: vec3<f32>,
    flags: u32,   // ObjectFlags bits (src/host.rs)
    max: vec3<f32>,
    _pad: u32,
}

const NEVER_CULL: u32 = 1u;
const NOT_OCCLUDER: u32 = 2u;
const DYNAMIC: u32 = 4u;
const CUTOUT: u32 = 8u;
// Set by the culler, never by the host: the object is tested on its own,
// from its object box (DYNAMIC, or not in the BVH since the last build),
// and the object's slot is empty (its command draws nothing).
const ALONE: u32 = 0x40000000u;
const REMOVED: u32 = 0x80000000u;
// The host's flags that take an object out of a method's lists (CUTOUT
// moves it to the list's cutout list).
const SPLIT_FLAGS: u32 = 3u;

// Object-level BVH node (src/bvh): children of an interior node sit at
// child and child + 1; a leaf has LEAF_BIT set and the object in the rest.
struct BvhNode {
    min: vec3<f32>,
    child: u32,
    max: vec3<f32>,
    parent: u32,
}

const LEAF_BIT: u32 = 0x80000000u;

// Child pairs start at odd indices (src/bvh validates it): O(1) sibling.
fn sibling(n: u32) -> u32 {
    return select(n - 1u, n + 1u, (n & 1u) == 1u);
}

// 1/d for a ray slab test, with d = 0 nudged to a tiny value of its sign.
fn safe_inv(d: f32) -> f32 {
    return 1.0 / select(d, select(-1e-30, 1e-30, d >= 0.0), abs(d) < 1e-30);
}

// Slab test of the ray eye + t * dir (inv = 1 / dir) against a box: the
// parameters where the ray enters and leaves it (enter > leave: a miss).
fn ray_box(eye: vec3<f32>, inv: vec3<f32>, bmin: vec3<f32>, bmax: vec3<f32>) -> vec2<f32> {
    let t0 = (bmin - eye) * inv;
    let t1 = (bmax - eye) * inv;
    return vec2<f32>(max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)), min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z)));
}

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
// The pixel at the centre of `cell` of a grid of `cells` (columns, rows)
// over a viewport of `size` pixels.
fn grid_cell_pixel(cell: u32, cells: vec2<u32>, size: vec2<f32>) -> vec2<i32> {
    let uv = vec2<f32>((f32(cell % cells.x) + 0.5) / f32(cells.x), (f32(cell / cells.x) + 0.5) / f32(cells.y));
    return min(vec2<i32>(uv * size), vec2<i32>(size) - 1);
}

fn flat_id(wid: vec3<u32>, nwg: vec3<u32>, lid: u32, size: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * size + lid;
}

// Indirect draw arguments (VkDrawIndirectCommand), for box draws.
struct DrawArgs {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
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

struct Box {
    min: vec3<f32>,
    max: vec3<f32>,
}

// Box padding in pixels at the far corner: 16 times the 1/256-pixel vertex
// snapping of common rasterizers.
const PIXEL_PAD: f32 = 0.0625;

// A pixel's height at distance d from the eye: a + b d (`footprint`).
fn pixel_angle(f: Frame) -> vec2<f32> {
    return f.footprint.xy;
}

// The origin of the pixel ray through NDC `ndc`.
fn ray_origin(f: Frame, ndc: vec2<f32>) -> vec3<f32> {
    return (f.ray_origins * vec4<f32>(ndc, 0.0, 1.0)).xyz;
}

// A node's box grown so that rasterizing it, or casting a ray into it,
// never loses a pixel that the geometry inside covers: a fraction of a pixel at the
// box's farthest corner (rasterizers snap vertices to a sub-pixel grid, so
// a face lying on the surface it bounds can lose an edge pixel), plus a
// little for float rounding.
fn padded_box(n: BvhNode, eye: vec3<f32>, pixel: vec2<f32>) -> Box {
    return padded_box_px(n, eye, pixel, PIXEL_PAD);
}

// padded_box with `px` pixels of padding at the farthest corner.
fn padded_box_px(n: BvhNode, eye: vec3<f32>, pixel: vec2<f32>, px: f32) -> Box {
    let pad = box_pad(n, eye, pixel, px);
    return Box(n.min - vec3<f32>(pad), n.max + vec3<f32>(pad));
}

// The world distance padded_box_px grows a node's box by.
fn box_pad(n: BvhNode, eye: vec3<f32>, pixel: vec2<f32>, px: f32) -> f32 {
    let far = length(max(abs(n.min - eye), abs(n.max - eye)));
    let scale = max(max(abs(n.min.x), abs(n.min.y)), max(max(abs(n.min.z), abs(n.max.x)), max(abs(n.max.y), abs(n.max.z))));
    return px * (pixel.x + pixel.y * far) + 1e-4 * length(n.max - n.min) + 1e-6 * (scale + length(eye)) + 1e-7;
}

// An object's box in its own frame (src/layout.rs OrientedBounds): rows x,
// y, z map a world point p to the frame (dot(x.xyz, p) + x.w, ...).
struct OrientedBounds {
    x: vec4<f32>,
    y: vec4<f32>,
    z: vec4<f32>,
    min: vec3<f32>,
    valid: u32,   // 0: the object has none
    max: vec3<f32>,
    _pad: u32,
}

// The span of the ray eye + t * dir inside an object's own box grown so
// that it holds the ball of radius `pad` (world units) around each of its
// points: a world step of length r moves local coordinate i by at most
// r * |row i|. An affine map keeps the ray parameter t, so the span compares
// with world spans directly. Without a box: the whole ray.
fn ray_oriented(o: OrientedBounds, eye: vec3<f32>, dir: vec3<f32>, pad: f32) -> vec2<f32> {
    if o.valid == 0u {
        return vec2<f32>(-3.0e38, 3.0e38);
    }
    let e = vec3<f32>(dot(o.x.xyz, eye) + o.x.w, dot(o.y.xyz, eye) + o.y.w, dot(o.z.xyz, eye) + o.z.w);
    let d = vec3<f32>(dot(o.x.xyz, dir), dot(o.y.xyz, dir), dot(o.z.xyz, dir));
    // Rounding of the map grows with the coordinates it carries.
    let size = max(max(abs(o.min), abs(o.max)), abs(e));
    let g = pad * vec3<f32>(length(o.x.xyz), length(o.y.xyz), length(o.z.xyz)) + 1e-4 * length(o.max - o.min) + 1e-6 * size;
    let inv = vec3<f32>(safe_inv(d.x), safe_inv(d.y), safe_inv(d.z));
    return ray_box(e, inv, o.min - g, o.max + g);
}

// HROC's occlusion test at a coarser resolution: one box fragment and one
// ray per block of scale × scale pixels, through the block's centre, against
// the farthest depth of the block. Any ray through a pixel centre of the
// block passes within (scale - 1) / √2 pixels of the block's ray, so a box
// padded by that much at its farthest corner (the box grown by a ball of
// that radius) is entered by the block's ray no later than by the pixel's
// (depth depends on t alone: t = 1 on the near plane for every ray), plus
// the snapping slack of the block-sized pixels the test rasterizes. With
// several samples per pixel, a sample may lie anywhere in its pixel, and
// any ray through one passes within scale / √2 pixels of the block's ray.
fn block_pad_px(scale: u32) -> f32 {
    let spread = select(f32(scale - 1u), f32(scale), HOST_SAMPLES > 1u);
    return spread * 0.70710678 + f32(scale) * PIXEL_PAD;
}

// pixel_angle over both axes, for pixels that may not be square.
fn pixel_angle_xy(f: Frame) -> vec2<f32> {
    return f.footprint.zw;
}

// True when the box reaches within `frame.near` of the near plane or behind
// it (this includes every box that holds the eye). Such a box loses
// fragments to clipping, so it cannot be tested by rasterization (§6).
fn crosses_near(p: vec4<f32>, near: f32, b: Box) -> bool {
    let v = select(b.max, b.min, p.xyz >= vec3<f32>(0.0)); // nearest corner
    return dot(p.xyz, v) + p.w <= near;
}

// Corner c of a box is (c & 1, c & 2, c & 4); the 12 triangles wind
// counter-clockwise seen from outside (hroc-bench tests/hroc.rs checks), so back-face
// culling keeps the faces nearest the eye.
const CUBE: array<u32, 36> = array<u32, 36>(
    0u, 4u, 6u, 0u, 6u, 2u, // -x
    1u, 3u, 7u, 1u, 7u, 5u, // +x
    0u, 1u, 5u, 0u, 5u, 4u, // -y
    2u, 6u, 7u, 2u, 7u, 3u, // +y
    0u, 2u, 3u, 0u, 3u, 1u, // -z
    4u, 5u, 7u, 4u, 7u, 6u, // +z
);

// Vertex v (0..36) of a box drawn as 12 triangles without an index buffer.
fn box_corner(b: Box, v: u32) -> vec3<f32> {
    let c = CUBE[v];
    return select(b.min, b.max, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u));
}

// Threads of a workgroup that scans (`workgroup_scan`).
const SCAN_WG: u32 = 256u;
var<workgroup> scan: array<u32, SCAN_WG>;

// Inclusive scan of `v` across the workgroup (Hillis–Steele), for the
// ordered compactions of workgroups of SCAN_WG threads (`compact.wgsl`,
// `set_frustum.wgsl`): `scan` then holds every thread's running sum, the
// workgroup's total last.
fn workgroup_scan(lid: u32, v: u32) -> u32 {
    scan[lid] = v;
    workgroupBarrier();
    for (var d = 1u; d < SCAN_WG; d = d << 1u) {
        var x = 0u;
        if lid >= d {
            x = scan[lid - d];
        }
        workgroupBarrier();
        scan[lid] += x;
        workgroupBarrier();
    }
    return scan[lid];
}
