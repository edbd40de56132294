// BVH refit on the GPU (HROC §6: the hierarchy follows moving objects).
// clear  — every interior node's box starts empty;
// leaves — one thread per object: takes the host's new box (when given),
//          writes its leaf, and widens every ancestor with atomic min/max
//          on order-preserving integer encodings of the floats, stopping
//          at the first ancestor that already held its box (whoever widened
//          that ancestor carries the same values further up);
// decode — interior nodes take their boxes back as floats.
// Leaves of DYNAMIC and removed objects keep their box (frozen leaves: the
// hybrid tests DYNAMIC objects on their own, from their object box).

struct RefitParams {
    objects: u32,
    nodes: u32,
    from_host: u32, // 1: host_boxes holds every object's new box
    _pad: u32,
}

@group(0) @binding(0) var<uniform> params: RefitParams;
@group(0) @binding(1) var<storage, read> host_boxes: array<vec4<f32>>; // min.xyz, _, max.xyz, _
@group(0) @binding(2) var<storage, read_write> bounds: array<ObjectBounds>;
@group(0) @binding(3) var<storage, read_write> nodes: array<BvhNode>;
@group(0) @binding(4) var<storage, read> leaf_of_object: array<u32>;
@group(0) @binding(5) var<storage, read_write> scratch: array<atomic<u32>>; // 6 per node

const NO_LEAF: u32 = 0xffffffffu;
const NO_PARENT: u32 = 0xffffffffu;
// A host box that is not finite and ordered covers everything the culler
// can test (the object is then never culled) rather than a wrong place.
const HUGE: f32 = 1e18;

fn ordered(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn unordered(u: u32) -> f32 {
    return bitcast<f32>(select(~u, u & 0x7fffffffu, (u & 0x80000000u) != 0u));
}

@compute @workgroup_size(256)
fn clear(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = flat_id(wid, nwg, lid, 256u);
    if n >= params.nodes {
        return;
    }
    for (var k = 0u; k < 3u; k++) {
        atomicStore(&scratch[6u * n + k], 0xffffffffu);
        atomicStore(&scratch[6u * n + 3u + k], 0u);
    }
}

fn widen(n: u32, lo: vec3<u32>, hi: vec3<u32>) -> bool {
    var changed = false;
    for (var k = 0u; k < 3u; k++) {
        changed = (atomicMin(&scratch[6u * n + k], lo[k]) > lo[k]) || changed;
        changed = (atomicMax(&scratch[6u * n + 3u + k], hi[k]) < hi[k]) || changed;
    }
    return changed;
}

@compute @workgroup_size(256)
fn leaves(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= params.objects {
        return;
    }
    let flags = bounds[i].flags;
    let frozen = (flags & (DYNAMIC | REMOVED)) != 0u;
    if params.from_host != 0u && (flags & REMOVED) == 0u {
        var lo = host_boxes[2u * i].xyz;
        var hi = host_boxes[2u * i + 1u].xyz;
        // NaN fails every comparison, so it lands here too.
        if !(all(abs(lo) <= vec3<f32>(HUGE)) && all(abs(hi) <= vec3<f32>(HUGE)) && all(lo <= hi)) {
            lo = vec3<f32>(-HUGE);
            hi = vec3<f32>(HUGE);
        }
        bounds[i].min = lo;
        bounds[i].max = hi;
    }
    let leaf = leaf_of_object[i];
    if leaf == NO_LEAF {
        return;
    }
    var lo = nodes[leaf].min;
    var hi = nodes[leaf].max;
    if !frozen {
        lo = bounds[i].min;
        hi = bounds[i].max;
        nodes[leaf].min = lo;
        nodes[leaf].max = hi;
    }
    let elo = vec3<u32>(ordered(lo.x), ordered(lo.y), ordered(lo.z));
    let ehi = vec3<u32>(ordered(hi.x), ordered(hi.y), ordered(hi.z));
    var n = nodes[leaf].parent;
    while n != NO_PARENT && widen(n, elo, ehi) {
        n = nodes[n].parent;
    }
}

@compute @workgroup_size(256)
fn decode(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = flat_id(wid, nwg, lid, 256u);
    if n >= params.nodes || (nodes[n].child & LEAF_BIT) != 0u {
        return;
    }
    let s = 6u * n;
    nodes[n].min = vec3<f32>(unordered(atomicLoad(&scratch[s])), unordered(atomicLoad(&scratch[s + 1u])), unordered(atomicLoad(&scratch[s + 2u])));
    nodes[n].max = vec3<f32>(unordered(atomicLoad(&scratch[s + 3u])), unordered(atomicLoad(&scratch[s + 4u])), unordered(atomicLoad(&scratch[s + 5u])));
}
