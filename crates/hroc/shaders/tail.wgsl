// The tail of a list drawn without a GPU count (an emulated draw count):
// the commands [count, max_count) get instance_count 0 and draw nothing.
// Commands are `words` u32s each (5 indexed, 4 not), instance_count the
// second word of both.

@group(0) @binding(0) var<storage, read_write> commands: array<u32>;
@group(0) @binding(1) var<storage, read> count: array<u32>;
// x: the list's max_count; y: u32 words per command; z: the list's first
// command in the buffer.
@group(0) @binding(2) var<uniform> params: vec4<u32>;

@compute @workgroup_size(64)
fn tail(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 64u);
    if i >= count[0] && i < params.x {
        commands[(params.z + i) * params.y + 1u] = 0u;
    }
}
