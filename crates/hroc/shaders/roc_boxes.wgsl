// Raster occlusion test of boxes (ROC [KT14, BK15]; IOC runs it per BVH
// level): rasterize each listed box against the depth buffer with forced
// early-Z, depth writes off and a small bias toward the camera; a fragment
// that passes marks its item. `boxes` holds object boxes (ROC, the
// renderer's bounds) or BVH nodes (IOC): both are 32-byte min/max records.
// Boxes that reach the near plane lose fragments to clipping, so the
// compute passes decide them without a test; the vertex stage only drops
// boxes outside the frustum or well across the near plane (a margin of
// near / 2, so it never drops a box the compute passes expect a mark from).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> list: array<u32>;     // items to test, one per instance
@group(0) @binding(2) var<storage, read> boxes: array<BvhNode>;
@group(0) @binding(3) var<storage, read_write> marks: array<u32>; // per item: 1 = a fragment passed
@group(0) @binding(4) var depth: HostDepth;                 // the depth tested against

// With ID marks (no forced early-Z), the pass binds no depth attachment
// and each fragment compares itself, as the attachment's
// LessEqual (GreaterEqual reversed) with its bias toward the camera would,
// and a little more (as HROC's test, hroc_test.wgsl). It rasterizes one
// sample per pixel, at its centre, against the farthest of the pixel's
// samples: over a multisampled target, boxes are padded by half a pixel's
// diagonal more, so a box that covers any sample of a pixel covers its
// centre, nearer there than the geometry at that sample
// (block_pad_px with one-pixel blocks).
override MANUAL_DEPTH: bool = false;

struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) item: u32,
}

@vertex
fn box_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) slot: u32) -> BoxOut {
    let item = list[slot];
    var b = padded_box(boxes[item], frame.eye.xyz, pixel_angle(frame));
    if MANUAL_DEPTH && HOST_SAMPLES > 1u {
        b = padded_box_px(boxes[item], frame.eye.xyz, pixel_angle_xy(frame), block_pad_px(1u));
    }
    var out: BoxOut;
    out.item = item;
    if !box_in_frustum(frame.planes, b.min, b.max) || crosses_near(frame.near_plane, 0.5 * frame.near, b) {
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0); // degenerate and clipped: no fragments
        return out;
    }
    out.clip = frame.view_proj * vec4<f32>(box_corner(b, v), 1.0);
    return out;
}

@fragment @early_depth_test(force)
fn box_fs(in: BoxOut) {
    if MANUAL_DEPTH && std_depth(frame, in.clip.z) > farthest_host_depth(depth, vec2<i32>(in.clip.xy), frame.reversed) + 4e-6 {
        return;
    }
    marks[in.item] = 1u;
}
