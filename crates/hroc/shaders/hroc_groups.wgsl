// HROC compute passes (Lee et al. 2021 §3.2, §4.2; Lee's thesis III.3):
// extract — one thread per effective occluder walks the BVH bottom-up;
//           objects tested alone (§6's hybrid: DYNAMIC objects and those
//           not in the tree) become occludee groups of their own;
// collect — one thread per node gathers occludee groups (unknown nodes),
//           frustum-culls them and splits those that cross the near plane;
// merge   — next V = O ∪ D;  filter — next V = objects owning a pixel (OF);
// seed    — after a camera cut, V = the objects a coarse grid of rays meets first.

const NIL: u32 = 0u;
const UNKNOWN: u32 = 1u;
const VISIBLE: u32 = 2u;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> leaf_of_object: array<u32>;
@group(0) @binding(3) var<storage, read> occluders: array<u32>;      // O marks
@group(0) @binding(4) var<storage, read_write> state: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> groups: array<DrawArgs>;
@group(0) @binding(6) var<storage, read_write> group_count: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read_write> occludees: array<u32>; // U marks
@group(0) @binding(8) var<storage, read> drawn: array<u32>;           // D marks
@group(0) @binding(9) var<storage, read_write> visible: array<u32>;   // next V
@group(0) @binding(10) var ids: texture_2d<u32>;
@group(0) @binding(11) var<storage, read> bounds: array<ObjectBounds>;

// Pixels per side of the occlusion test's blocks (hroc_test.wgsl): groups
// are padded, frustum-culled and split at the near plane as the test pads them.
override TEST_SCALE: u32 = 1u;

fn test_box(n: BvhNode) -> Box {
    return padded_box_px(n, frame.eye.xyz, pixel_angle_xy(frame), block_pad_px(TEST_SCALE));
}



@compute @workgroup_size(256)
fn extract(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= frame.object_count {
        return;
    }
    let flags = bounds[i].flags;
    if (flags & REMOVED) != 0u || (occluders[i] != 0u && (flags & ALONE) != 0u) {
        return; // nothing to draw, or drawn and visible already
    }
    if (flags & ALONE) != 0u {
        // The hybrid (§6): the object's own box is a group, marked without
        // rays as ROC marks its boxes; near-plane boxes are visible untested.
        let b = test_box(BvhNode(bounds[i].min, 0u, bounds[i].max, 0u));
        if box_in_frustum(frame.planes, b.min, b.max) {
            if crosses_near(frame.planes, frame.near, b) {
                occludees[i] = 1u;
            } else {
                emit_group(LEAF_BIT | i);
            }
        }
        return;
    }
    if occluders[i] == 0u {
        return;
    }
    // Atomic max makes the result independent of thread order: a node
    // marked unknown by its sibling's walk becomes visible by its own.
    var n = leaf_of_object[i];
    loop {
        if atomicMax(&state[n], VISIBLE) == VISIBLE || n == 0u {
            break; // another walk went on from here, or the root
        }
        atomicMax(&state[sibling(n)], UNKNOWN);
        n = nodes[n].parent;
    }
}

fn emit_group(n: u32) {
    let slot = atomicAdd(&group_count[0], 1u);
    groups[slot] = DrawArgs(36u, 1u, 0u, n);
}

@compute @workgroup_size(256)
fn collect(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = flat_id(wid, nwg, lid, 256u);
    if g >= frame.node_count {
        return;
    }
    let s = atomicLoad(&state[g]);
    // No occluder at all: the root is the one group.
    let root_group = g == 0u && s == NIL;
    if s != UNKNOWN && !root_group {
        return;
    }
    // Adaptive grouping: a group crossing the near plane (or holding the
    // eye) is replaced by its children; such leaves are visible untested.
    var stack: array<u32, STACK>;
    stack[0] = g;
    var sp = 1u;
    while sp > 0u {
        sp -= 1u;
        let n = stack[sp];
        let node = nodes[n];
        let b = test_box(node);
        if !box_in_frustum(frame.planes, b.min, b.max) {
            continue;
        }
        if !crosses_near(frame.planes, frame.near, b) {
            emit_group(n);
        } else if (node.child & LEAF_BIT) != 0u {
            occludees[node.child & ~LEAF_BIT] = 1u;
        } else if sp + 2u <= STACK {
            stack[sp] = node.child;
            stack[sp + 1u] = node.child + 1u;
            sp += 2u;
        }
    }
}

@compute @workgroup_size(256)
fn merge(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i < frame.object_count {
        visible[i] = select(0u, 1u, occluders[i] != 0u || drawn[i] != 0u);
    }
}

// Occluder filtering (§4.2): the item buffer decides the next occluders.
// One thread reads the centre pixel of each FILTER_STRIDE² square.
override FILTER_STRIDE: u32 = 1u;

@compute @workgroup_size(16, 16)
fn filter_occluders(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(ids);
    let px = gid.xy * FILTER_STRIDE + vec2<u32>(FILTER_STRIDE / 2u);
    if px.x >= size.x || px.y >= size.y {
        return;
    }
    let id = textureLoad(ids, px, 0).r;
    if id != 0u {
        visible[id - 1u] = 1u;
    }
}

// Occluder seed (HROC §6 names incoherent frames as a limit: after a cut,
// last frame's V occludes nothing here). One ray per cell of a coarse
// screen grid walks the BVH and marks the object whose box it enters first;
// those objects are V. For speed only: V may be any set of objects, and no
// culling decision rests on it.
override SEED_COLS: u32 = 64u;
override SEED_ROWS: u32 = 36u;

@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>) {
    let cell = gid.x;
    if cell >= SEED_COLS * SEED_ROWS || frame.node_count == 0u {
        return;
    }
    let ndc = vec2<f32>((f32(cell % SEED_COLS) + 0.5) / f32(SEED_COLS) * 2.0 - 1.0, 1.0 - (f32(cell / SEED_COLS) + 0.5) / f32(SEED_ROWS) * 2.0);
    let eye = frame.eye.xyz;
    let dir = (frame.ray_dirs * vec4<f32>(ndc, 1.0, 0.0)).xyz;
    let inv = vec3<f32>(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
    var best = 3.0e38;
    var hit = NO_HIT;
    var stack: array<u32, STACK>;
    stack[0] = 0u;
    var sp = 1u;
    while sp > 0u {
        sp -= 1u;
        let node = nodes[stack[sp]];
        let span = ray_box(eye, inv, node.min, node.max);
        let t = max(span.x, 1.0); // t = 1 on the near plane
        if span.y < t || t >= best {
            continue;
        }
        if (node.child & LEAF_BIT) != 0u {
            best = t;
            hit = node.child & ~LEAF_BIT;
        } else if sp + 2u <= STACK {
            stack[sp] = node.child;
            stack[sp + 1u] = node.child + 1u;
            sp += 2u;
        }
    }
    if hit != NO_HIT {
        visible[hit] = 1u;
    }
}

const NO_HIT: u32 = 0xffffffffu;
