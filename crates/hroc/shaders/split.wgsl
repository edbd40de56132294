// Object flags over a list handed to the host (src/flag_split.rs): commands
// of objects whose flags `params.y` holds are emptied in place
// (instance_count 0, so the list keeps its order and count);
// NOT_OCCLUDER objects the method drew are collected to be drawn last,
// against the final depth; CUTOUT objects go to the list's cutout list
// (the same slots, every other command empty), which the host draws right
// after it with its alpha-tested pipeline.

@group(0) @binding(0) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(1) var<storage, read> src: array<DrawCommand>;
@group(0) @binding(2) var<storage, read> count: array<u32>;
@group(0) @binding(3) var<storage, read_write> dst: array<DrawCommand>;
@group(0) @binding(4) var<storage, read_write> deferred: array<u32>;
// x: the list's bound; y: the flags that empty a command; z: 1 to fill the cutout list.
@group(0) @binding(5) var<uniform> params: vec4<u32>;
@group(0) @binding(6) var<storage, read_write> cutouts: array<DrawCommand>;

@compute @workgroup_size(256)
fn split(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= min(min(count[0], params.x), min(arrayLength(&src), arrayLength(&dst))) {
        return;
    }
    var c = src[i];
    let flags = bounds[c.first_instance].flags;
    if (flags & NOT_OCCLUDER) != 0u && c.instance_count > 0u && c.index_count > 0u {
        deferred[c.first_instance] = 1u;
    }
    if params.z != 0u && i < arrayLength(&cutouts) {
        var cut = c;
        if (flags & CUTOUT) == 0u || (flags & params.y & ~CUTOUT) != 0u {
            cut.instance_count = 0u;
        }
        cutouts[i] = cut;
    }
    if (flags & params.y) != 0u {
        c.instance_count = 0u;
    }
    dst[i] = c;
}
