// View-frustum culling: one thread per object box.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(2) var<storage, read_write> flags: array<u32>;

@compute @workgroup_size(256)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= frame.object_count {
        return;
    }
    let b = bounds[i];
    flags[i] = select(0u, 1u, box_in_frustum(frame.planes, b.min, b.max));
}
