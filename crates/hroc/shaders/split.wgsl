// Object flags over a method's draw list (src/host.rs FlagSplit): commands
// of flagged objects are emptied in place (instance_count 0, so the list
// keeps its order and count); NOT_OCCLUDER objects the method drew are
// collected to be drawn last, against the final depth.

@group(0) @binding(0) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(1) var<storage, read> src: array<DrawCommand>;
@group(0) @binding(2) var<storage, read> count: array<u32>;
@group(0) @binding(3) var<storage, read_write> dst: array<DrawCommand>;
@group(0) @binding(4) var<storage, read_write> deferred: array<u32>;
@group(0) @binding(5) var<uniform> max_count: vec4<u32>; // x: the list's bound

@compute @workgroup_size(256)
fn split(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= min(min(count[0], max_count.x), min(arrayLength(&src), arrayLength(&dst))) {
        return;
    }
    var c = src[i];
    let flags = bounds[c.first_instance].flags;
    if (flags & NOT_OCCLUDER) != 0u && c.instance_count > 0u && c.index_count > 0u {
        deferred[c.first_instance] = 1u;
    }
    if (flags & SPLIT_FLAGS) != 0u {
        c.instance_count = 0u;
    }
    dst[i] = c;
}
