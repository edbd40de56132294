// The tail of a list drawn without a GPU count (an emulated draw count):
// the commands [count, max_count) get instance_count 0 and draw nothing.

@group(0) @binding(0) var<storage, read_write> commands: array<DrawCommand>;
@group(0) @binding(1) var<storage, read> count: array<u32>;
// x: the list's max_count.
@group(0) @binding(2) var<uniform> params: vec4<u32>;

@compute @workgroup_size(64)
fn tail(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 64u);
    if i >= count[0] && i < params.x {
        commands[i].instance_count = 0u;
    }
}
