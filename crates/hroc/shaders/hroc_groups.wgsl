// HROC step 2, the occludee groups (Lee et al. 2021 §3.2; Lee's thesis
// III.3):
// extract — one thread per effective occluder walks the BVH bottom-up;
//           objects tested alone (§6's hybrid: DYNAMIC objects and those
//           not in the tree) become occludee groups of their own;
// collect — one thread per node gathers occludee groups (unknown nodes),
//           frustum-culls them and splits those that cross the near plane.
// Its bindings are numbered as hroc_next.wgsl's and hroc_seed.wgsl's: the
// three share one bind group.

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
            if crosses_near(frame.near_plane, frame.near, b) {
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
        if !crosses_near(frame.near_plane, frame.near, b) {
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
