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
// and a little more (as HROC's test, hroc_test.wgsl). Over a multisampled
// target the pass rasterizes at its sample count and `box_fs_sample` runs
// once per covered sample, at the sample, against that sample's depth:
// exact per sample, as the attachment's test.
override MANUAL_DEPTH: bool = false;

struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) item: u32,
}

@vertex
fn box_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) slot: u32) -> BoxOut {
    return box_out(v, slot);
}

// The box vertex of `box_fs_sample`.
struct BoxSampleOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) item: u32,
    // Clip z and w, interpolated at each sample: the sample's depth is
    // z / w on every backend, wherever it puts the position builtin.
    @location(1) @interpolate(perspective, sample) zw: vec2<f32>,
}

@vertex
fn box_vs_sample(@builtin(vertex_index) v: u32, @builtin(instance_index) slot: u32) -> BoxSampleOut {
    let o = box_out(v, slot);
    return BoxSampleOut(o.clip, o.item, o.clip.zw);
}

// Box marks (`Marks::Boxes`, the culler marking what a host's list drew
// without the host's shaders): `list` holds the list's indexed draw
// commands (5 u32 each, the object at `first_instance`), one per
// instance; an emptied command draws nothing. A box that reaches the near
// plane (the eye inside it) would lose its fragments to clipping and
// back-face culling: it draws one small triangle on the near plane over
// pixel (0, 0) instead, which passes any depth there, so its object is
// marked, as its own fragments may well have passed.
override COMMANDS: bool = false;

fn box_out(v: u32, slot: u32) -> BoxOut {
    var out: BoxOut;
    var item = 0u;
    if COMMANDS {
        item = list[slot * 5u + 4u];
        if list[slot * 5u + 1u] == 0u {
            out.item = item;
            out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0);
            return out;
        }
    } else {
        item = list[slot];
    }
    let b = padded_box(boxes[item], frame.eye.xyz, pixel_angle(frame));
    out.item = item;
    if COMMANDS && box_in_frustum(frame.planes, b.min, b.max) && crosses_near(frame.near_plane, 0.5 * frame.near, b) {
        // Counter-clockwise in NDC, covering the whole of pixel (0, 0).
        let d = 4.0 * frame.viewport.zw;
        var corner = array<vec2<f32>, 3>(vec2<f32>(-1.0, 1.0 - d.y), vec2<f32>(-1.0 + d.x, 1.0), vec2<f32>(-1.0, 1.0));
        let z = select(0.0, 1.0, frame.reversed != 0u);
        out.clip = select(vec4<f32>(0.0, 0.0, -1.0, 1.0), vec4<f32>(corner[min(v, 2u)], z, 1.0), v < 3u);
        return out;
    }
    if !box_in_frustum(frame.planes, b.min, b.max) || crosses_near(frame.near_plane, 0.5 * frame.near, b) {
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0); // degenerate and clipped: no fragments
        return out;
    }
    out.clip = frame.view_proj * vec4<f32>(box_corner(b, v), 1.0);
    return out;
}

// Box marks rasterize into a target MARKS_SCALE times smaller each way and
// test one pixel of each MARKS_SCALE² block of the host's (a sixteenth of
// the fragments at 4): a box seen only between the pixels tested leaves
// its object unmarked, which every method takes (an unmarked object is
// tested like any other).
override MARKS_SCALE: u32 = 1u;

fn host_pixel(p: vec2<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(depth));
    return min(vec2<i32>(p) * i32(MARKS_SCALE) + i32(MARKS_SCALE / 2u), size - 1);
}

@fragment @early_depth_test(force)
fn box_fs(in: BoxOut) {
    if MANUAL_DEPTH && std_depth(frame, in.clip.z) > farthest_host_depth(depth, host_pixel(in.clip.xy), frame.reversed) + 4e-6 {
        return;
    }
    marks[in.item] = 1u;
}

// `box_fs` without a depth attachment over a multisampled target: one
// invocation per covered sample (sample interpolation makes the stage run
// per sample), comparing the box's depth at the sample with the host's.
@fragment
fn box_fs_sample(in: BoxSampleOut, @builtin(sample_index) s: u32) {
    if std_depth(frame, in.zw.x / in.zw.y) > std_depth(frame, textureLoad(depth, vec2<i32>(in.clip.xy), i32(s)).r) + 4e-6 {
        return;
    }
    marks[in.item] = 1u;
}
