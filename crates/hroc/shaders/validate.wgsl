// Validation (`CullerDesc::validation`, src/validation.rs): checks on the
// GPU, without waiting, that the host's draws kept the host contract.
//
// The host's draws of a frame come in groups: consecutive lists of one
// phase, which the host marks into one buffer or not at all. Every list's objects are
// stamped with the frame's tag and their group (`stamp`); after a group
// with the host's marks, its marked objects are stamped too (`marks`). The
// depth and IDs are read after each group (`check_pixels`), which compares
// them with what the last read saw (after the first group, with the
// cleared targets): drawing only brings depth nearer and never writes ID
// 0. The frame's last read (FINAL) checks every sample's ID: in range,
// naming an object an occluding list drew this frame, and not in front of
// that object's box along the pixel's ray. A view without IDs checks every
// drawn sample against the boxes of all the objects the frame drew
// instead (`box_entries`): not in front of where its ray enters the
// nearest, and names the drawn box nearest the sample (`suspect`). After a
// group with the host's marks, `late_marks` looks for marks no passing
// fragment made. Before the frame's first draw (BEGIN, where the host
// clears before the culler's frame), the targets must hold their cleared
// values.
//
// What each check found is counted per kind, with its first example, in
// `results`, which the view reads back a frame or two later.

// Kinds of finding (src/validation.rs `Kind`, in this order).
const DEPTH_FARTHER: u32 = 0u;
const IDS_CLEARED: u32 = 1u;
const ID_RANGE: u32 = 2u;
const ID_NOT_DRAWN: u32 = 3u;
const OUTSIDE_BOX: u32 = 4u;
const DEPTH_WITHOUT_ID: u32 = 5u;
const MISSING_MARK: u32 = 6u;
const HIDDEN_MARK: u32 = 7u;
const INDEX_FOR_ID: u32 = 8u;
const NOT_CLEARED: u32 = 9u;
const BEFORE_BOXES: u32 = 10u;
const KINDS: u32 = 11u;
// Groups of draws a frame tells apart (later ones share the last).
const GROUPS: u32 = 32u;
// No object, pixel or group.
const NONE: u32 = 0xffffffffu;

// `Check::mode` bits. FIRST: the group is the frame's first, which the
// cleared targets (far depth, ID 0) precede.
const FIRST: u32 = 1u;
const CHECK_IDS: u32 = 2u;
const HOST_MARKS: u32 = 4u;
const FINAL: u32 = 8u;
// Before the frame's first draw: the targets hold their cleared values.
const BEGIN: u32 = 16u;
// Without IDs, the frame's last read compares with the drawn boxes
// (`box_entries`).
const BOXES: u32 = 32u;

// src/validation.rs CheckUniform.
struct Check {
    // The frame's tag: bits 8.. of a stamp.
    tag: u32,
    // The group checked or marked.
    group: u32,
    mode: u32,
    // Bits of an object index in `results.suspect` (`suspect`).
    object_bits: u32,
    // The pixels the frame reads: one in stride × stride, from offset.
    offset: vec2<u32>,
    stride: u32,
    // The objects `late_marks` checks: one in object_stride, a different
    // one each frame.
    object_stride: u32,
}

struct Finding {
    count: atomic<u32>,
    object: u32,
    // x | y << 16
    pixel: u32,
    group: u32,
}

struct Results {
    findings: array<Finding, KINDS>,
    // 1 where a group changed the depth or ID of some pixel.
    changed: array<u32, GROUPS>,
    // Objects a group drew and marked.
    marked: array<atomic<u32>, GROUPS>,
    // BEFORE_BOXES: the drawn box nearest its sample, as the complement
    // of the distance's f32 bits (their top 32 - object_bits) over the
    // object's index (`suspect`): the greatest is the nearest.
    suspect: atomic<u32>,
    _pad: array<u32, 3>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> check: Check;
@group(0) @binding(2) var<storage, read_write> results: Results;
// Per object: tag << 8 | AGAIN | MARKING | group.
const AGAIN: u32 = 0x80u;   // drawn before in the frame
const MARKING: u32 = 0x40u; // drawn by a list whose marks the host writes
const GROUP: u32 = 0x3fu;
@group(0) @binding(3) var<storage, read_write> stamps: array<u32>;
// Per object: tag << 8 | group, when the group marked it.
@group(0) @binding(4) var<storage, read_write> marked: array<u32>;
// Per pixel read (`check_pixels`), two words: the farthest sample's
// standard depth (f32 bits), and sample 0's ID; in a view without IDs,
// the second is the frame's nearest entry into a drawn box along the
// pixel's ray (`box_entries`: ENTRY_NONE less the standard depth's bits,
// 0 for none), reset by the frame's last read.
@group(0) @binding(5) var<storage, read_write> shadow: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(7) var<storage, read> oriented: array<OrientedBounds>;
@group(0) @binding(8) var depth: HostDepth;
@group(0) @binding(9) var ids: HostIds;
// The group's marks (the method's buffer).
@group(0) @binding(10) var<storage, read> marks: array<u32>;
// A list handed to the host.
@group(0) @binding(12) var<storage, read> commands: array<DrawCommand>;
@group(0) @binding(13) var<storage, read> count: array<u32>;
// Per object: the place of the list that drew it among the frame's lists.
@group(0) @binding(14) var<storage, read_write> order: array<u32>;
// Per object: tag << 8 | group, when it owned a sample after the group
// that drew it with the host's marks.
@group(0) @binding(15) var<storage, read_write> owned: array<u32>;
// The list `stamp` stamps: its group, and its place among the frame's lists.
struct Stamping {
    group: u32,
    list: u32,
    // The host marks the list.
    marking: u32,
    _pad: u32,
}
@group(0) @binding(16) var<uniform> stamping: Stamping;

fn found(kind: u32, object: u32, pixel: u32, group: u32) {
    if atomicAdd(&results.findings[kind].count, 1u) == 0u {
        results.findings[kind].object = object;
        results.findings[kind].pixel = pixel;
        results.findings[kind].group = group;
    }
}

// Stamps the objects a list draws with the frame's tag and the group.
// A few threads stride over the list (a CPU rasterizer pays per thread).
@compute @workgroup_size(64)
fn stamp(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let end = min(count[0], arrayLength(&commands));
    for (var i = gid.x; i < end; i += nwg.x * 64u) {
        let c = commands[i];
        let o = c.first_instance;
        if c.instance_count == 0u || c.index_count == 0u || o >= arrayLength(&stamps) {
            continue;
        }
        let again = select(0u, AGAIN, (stamps[o] >> 8u) == check.tag);
        stamps[o] = (check.tag << 8u) | again | select(0u, MARKING, stamping.marking != 0u) | min(stamping.group, GROUPS - 1u);
        order[o] = stamping.list;
    }
}

// After a group drawn with the host's marks: stamps the objects it drew
// and marked. Threads stride over the objects.
@compute @workgroup_size(64)
fn marks_of_group(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let mine = (check.tag << 8u) | check.group;
    for (var o = gid.x; o < min(arrayLength(&stamps), arrayLength(&marks)); o += nwg.x * 64u) {
        if (stamps[o] & ~AGAIN) == (mine | MARKING) && marks[o] != 0u {
            marked[o] = mine;
            atomicAdd(&results.marked[check.group], 1u);
        }
    }
}

// After the pixel pass of a group drawn with the host's marks: an object
// the group drew and marked, that owns no sample now, while every sample
// of the pixels it can cover is empty or owned by an object drawn before
// it, never passed the depth test (it would own a sample, or one drawn
// after it would), so a fragment that failed the test marked it: no
// forced early-Z. Lists that marks are read from are in object order, so
// "before" is an earlier list, or the same list and a lower index.
@compute @workgroup_size(64)
fn late_marks(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    for (var a = gid.x * check.object_stride + check.tag % check.object_stride; a < arrayLength(&stamps); a += nwg.x * 64u * check.object_stride) {
        if late_mark(a) {
            found(HIDDEN_MARK, a, NONE, check.group);
        }
    }
}

// Whether object `a` was marked by the checked group and never passed
// the depth test (`late_marks`).
fn late_mark(a: u32) -> bool {
    let mine = (check.tag << 8u) | check.group;
    let s = stamps[a];
    if s != (mine | MARKING) || marked[a] != mine || owned[a] == mine {
        return false;
    }
    let r = box_pixels(bounds[a]);
    if r.x > r.z {
        return false;
    }
    for (var y = r.y; y <= r.w; y++) {
        for (var x = r.x; x <= r.z; x++) {
            for (var k = 0; k < i32(HOST_SAMPLES); k++) {
                let id = host_id(ids, vec2<i32>(x, y), k);
                if id == 0u {
                    continue;
                }
                let b = id - 1u;
                if b >= arrayLength(&stamps) || (stamps[b] >> 8u) != check.tag || !(order[b] < order[a] || (order[b] == order[a] && b < a)) {
                    return false;
                }
            }
        }
    }
    return true;
}

// The NDC rectangle of box `b`'s corners (lo.xy, hi.xy), or lo.x =
// REACHES_NEAR where the box reaches the near plane.
const REACHES_NEAR: f32 = 3.4e38;
fn box_ndc(b: ObjectBounds) -> vec4<f32> {
    var lo = vec2<f32>(3.0e38);
    var hi = vec2<f32>(-3.0e38);
    for (var c = 0u; c < 8u; c++) {
        let p = select(b.min, b.max, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u));
        let clip = frame.view_proj * vec4<f32>(p, 1.0);
        if clip.w <= 1e-6 || std_depth(frame, clip.z / clip.w) <= DEPTH_SLACK {
            return vec4<f32>(REACHES_NEAR);
        }
        lo = min(lo, clip.xy / clip.w);
        hi = max(hi, clip.xy / clip.w);
    }
    return vec4<f32>(lo, hi);
}

// The pixels of a view of `size` that the NDC rectangle `r` can cover
// (x0, y0, x1, y1, a pixel more on each side), or an empty rectangle
// (x0 > x1) off the view.
fn ndc_pixels(r: vec4<f32>, size: vec2<i32>) -> vec4<i32> {
    let lo = r.xy;
    let hi = r.zw;
    if lo.x > 1.0 || lo.y > 1.0 || hi.x < -1.0 || hi.y < -1.0 {
        return vec4<i32>(1, 0, 0, 0);
    }
    let first = max(vec2<i32>(floor(vec2<f32>(lo.x + 1.0, 1.0 - hi.y) * 0.5 * frame.viewport.xy)) - 1, vec2<i32>(0));
    let last = min(vec2<i32>(floor(vec2<f32>(hi.x + 1.0, 1.0 - lo.y) * 0.5 * frame.viewport.xy)) + 1, size - 1);
    return vec4<i32>(first, last);
}

// The pixels a box can cover (`ndc_pixels`), or an empty rectangle for
// a box that reaches the near plane, lies off the view or covers over
// 32 × 32 pixels.
fn box_pixels(b: ObjectBounds) -> vec4<i32> {
    let r = box_ndc(b);
    if r.x == REACHES_NEAR {
        return vec4<i32>(1, 0, 0, 0);
    }
    let px = ndc_pixels(r, vec2<i32>(frame.viewport.xy));
    if (px.z - px.x + 1) * (px.w - px.y + 1) > 1024 {
        return vec4<i32>(1, 0, 0, 0);
    }
    return px;
}

// The standard depth at `t` along the ray `origin + t * dir`, and how far
// f32 rounding may move it: clip z and w are sums of products as large as
// the point's coordinates, which the host's vertex shader rounds as this
// does (a box 70 m from the origin seen from 4 m: 3e-5).
fn depth_at(origin: vec3<f32>, dir: vec3<f32>, t: f32) -> vec2<f32> {
    let p = vec4<f32>(origin + t * dir, 1.0);
    let c = frame.view_proj * p;
    let rows = transpose(frame.view_proj);
    let terms = dot(abs(rows[2]), abs(p)) + dot(abs(rows[3]), abs(p));
    return vec2<f32>(std_depth(frame, c.z / c.w), 5e-7 * terms / abs(c.w));
}

// Where the ray through pixel `p`'s centre enters and leaves object `o`'s
// box (and its own box, if it has one), padded as the culler's box tests
// pad boxes (where in the pixel its samples lie, and float rounding),
// from the near plane on: the standard depths of both, and their rounding
// (`depth_at`); x is `MISSED` where the ray misses it. Geometry inside
// the box drew a fragment there at a depth between the two (depth biased
// away from the viewer: behind them), which rounding may find in either
// order for a thin box.
fn box_depths(o: u32, p: vec2<i32>) -> vec3<f32> {
    let c = vec2<f32>(p) + 0.5;
    let ndc = vec2<f32>(c.x * 2.0 * frame.viewport.z - 1.0, 1.0 - c.y * 2.0 * frame.viewport.w);
    let origin = ray_origin(frame, ndc);
    let dir = (frame.ray_dirs * vec4<f32>(ndc, 1.0, 0.0)).xyz;
    let b = bounds[o];
    let far = length(max(abs(b.min - origin), abs(b.max - origin)));
    let scale = max(max(abs(b.min), abs(b.max)), abs(origin));
    let pixel = pixel_angle(frame);
    let pad = block_pad_px(1u) * (pixel.x + pixel.y * far) + 1e-4 * length(b.max - b.min) + 1e-6 * (scale.x + scale.y + scale.z) + 1e-7;
    let inv = vec3<f32>(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
    let world = ray_box(origin, inv, b.min - vec3<f32>(pad), b.max + vec3<f32>(pad));
    let own = ray_oriented(oriented[o], origin, dir, pad);
    // The ray reaches the near plane at t = 1.
    let enter = max(max(world.x, own.x), 1.0);
    let leave = min(world.y, own.y);
    if enter > leave {
        return vec3<f32>(MISSED);
    }
    let a = depth_at(origin, dir, enter);
    let z = depth_at(origin, dir, leave);
    return vec3<f32>(a.x, z.x, max(a.y, z.y));
}

// `box_depths` of a ray that misses the box (past every depth).
const MISSED: f32 = 4.0;

// How far in front of where its box begins a fragment's depth may lie
// beyond the rounding `depth_at` bounds: the rasterizer's interpolation of
// depth, several ulps where depth is coarse, so four times the culler's
// own margin (27 ulps at 1). A box too small or a depth bias the culler
// could act on moves depth far more.
const FRAGMENT_SLACK: f32 = 4.0 * DEPTH_SLACK;

// True when a fragment of depth `d` at pixel `p` lies on or behind where
// the pixel's ray enters object `o`'s box: geometry inside the box can
// have drawn it.
fn reaches_box(o: u32, p: vec2<i32>, d: f32) -> bool {
    let span = box_depths(o, p);
    return span.x != MISSED && std_depth(frame, d) >= min(span.x, span.y) - FRAGMENT_SLACK - span.z;
}

// True when a fragment of depth `d` at pixel `p` lies inside object `o`'s
// box along the pixel's ray: geometry of `o` drew it.
fn holds_point(o: u32, p: vec2<i32>, d: f32) -> bool {
    let span = box_depths(o, p);
    let z = std_depth(frame, d);
    let slack = FRAGMENT_SLACK + span.z;
    return span.x != MISSED && z >= min(span.x, span.y) - slack && z <= max(span.x, span.y) + slack;
}

// Reads the host's depth and IDs at one pixel in `stride` × `stride`, a
// different one each frame (a CPU rasterizer pays for every pixel read),
// after a group, comparing with the last read; FINAL also checks every
// sample's ID.
@compute @workgroup_size(8, 8)
fn check_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(depth);
    let p = gid.xy * check.stride + check.offset;
    let cols = (size.x + check.stride - 1u) / check.stride;
    if (check.mode & BEGIN) != 0u {
        if all(p < size) {
            check_cleared(vec2<i32>(p));
        }
        return;
    }
    if all(p < size) && check_pixel(vec2<i32>(p), gid.y * cols + gid.x) {
        // Every writer stores the same 1.
        results.changed[min(check.group, GROUPS - 1u)] = 1u;
    }
}

// Pixel `p`, read `i` of the frame: true when its depth or ID changed
// since the last read. Each sample is loaded once.
fn check_pixel(p: vec2<i32>, i: u32) -> bool {
    let with_ids = (check.mode & CHECK_IDS) != 0u;
    let last = (check.mode & FINAL) != 0u;
    let px = u32(p.x) | (u32(p.y) << 16u);
    // Without IDs, at the frame's end: no drawn sample before the nearest
    // drawn box (`box_entries`).
    var entry = 3.0e38;
    let boxes = (check.mode & BOXES) != 0u;
    if boxes {
        let e = atomicExchange(&shadow[2u * i + 1u], 0u);
        entry = select(bitcast<f32>(ENTRY_NONE - e), 3.0e38, e == 0u);
    }
    var far = 0.0;
    var id0 = 0u;
    for (var s = 0; s < i32(HOST_SAMPLES); s++) {
        let d = textureLoad(depth, p, s).r;
        let z = std_depth(frame, d);
        far = max(far, z);
        if with_ids {
            let id = host_id(ids, p, s);
            if s == 0 {
                id0 = id;
            }
            check_sample(id, d, p, px);
        } else if boxes && z < 1.0 && z > FRAGMENT_SLACK && z < entry {
            found(BEFORE_BOXES, NONE, px, bitcast<u32>(z));
        }
    }
    // The cleared targets: far depth, ID 0.
    let first = (check.mode & FIRST) != 0u;
    let old = vec2<u32>(select(atomicLoad(&shadow[2u * i]), bitcast<u32>(1.0), first), select(atomicLoad(&shadow[2u * i + 1u]), 0u, first || !with_ids));
    if far > bitcast<f32>(old.x) {
        found(DEPTH_FARTHER, NONE, px, check.group);
    }
    if old.y != 0u && id0 == 0u && with_ids {
        found(IDS_CLEARED, old.y - 1u, px, check.group);
    }
    atomicStore(&shadow[2u * i], bitcast<u32>(far));
    if with_ids {
        atomicStore(&shadow[2u * i + 1u], id0);
    }
    return bitcast<u32>(far) != old.x || id0 != old.y;
}

// Before the frame's first draw, where the host has cleared its targets
// (the clearing rule): every sample of pixel `p` holds far depth, and ID
// 0 where the view checks IDs.
fn check_cleared(p: vec2<i32>) {
    let px = u32(p.x) | (u32(p.y) << 16u);
    for (var s = 0; s < i32(HOST_SAMPLES); s++) {
        let stale_id = (check.mode & CHECK_IDS) != 0u && host_id(ids, p, s) != 0u;
        if std_depth(frame, textureLoad(depth, p, s).r) < 1.0 || stale_id {
            found(NOT_CLEARED, NONE, px, NONE);
            return;
        }
    }
}

// `shadow`'s box entries are stored as this less the f32 bits of a
// standard depth (never negative, so its bits order as it does), so that
// 0 means none and the nearest is the greatest (`atomicMax`).
const ENTRY_NONE: u32 = 0x7fffffffu;

// True when object `o` was drawn by an occluding list this frame.
fn drawn_now(o: u32) -> bool {
    return (stamps[o] >> 8u) == check.tag;
}

// Without IDs, before the frame's last read: every object an occluding
// list drew this frame enters, at each pixel read that its box can cover,
// the depth from which geometry inside the box can have drawn there
// (`reaches_box`'s bound), kept where it is the nearest so far. A drawn
// sample in front of every such entry was drawn by no geometry inside its
// box. Threads stride over the objects (a CPU rasterizer pays per thread);
// an object covers at most every pixel read.
@compute @workgroup_size(64)
fn box_entries(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(depth));
    let s = i32(check.stride);
    let off = vec2<i32>(check.offset);
    let cols = (size.x + s - 1) / s;
    for (var o = gid.x; o < arrayLength(&stamps); o += nwg.x * 64u) {
        if !drawn_now(o) {
            continue;
        }
        let r = box_rect(bounds[o], size);
        if r.x > r.z {
            continue;
        }
        // The pixels read within the rectangle: p = g * s + off.
        let g0 = max((r.xy - off + vec2<i32>(s - 1)) / s, vec2<i32>(0));
        let g1 = min((r.zw - off) / s, (size - 1 - off) / s);
        for (var gy = g0.y; gy <= g1.y; gy++) {
            for (var gx = g0.x; gx <= g1.x; gx++) {
                let p = vec2<i32>(gx, gy) * s + off;
                let slot = 2u * u32(gy * cols + gx) + 1u;
                // Only where some sample is drawn and no box yet enters
                // before the nearest (a CPU rasterizer pays per ray).
                let nearest = nearest_host_depth(p);
                let e = atomicLoad(&shadow[slot]);
                if nearest >= 1.0 || (e != 0u && bitcast<f32>(ENTRY_NONE - e) <= nearest) {
                    continue;
                }
                let span = box_depths(o, p);
                if span.x == MISSED {
                    continue;
                }
                let enter = max(min(span.x, span.y) - FRAGMENT_SLACK - span.z, 0.0);
                atomicMax(&shadow[slot], ENTRY_NONE - bitcast<u32>(enter));
            }
        }
    }
}

// The nearest of the host depth's samples at pixel `p`, in standard form.
fn nearest_host_depth(p: vec2<i32>) -> f32 {
    var near = 1.0;
    for (var s = 0; s < i32(HOST_SAMPLES); s++) {
        near = min(near, std_depth(frame, textureLoad(depth, p, s).r));
    }
    return near;
}

// The pixels object box `b` can cover in a view of `size`
// (`ndc_pixels`), the whole view where it reaches the near plane.
fn box_rect(b: ObjectBounds, size: vec2<i32>) -> vec4<i32> {
    let r = box_ndc(b);
    if r.x == REACHES_NEAR {
        return vec4<i32>(0, 0, size - 1);
    }
    return ndc_pixels(r, size);
}

// The world point of the first BEFORE_BOXES sample: on its pixel's ray,
// at its depth (found by bisection, for perspective and orthographic
// views alike).
fn suspect_point() -> vec3<f32> {
    let px = results.findings[BEFORE_BOXES].pixel;
    let z = bitcast<f32>(results.findings[BEFORE_BOXES].group);
    let c = vec2<f32>(f32(px & 0xffffu), f32(px >> 16u)) + 0.5;
    let ndc = vec2<f32>(c.x * 2.0 * frame.viewport.z - 1.0, 1.0 - c.y * 2.0 * frame.viewport.w);
    let origin = ray_origin(frame, ndc);
    let dir = (frame.ray_dirs * vec4<f32>(ndc, 1.0, 0.0)).xyz;
    var lo = 1.0;
    var hi = 2.0;
    for (var k = 0; k < 64 && depth_at(origin, dir, hi).x < z; k++) {
        hi *= 2.0;
    }
    for (var k = 0; k < 32; k++) {
        let mid = 0.5 * (lo + hi);
        if depth_at(origin, dir, mid).x < z {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return origin + hi * dir;
}

// How far object `o`'s box lies from point `p` (0 inside).
fn box_distance(o: u32, p: vec3<f32>) -> f32 {
    let b = bounds[o];
    return length(p - clamp(p, b.min, b.max));
}

// After a BEFORE_BOXES finding, the drawn box nearest its sample, which
// the finding names as the likeliest to have drawn it: one key per
// object, its distance over its index (`Results::suspect`).
@compute @workgroup_size(64)
fn suspect(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    if atomicLoad(&results.findings[BEFORE_BOXES].count) == 0u {
        return;
    }
    let p = suspect_point();
    let bits = check.object_bits;
    for (var o = gid.x; o < arrayLength(&stamps); o += nwg.x * 64u) {
        if drawn_now(o) {
            let key = ((bitcast<u32>(box_distance(o, p)) >> bits) << bits) | o;
            atomicMax(&results.suspect, ~key);
        }
    }
}

// One sample's ID `id` and depth `d` at pixel `p`: marked when the group
// checked drew it with the host's marks; and at the frame's end, in range,
// drawn this frame, within its box, and there wherever depth was drawn.
fn check_sample(id: u32, d: f32, p: vec2<i32>, px: u32) {
    let last = (check.mode & FINAL) != 0u;
    if id == 0u {
        if last && std_depth(frame, d) < 1.0 {
            found(DEPTH_WITHOUT_ID, NONE, px, NONE);
        }
        return;
    }
    let o = id - 1u;
    if o >= arrayLength(&stamps) {
        if last {
            found(ID_RANGE, id, px, NONE);
        }
        return;
    }
    let st = stamps[o];
    let drawn = (st >> 8u) == check.tag;
    // (An object drawn twice in the frame may own a sample from its first
    // draw, which the group's marks do not record.)
    if (check.mode & HOST_MARKS) != 0u && drawn && (st & (AGAIN | MARKING | GROUP)) == (MARKING | check.group) {
        owned[o] = (check.tag << 8u) | check.group;
        if marked[o] != owned[o] {
            found(MISSING_MARK, o, px, check.group);
        }
    }
    if !last || (drawn && (std_depth(frame, d) <= FRAGMENT_SLACK || reaches_box(o, p, d))) {
        return;
    }
    found(select(ID_NOT_DRAWN, OUTSIDE_BOX, drawn), o, px, select(NONE, st & GROUP, drawn));
    // The value is the object's index, not index + 1?
    if id < arrayLength(&stamps) && (stamps[id] >> 8u) == check.tag && holds_point(id, p, d) {
        found(INDEX_FOR_ID, id, px, stamps[id] & GROUP);
    }
}
