// Visibility as data (`View::visibility`): after each list the culler
// hands, the slot of every object the list draws gets this frame's stamp
// of the list's phase. The buffer's header holds the frame's stamp of
// every phase, so a host's shader tells in which phase an object is drawn
// by one comparison (`device::visibility_wgsl`). The commands stamped are
// [0, min(count, max_count)), what the host draws of the list; a grid of
// at most LIST_THREADS (list_pass.rs) strides over them.

@group(0) @binding(0) var<storage, read> commands: array<DrawCommand>;
@group(0) @binding(1) var<storage, read> count: array<u32>;
// x: the list's max_count; y: the stamp of its phase this frame.
@group(0) @binding(2) var<uniform> params: vec4<u32>;
// HEADER stamps (one per phase), then one u32 per object slot.
@group(0) @binding(3) var<storage, read_write> visibility: array<u32>;

override HEADER: u32 = 8u;

@compute @workgroup_size(64)
fn stamp(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = min(count[0], params.x);
    for (var i = flat_id(wid, nwg, lid, 64u); i < n; i += nwg.x * nwg.y * 64u) {
        let c = commands[i];
        if c.instance_count != 0u && HEADER + c.first_instance < arrayLength(&visibility) {
            visibility[HEADER + c.first_instance] = params.y;
        }
    }
}
