// The tail of a list drawn without a GPU count (an emulated draw count):
// the commands [count, max_count) get instance_count 0 and draw nothing.
// A grid of at most LIST_THREADS (list_pass.rs) strides over them.

@group(0) @binding(0) var<storage, read_write> commands: array<DrawCommand>;
@group(0) @binding(1) var<storage, read> count: array<u32>;
// x: the list's max_count.
@group(0) @binding(2) var<uniform> params: vec4<u32>;

@compute @workgroup_size(64)
fn tail(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    // (A count past the bound, as a list drawn whole may hold, empties nothing.)
    for (var i = min(count[0], params.x) + flat_id(wid, nwg, lid, 64u); i < params.x; i += nwg.x * nwg.y * 64u) {
        commands[i].instance_count = 0u;
    }
}
