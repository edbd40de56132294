// HROC step 2, the occludee groups (Lee et al. 2021 §3.2; Lee's thesis
// III.3), in one compute pass with step 1's refill before it:
// extract   — one thread per object walks the BVH bottom-up from each
//             effective occluder (V's that drew, and the refill's); a walk
//             that first marks a sibling unknown lists it as a candidate,
//             and sizes the collection's launch;
// alone     — one thread per object, only when some objects are tested
//             alone (§6's hybrid: DYNAMIC objects and those not in the
//             tree): each becomes an occludee group of its own;
// collect   — one thread per candidate (and one for the root), launched
//             from what the walks wrote, gathers the occludee groups
//             (nodes still unknown), frustum-culls them and splits those
//             that cross the near plane.
// Its bindings are numbered as hroc_next.wgsl's and hroc_seed.wgsl's: the
// three share one list of resources. The end of the frame
// (hroc_next.wgsl) resets the walk's counts and launch for the next.

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
@group(0) @binding(11) var<storage, read> bounds: array<ObjectBounds>;
// The collection's workgroups (x, y, 1), which the walks raise: the
// collection is dispatched from here.
@group(0) @binding(18) var<storage, read_write> collect_launch: array<atomic<u32>>;
// The walk's counts and the candidates:
// [0]  objects walked from;
// [1]  candidates;
// [2], [3]  the last frame's [0] and [1], which step 5 keeps as it resets them;
// [4..) the candidate nodes.
@group(0) @binding(19) var<storage, read_write> work: array<atomic<u32>>;
const WALKED: u32 = 0u;
const COUNT: u32 = 1u;
const CANDIDATES: u32 = 4u;

// Pixels per side of the occlusion test's blocks (hroc_test.wgsl): groups
// are padded, frustum-culled and split at the near plane as the test pads them.
override TEST_SCALE: u32 = 1u;

fn test_box(n: BvhNode) -> Box {
    return padded_box_px(n, frame.eye.xyz, pixel_angle_xy(frame), block_pad_px(TEST_SCALE));
}

// Workgroups (x, y) of a 1D launch of `threads` spread as dispatch_size
// spreads them (gpu/mod.rs): y rows of at most 65535.
fn launch(threads: u32) -> vec2<u32> {
    let groups = max(1u, (threads + 255u) / 256u);
    return vec2<u32>(min(groups, 65535u), (groups + 65534u) / 65535u);
}

// Flat index of a thread of such a launch: rows are 65535 workgroups wide
// whenever there is more than one, so num_workgroups is not read (DX12
// leaves it 0 in the indirect dispatches wgpu does not validate).
fn launched_id(wid: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * 65535u + wid.x) * 256u + lid;
}

@compute @workgroup_size(256)
fn extract(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    // Only effective occluders walk; objects tested alone are groups of
    // their own (`alone`), visible untested when they occlude.
    if i >= frame.object_count || occluders[i] == 0u || (bounds[i].flags & (REMOVED | ALONE)) != 0u {
        return;
    }
    atomicAdd(&work[WALKED], 1u);
    // Atomic max makes the result independent of thread order: a node
    // marked unknown by its sibling's walk becomes visible by its own.
    var n = leaf_of_object[i];
    loop {
        if atomicMax(&state[n], VISIBLE) == VISIBLE || n == 0u {
            break; // another walk went on from here, or the root
        }
        let s = sibling(n);
        if atomicMax(&state[s], UNKNOWN) == NIL {
            add_candidate(s);
        }
        n = nodes[n].parent;
    }
}

// Lists node `n` for `collect`, whose thread 0 is the root's: the
// candidate in slot c is thread c + 1's.
fn add_candidate(n: u32) {
    let c = atomicAdd(&work[COUNT], 1u);
    atomicStore(&work[CANDIDATES + c], n);
    let threads = launch(c + 2u);
    atomicMax(&collect_launch[0], threads.x);
    atomicMax(&collect_launch[1], threads.y);
}

@compute @workgroup_size(256)
fn alone(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= frame.object_count {
        return;
    }
    let flags = bounds[i].flags;
    if (flags & REMOVED) != 0u || (flags & ALONE) == 0u || occluders[i] != 0u {
        return; // nothing to draw, in the tree, or drawn and visible already
    }
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
}

fn emit_group(n: u32) {
    let slot = atomicAdd(&group_count[0], 1u);
    groups[slot] = DrawArgs(36u, 1u, 0u, n);
}

@compute @workgroup_size(256)
fn collect(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = launched_id(wid, lid);
    if t > atomicLoad(&work[COUNT]) || frame.node_count == 0u {
        return;
    }
    // Thread 0: with no occluder at all, the root is the one group.
    var g = 0u;
    if t > 0u {
        g = atomicLoad(&work[CANDIDATES + t - 1u]);
    }
    let s = atomicLoad(&state[g]);
    if s != select(UNKNOWN, NIL, t == 0u) {
        return; // a candidate a later walk made visible, or a root walked
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
