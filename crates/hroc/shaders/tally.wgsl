// Objects and triangles the lists of a frame draw: the commands [0,
// min(count, max_count)) of each that have an instance (methods zero
// `instance_count` of the objects they cull). One dispatch counts up to
// three lists, recorded once at the end of the frame (tally.rs): each
// workgroup sums what its threads see, then adds it to the frame's totals.
// A grid of at most TALLY_THREADS (tally.rs) strides over the commands:
// the pass costs what the lists hold, not their capacity.

@group(0) @binding(0) var<storage, read> commands_a: array<DrawCommand>;
@group(0) @binding(1) var<storage, read> count_a: array<u32>;
@group(0) @binding(4) var<storage, read> commands_b: array<DrawCommand>;
@group(0) @binding(5) var<storage, read> count_b: array<u32>;
@group(0) @binding(6) var<storage, read> commands_c: array<DrawCommand>;
@group(0) @binding(7) var<storage, read> count_c: array<u32>;
// xyz: the max_count of lists a, b and c (0: no list in that slot).
@group(0) @binding(2) var<uniform> limit: vec4<u32>;
// [objects, triangles]
@group(0) @binding(3) var<storage, read_write> totals: array<atomic<u32>, 2>;

var<workgroup> local: array<atomic<u32>, 2>;

// Objects and triangles of a command (0 when it draws nothing).
fn drawn(c: DrawCommand) -> vec2<u32> {
    if c.instance_count > 0u && c.index_count > 0u {
        return vec2<u32>(1u, c.index_count / 3u);
    }
    return vec2<u32>(0u);
}

@compute @workgroup_size(64)
fn tally(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let stride = nwg.x * nwg.y * 64u;
    let first = flat_id(wid, nwg, lid, 64u);
    var sum = vec2<u32>(0u);
    for (var i = first; i < min(count_a[0], limit.x); i += stride) {
        sum += drawn(commands_a[i]);
    }
    for (var i = first; i < min(count_b[0], limit.y); i += stride) {
        sum += drawn(commands_b[i]);
    }
    for (var i = first; i < min(count_c[0], limit.z); i += stride) {
        sum += drawn(commands_c[i]);
    }
    if sum.x > 0u {
        atomicAdd(&local[0], sum.x);
        atomicAdd(&local[1], sum.y);
    }
    workgroupBarrier();
    if lid == 0u {
        let objects = atomicLoad(&local[0]);
        if objects > 0u {
            atomicAdd(&totals[0], objects);
            atomicAdd(&totals[1], atomicLoad(&local[1]));
        }
    }
}
