// ID marks (`Marks::Ids`, for devices without forced early-Z): after an
// occluding list, every object that owns a pixel of the object-ID target
// (the host writes object index + 1, 0 where nothing is drawn) and that
// `within` holds is marked, where a fragment shader would call `hroc_mark`
// under early-Z. `within` keeps out pixels the list did not draw (the
// never-culled objects, the host's own geometry): a method that skips the
// test of what it marks (HROC's O) must not mark those. One thread per
// pixel, which reads every sample of it.

@group(0) @binding(0) var ids: HostIds;
@group(0) @binding(1) var<storage, read_write> marks: array<u32>;
@group(0) @binding(2) var<storage, read> within: array<u32>;

@compute @workgroup_size(16, 16)
fn mark_ids(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(ids);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    for (var s = 0; s < i32(HOST_SAMPLES); s++) {
        let id = host_id(ids, vec2<i32>(gid.xy), s);
        if id != 0u && id <= arrayLength(&marks) && within[id - 1u] != 0u {
            marks[id - 1u] = 1u;
        }
    }
}
