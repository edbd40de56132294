// Hi-Z occlusion test, one thread per object (two-phase Hi-Z as in Nanite,
// niagara, Bevy; WOC tests against its warped pyramid the same way).
// The padded box's 8 corners are projected; the pixels its screen rect
// touches are mapped to the finest level where they span at most 2x2
// texels (never a finer one), and all those texels are read. The object
// may be visible when the box's nearest depth is not behind their farthest
// depth (with DEPTH_SLACK: both are rounded). Boxes reaching the near plane are visible without a test (their
// projection is unbounded).
// TWO_PHASE (hzb, late pass): draw what passed and was not in V (drawn in
// the early pass); the result for every object is next frame's V.
// Otherwise (woc): draw what passed.

override TWO_PHASE: bool = true;

struct Mip {
    offset: u32,
    width: u32,
    height: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> bounds: array<BvhNode>; // object boxes (ObjectBounds layout)
@group(0) @binding(2) var<storage, read> mips: array<Mip>;
@group(0) @binding(3) var<storage, read> hiz: array<f32>;
@group(0) @binding(4) var<storage, read_write> visible: array<u32>; // V (TWO_PHASE)
@group(0) @binding(5) var<storage, read_write> fresh: array<u32>;   // to draw now
@group(0) @binding(6) var<storage, read_write> stats: array<atomic<u32>>; // tested, near plane

var<workgroup> counts: array<atomic<u32>, 2>;

fn hiz_visible(b: Box) -> bool {
    var lo = vec3<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    for (var c = 0u; c < 8u; c++) {
        let p = select(b.min, b.max, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u));
        let clip = frame.view_proj * vec4<f32>(p, 1.0);
        let ndc = clip.xyz / clip.w;
        lo = min(lo, vec3<f32>(ndc.xy, std_depth(frame, ndc.z)));
        hi = max(hi, ndc.xy);
    }
    // Pixel rect, y down; every pixel it touches.
    let size = frame.viewport.xy;
    let r0 = vec2<f32>(lo.x * 0.5 + 0.5, 0.5 - hi.y * 0.5) * size;
    let r1 = vec2<f32>(hi.x * 0.5 + 0.5, 0.5 - lo.y * 0.5) * size;
    let p0 = vec2<u32>(clamp(floor(r0), vec2<f32>(0.0), size - 1.0));
    let p1 = vec2<u32>(clamp(floor(r1), vec2<f32>(0.0), size - 1.0));
    // The coarsest level where the rect spans at most 2x2 texels. A level's
    // side is the full side halved l times, at least 1 (mip_chain); the
    // loop computes it rather than loading `mips[l]`, and loads the level
    // once after: llvmpipe's GL compiles a struct loaded from storage in
    // the loop to the first iteration's value after it (measured: hzb then
    // culled visible objects on GL only).
    let levels = arrayLength(&mips);
    let full = vec2<u32>(mips[0].width, mips[0].height);
    var l = 0u;
    loop {
        let last = max(full >> vec2<u32>(l), vec2<u32>(1u)) - 1u;
        let t = min(p1 >> vec2<u32>(l), last) - min(p0 >> vec2<u32>(l), last);
        if all(t <= vec2<u32>(1u)) || l + 1u >= levels {
            break;
        }
        l++;
    }
    let m = mips[l];
    let last = vec2<u32>(m.width, m.height) - 1u;
    let t0 = min(p0 >> vec2<u32>(l), last);
    let t1 = min(p1 >> vec2<u32>(l), last);
    var far = 0.0;
    for (var y = t0.y; y <= t1.y; y++) {
        for (var x = t0.x; x <= t1.x; x++) {
            far = max(far, hiz[m.offset + y * m.width + x]);
        }
    }
    return lo.z <= far + DEPTH_SLACK;
}

@compute @workgroup_size(256)
fn test(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i < frame.object_count {
        let b = padded_box(bounds[i], frame.eye.xyz, pixel_angle(frame));
        var vis = false;
        if box_in_frustum(frame.planes, b.min, b.max) {
            if crosses_near(frame.near_plane, frame.near, b) {
                vis = true;
                atomicAdd(&counts[1], 1u);
            } else {
                vis = hiz_visible(b);
                atomicAdd(&counts[0], 1u);
            }
        }
        if TWO_PHASE {
            fresh[i] = select(0u, 1u, vis && visible[i] == 0u);
            visible[i] = select(0u, 1u, vis);
        } else {
            fresh[i] = select(0u, 1u, vis);
        }
    }
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&stats[0], atomicLoad(&counts[0]));
        atomicAdd(&stats[1], atomicLoad(&counts[1]));
    }
}
