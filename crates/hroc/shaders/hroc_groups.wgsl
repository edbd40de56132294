// HROC step 2, the occludee groups (Lee et al. 2021 §3.2; Lee's thesis
// III.3), in work that scales with the occluders rather than the scene:
// walk_size — one thread sizes the walk to V's packed list and the objects
//             step 1's refill drew, and empties the list of candidates;
// extract   — one thread per object of those walks the BVH bottom-up from
//             each effective occluder; a walk that first marks a sibling
//             unknown lists it as a candidate;
// alone     — one thread per object, only when some objects are tested
//             alone (§6's hybrid: DYNAMIC objects and those not in the
//             tree): each becomes an occludee group of its own;
// collect   — one thread per candidate (and one for the root) gathers the
//             occludee groups (nodes still unknown), frustum-culls them
//             and splits those that cross the near plane.
// Its bindings are numbered as hroc_next.wgsl's and hroc_seed.wgsl's: the
// three share one list of resources.

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
@group(0) @binding(18) var<storage, read> v_list: array<DrawCommand>;  // V, packed
@group(0) @binding(19) var<storage, read> v_count: array<u32>;         // |V|
// What step 1's refill drew where V left holes: occluders (in O), not in
// V's list.
@group(0) @binding(21) var<storage, read> refill_list: array<DrawCommand>;
@group(0) @binding(22) var<storage, read> refill_count: array<u32>;
// The walk's and the collection's workgroups (x, y, 1), each copied from
// here to the buffer it is dispatched from, and their items:
// [0..4)  the walk's workgroups, and the objects it walks from;
// [4..8)  the collection's workgroups, and the candidate count;
// [8]     |V|: the walk's objects are V's, then the refill's;
// [9..)   the candidate nodes.
@group(0) @binding(20) var<storage, read_write> work: array<atomic<u32>>;
const WALK: u32 = 0u;
const COLLECT: u32 = 4u;
const V_COUNT: u32 = 8u;
const CANDIDATES: u32 = 9u;

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

@compute @workgroup_size(1)
fn walk_size() {
    let v = v_count[0];
    let objects = v + refill_count[0];
    let walk = select(vec2<u32>(0u, 1u), launch(objects), objects > 0u);
    atomicStore(&work[WALK], walk.x);
    atomicStore(&work[WALK + 1u], walk.y);
    atomicStore(&work[WALK + 2u], 1u);
    atomicStore(&work[WALK + 3u], objects);
    atomicStore(&work[V_COUNT], v);
    // The root's thread runs even when no walk lists a candidate.
    atomicStore(&work[COLLECT], 1u);
    atomicStore(&work[COLLECT + 1u], 1u);
    atomicStore(&work[COLLECT + 2u], 1u);
    atomicStore(&work[COLLECT + 3u], 0u);
}

@compute @workgroup_size(256)
fn extract(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let k = launched_id(wid, lid);
    if k >= atomicLoad(&work[WALK + 3u]) {
        return;
    }
    let v = atomicLoad(&work[V_COUNT]);
    var i = 0u;
    if k < v {
        i = v_list[k].first_instance;
    } else {
        i = refill_list[k - v].first_instance;
    }
    // Only effective occluders walk; objects tested alone are groups of
    // their own (`alone`), visible untested when they occlude.
    if occluders[i] == 0u || (bounds[i].flags & (REMOVED | ALONE)) != 0u {
        return;
    }
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
    let c = atomicAdd(&work[COLLECT + 3u], 1u);
    atomicStore(&work[CANDIDATES + c], n);
    let threads = launch(c + 2u);
    atomicMax(&work[COLLECT], threads.x);
    atomicMax(&work[COLLECT + 1u], threads.y);
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
    if t > atomicLoad(&work[COLLECT + 3u]) || frame.node_count == 0u {
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
