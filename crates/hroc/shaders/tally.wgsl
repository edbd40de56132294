// Objects and triangles one list draws: its commands [0, min(count,
// max_count)) that have an instance (methods zero `instance_count` of the
// objects they cull). Summed per workgroup, then into the frame's totals.
// A grid of at most LIST_THREADS (list_pass.rs) strides over the commands:
// the pass costs what the list holds, not its capacity.

@group(0) @binding(0) var<storage, read> commands: array<DrawCommand>;
@group(0) @binding(1) var<storage, read> count: array<u32>;
// x: the list's max_count.
@group(0) @binding(2) var<uniform> limit: vec4<u32>;
// [objects, triangles]
@group(0) @binding(3) var<storage, read_write> totals: array<atomic<u32>, 2>;

var<workgroup> local: array<atomic<u32>, 2>;

@compute @workgroup_size(64)
fn tally(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = min(count[0], limit.x);
    var objects = 0u;
    var triangles = 0u;
    for (var i = flat_id(wid, nwg, lid, 64u); i < n; i += nwg.x * nwg.y * 64u) {
        let c = commands[i];
        if c.instance_count > 0u && c.index_count > 0u {
            objects += 1u;
            triangles += c.index_count / 3u;
        }
    }
    if objects > 0u {
        atomicAdd(&local[0], objects);
        atomicAdd(&local[1], triangles);
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
