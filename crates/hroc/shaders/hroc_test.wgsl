// HROC batch occlusion test (Lee et al. 2021 §3.3; Lee's thesis III.4): rasterize group
// boxes against the occlusion map with forced early-Z, no depth writes.
// A fragment of a leaf group marks its object; a fragment of an interior
// group casts a ray through its pixel into the group's subtree and marks
// every leaf whose box the ray enters in front of the occlusion map — all
// of them, never stopping at the first hit. Visited marks (both children
// done → parent done) prune repeated traversal. A group with LEAF_BIT in
// its id is an object tested alone (§6's hybrid): its own box, no rays.
// An object the host gave a box in its own frame (OrientedBounds) is marked
// only where a ray also enters that box in front of the map: a leaf box
// fragment then casts one ray, and the traversal clips its leaves' spans.
// With TEST_SCALE > 1 (or a multisampled target) the test runs on blocks
// of TEST_SCALE² pixels: boxes are rasterized against a map holding each
// block's farthest depth (reduce_fs, drawn first in the test's own pass)
// and padded for rays through block centres (block_pad_px in common.wgsl);
// the rays take the same farthest depth from the host's (block_limit).


@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read_write> occludees: array<u32>; // U marks
@group(0) @binding(3) var<storage, read_write> visited: array<u32>;
// The occlusion map: the host's depth, whose blocks' farthest depth the
// rays and reduce_fs take.
@group(0) @binding(4) var occlusion_map: HostDepth;
// Per slot: rays cast, nodes visited (spread over slots against contention).
@group(0) @binding(5) var<storage, read_write> ray_stats: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(15) var<storage, read> oriented: array<OrientedBounds>;

override TEST_SCALE: u32 = 1u;

fn test_box(n: BvhNode) -> Box {
    return padded_box_px(n, frame.eye.xyz, pixel_angle_xy(frame), block_pad_px(TEST_SCALE));
}

// A triangle over the whole target.
@vertex
fn reduce_vs(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((v << 1u) & 2u), f32(v & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// The farthest standard depth of the block at `block` of TEST_SCALE ×
// TEST_SCALE pixels (TEST_SCALE divides the target's size), every sample.
fn block_limit(block: vec2<i32>) -> f32 {
    let base = block * i32(TEST_SCALE);
    var farthest = 0.0;
    for (var y = 0; y < i32(TEST_SCALE); y++) {
        for (var x = 0; x < i32(TEST_SCALE); x++) {
            farthest = max(farthest, farthest_host_depth(occlusion_map, base + vec2<i32>(x, y), frame.reversed));
        }
    }
    return farthest;
}

// The occlusion map of the test's blocks, each block's farthest depth.
@fragment
fn reduce_fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
    return std_depth(frame, block_limit(vec2<i32>(p.xy)));
}


struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) node: u32,
}

// One group box per draw command (the indirect draw count): the command's
// first instance is the group.
@vertex
fn box_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) node: u32) -> BoxOut {
    return group_box(v, node);
}

// The groups as one instanced draw (an emulated draw count, where a
// multi-draw costs a driver call per command slot): instance i is the
// group of command i, as collected (hroc_groups.wgsl).
@group(0) @binding(16) var<storage, read> groups: array<DrawArgs>;

@vertex
fn group_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> BoxOut {
    return group_box(v, groups[i].first_instance);
}

fn group_box(v: u32, node: u32) -> BoxOut {
    var n = BvhNode(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u);
    if (node & LEAF_BIT) != 0u {
        let o = node & ~LEAF_BIT;
        n = BvhNode(bounds[o].min, 0u, bounds[o].max, 0u);
    } else {
        n = nodes[node];
    }
    let b = test_box(n);
    var out: BoxOut;
    out.clip = frame.view_proj * vec4<f32>(box_corner(b, v), 1.0);
    out.node = node;
    return out;
}

// The ray through the centre of the block at `clip` (in blocks;
// frame.viewport is in pixels), t = 1 on the near plane, and the
// deepest the test lets it reach there. Depth along the ray is compared in
// depth-buffer space, where the occlusion map lives (distances unprojected
// near z = 1 lose precision).
struct BlockRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
    inv: vec3<f32>,
    c0: vec4<f32>,
    c1: vec4<f32>,
    limit: f32,
}

fn block_ray(clip: vec2<f32>) -> BlockRay {
    let centre = clip * f32(TEST_SCALE);
    let ndc = vec2<f32>(centre.x * frame.viewport.z * 2.0 - 1.0, 1.0 - centre.y * frame.viewport.w * 2.0);
    let dir = (frame.ray_dirs * vec4<f32>(ndc, 1.0, 0.0)).xyz;
    var r: BlockRay;
    r.origin = ray_origin(frame, ndc);
    r.dir = dir;
    r.inv = vec3<f32>(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
    r.c0 = frame.view_proj * vec4<f32>(r.origin, 1.0);
    r.c1 = frame.view_proj * vec4<f32>(dir, 0.0);
    r.limit = block_limit(vec2<i32>(clip)) + DEPTH_SLACK;
    return r;
}

// Whether the ray enters a span in front of the occlusion map.
fn in_front(r: BlockRay, span: vec2<f32>) -> bool {
    let t = max(span.x, 1.0); // nothing before the near plane is drawn
    if span.y < t {
        return false;
    }
    return std_depth(frame, (r.c0.z + t * r.c1.z) / (r.c0.w + t * r.c1.w)) <= r.limit;
}

// The span of the ray in a leaf's padded box, clipped to its object's own
// box padded alike (both hold the geometry's padding balls).
fn leaf_span(r: BlockRay, o: u32, n: BvhNode) -> vec2<f32> {
    let pad = box_pad(n, frame.eye.xyz, pixel_angle_xy(frame), block_pad_px(TEST_SCALE));
    let w = ray_box(r.origin, r.inv, n.min - vec3<f32>(pad), n.max + vec3<f32>(pad));
    let l = ray_oriented(oriented[o], r.origin, r.dir, pad);
    return vec2<f32>(max(w.x, l.x), min(w.y, l.y));
}

// A leaf box's fragment: its object is marked unless it has an own box
// that the block's ray misses, or enters behind the map.
fn mark_object(o: u32, n: BvhNode, clip: vec2<f32>) {
    if occludees[o] != 0u {
        return;
    }
    if oriented[o].valid != 0u {
        let r = block_ray(clip);
        if !in_front(r, leaf_span(r, o, n)) {
            return;
        }
    }
    occludees[o] = 1u;
}

// Marks a leaf and propagates "visited" up while the sibling is done too.
fn mark_leaf(leaf: u32, group: u32) {
    occludees[nodes[leaf].child & ~LEAF_BIT] = 1u;
    visited[leaf] = 1u;
    var n = leaf;
    while n != group && visited[sibling(n)] != 0u {
        n = nodes[n].parent;
        visited[n] = 1u;
    }
}

// The ray `r` into the subtree of interior group node `group`: marks every
// leaf whose box it enters in front of the map (and, through `mark_leaf`,
// the visited nodes). Returns the nodes it visited.
//
// Child index 0 ends a path: the root is nobody's child, so only a node
// read as zeros points there. SIMD rasterizers run the lanes of a block
// that failed coverage or the early depth test along with the live ones,
// with their stores dropped, and llvmpipe gives such lanes zeros for
// every storage load: followed, node 0's "children" 0 and 1 would cycle
// until the driver's loop limiter (65,535 iterations) ends the loop, and
// every live lane of the block would wait for it. `tests/shaders.rs` runs
// this function on zeroed nodes.
fn cast_ray(group: u32, r: BlockRay) -> u32 {
    let eye = frame.eye.xyz;
    let pixel = pixel_angle_xy(frame);
    let pad = block_pad_px(TEST_SCALE);
    let first = nodes[group].child;
    if first == 0u {
        return 0u;
    }
    var stack: array<u32, STACK>;
    stack[0] = first;
    stack[1] = first + 1u;
    var sp = 2u;
    var steps = 0u;
    while sp > 0u {
        sp -= 1u;
        let n = stack[sp];
        if visited[n] != 0u {
            continue;
        }
        steps += 1u;
        let node = nodes[n];
        var span: vec2<f32>;
        if (node.child & LEAF_BIT) != 0u {
            span = leaf_span(r, node.child & ~LEAF_BIT, node);
        } else {
            let b = padded_box_px(node, eye, pixel, pad);
            span = ray_box(r.origin, r.inv, b.min, b.max);
        }
        if !in_front(r, span) {
            continue;
        }
        if (node.child & LEAF_BIT) != 0u {
            mark_leaf(n, group);
        } else if node.child != 0u && sp + 2u <= STACK {
            stack[sp] = node.child;
            stack[sp + 1u] = node.child + 1u;
            sp += 2u;
        }
    }
    return steps;
}

// Without a depth attachment (a backend that cannot sample the depth it
// tests against while it is attached), the test compares each fragment
// itself, as the attachment's LessEqual (GreaterEqual reversed) with its
// bias toward the camera would, and a little more (16 units of
// Depth32Float's step below 1 are 1.9e-6).
override MANUAL_DEPTH: bool = false;

@fragment @early_depth_test(force)
fn box_fs(in: BoxOut) {
    if MANUAL_DEPTH && std_depth(frame, in.clip.z) > block_limit(vec2<i32>(in.clip.xy)) + 4e-6 {
        return;
    }
    if (in.node & LEAF_BIT) != 0u {
        let o = in.node & ~LEAF_BIT;
        mark_object(o, BvhNode(bounds[o].min, 0u, bounds[o].max, 0u), in.clip.xy);
        return;
    }
    let group = nodes[in.node];
    if (group.child & LEAF_BIT) != 0u {
        mark_object(group.child & ~LEAF_BIT, group, in.clip.xy);
        return;
    }
    if visited[in.node] != 0u {
        return;
    }
    let steps = cast_ray(in.node, block_ray(in.clip.xy));
    let texel = vec2<u32>(in.clip.xy);
    let slot = (texel.x + 7u * texel.y) % STAT_SLOTS;
    atomicAdd(&ray_stats[2u * slot], 1u);
    atomicAdd(&ray_stats[2u * slot + 1u], steps);
}

// Front-to-back rounds over one list: the occludees U in step 4, or the
// occluder list V in step 1 (occluder rounds, two of them). The batch test
// marks U against a map of last frame's occluders only; objects that came
// into view this frame are missing from it, and whatever they hide passes
// the test. V, last frame's visible set, holds objects that this frame's
// view hides behind others of V. Each round draws the list's objects whose
// box is nearest at some block (`front`), then tests the others' boxes
// again against the depth those draws left, front to back as CHC++
// interleaves its queries with drawing (Mattausch et al. 2008), but with
// no read-back: the survivors are the next round's candidates, and the
// last round draws all of its candidates. Round k's candidates are the
// objects whose `candidates` flag equals round.candidate (k + 1; the
// list's own marks in round 0); a pass never reads in its vertex stage
// what its fragments write, so the flags of round k + 1 and the front
// marks are separate buffers, tagged by round instead of cleared.

struct RoundParams {
    candidate: u32,
    front: u32,
    alive: u32,
    _pad: u32,
}

@group(0) @binding(8) var<uniform> round: RoundParams;
// The compacted list (U or V): vertices 36 i to 36 i + 35 are the box of its
// i-th object (one draw, not instances: a CPU rasterizer pays per instance).
@group(0) @binding(9) var<storage, read> occludee_list: array<DrawCommand>;
// What the pass marks: front marks (front_fs) or next round's candidates (late_fs).
@group(0) @binding(10) var<storage, read_write> round_marks: array<u32>;
@group(0) @binding(11) var<storage, read> candidates: array<u32>;
@group(0) @binding(12) var<storage, read> front_marks: array<u32>;

// rounds_init only: the list's count, and the box draw it sizes.
@group(0) @binding(13) var<storage, read> occludee_count: array<u32>;
@group(0) @binding(14) var<storage, read_write> box_draw: array<u32>;

struct RoundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) object: u32,
}

fn round_box(o: u32, v: u32, drawn: bool) -> RoundOut {
    var out: RoundOut;
    out.object = o;
    if !drawn {
        out.clip = vec4<f32>(0.0, 0.0, -2.0, 1.0); // a point behind the near plane
        return out;
    }
    let b = test_box(BvhNode(bounds[o].min, 0u, bounds[o].max, 0u));
    out.clip = frame.view_proj * vec4<f32>(box_corner(b, v), 1.0);
    return out;
}

// Round 0: an object whose test box crosses the near plane has no front
// faces to rasterize, so it is drawn in front at once, as group extraction
// draws such leaves untested.
@compute @workgroup_size(256)
fn rounds_init(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let o = id.y * nwg.x * 256u + id.x;
    if o == 0u {
        box_draw[0] = 36u * occludee_count[0];
    }
    if o >= frame.object_count || candidates[o] != round.candidate {
        return;
    }
    if crosses_near(frame.near_plane, frame.near, test_box(BvhNode(bounds[o].min, 0u, bounds[o].max, 0u))) {
        round_marks[o] = round.front;
    }
}

// The boxes of this round's candidates, with depth writes and no fragment
// stage, over the blocks' occlusion map: the nearest box depth.
@vertex
fn front_vs(@builtin(vertex_index) v: u32) -> RoundOut {
    let o = occludee_list[v / 36u].first_instance;
    return round_box(o, v % 36u, candidates[o] == round.candidate);
}

// Every box of the list: the passes below test the round in the fragment
// stage (a vertex stage that reads the state measured slower on lavapipe).
@vertex
fn round_vs(@builtin(vertex_index) v: u32) -> RoundOut {
    let o = occludee_list[v / 36u].first_instance;
    return round_box(o, v % 36u, true);
}

// Against the nearest box depth (read-only, biased towards the eye): a
// candidate whose box is the nearest at some block is drawn this round.
@fragment @early_depth_test(force)
fn front_fs(in: RoundOut) {
    if candidates[in.object] == round.candidate {
        round_marks[in.object] = round.front;
    }
}

// Against the depth this round's draws left: a box still in front
// somewhere (and the object's own box too, where it has one) makes its
// object a candidate of the next round.
@fragment @early_depth_test(force)
fn late_fs(in: RoundOut) {
    let o = in.object;
    if candidates[o] != round.candidate || front_marks[o] == round.front || round_marks[o] == round.alive {
        return;
    }
    if oriented[o].valid != 0u {
        let r = block_ray(in.clip.xy);
        if !in_front(r, leaf_span(r, o, BvhNode(bounds[o].min, 0u, bounds[o].max, 0u))) {
            return;
        }
    }
    round_marks[o] = round.alive;
}
