// ROC compute passes (one thread per object):
// select — pick the boxes to rasterize: objects in the frustum (roc: only
//          those not drawn yet, i.e. not in V; roc-all: every one); boxes
//          reaching the near plane are visible without a test;
// split  — roc-all after the test: draw now what passed and was not in V;
//          the test result is next frame's V (as NVIDIA's temporal ROC).

override ALL: bool = false;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> bounds: array<BvhNode>;    // object boxes (ObjectBounds layout)
@group(0) @binding(2) var<storage, read_write> visible: array<u32>; // V
@group(0) @binding(3) var<storage, read_write> tested: array<u32>;  // box-test marks
@group(0) @binding(4) var<storage, read_write> list: array<u32>;    // boxes to rasterize
@group(0) @binding(5) var<storage, read_write> args: array<atomic<u32>>; // DrawArgs of the box draw
@group(0) @binding(6) var<storage, read_write> fresh: array<u32>;   // roc-all: to draw now

@compute @workgroup_size(256)
fn select_boxes(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i == 0u {
        atomicStore(&args[0], 36u);
    }
    if i >= frame.object_count || (!ALL && visible[i] != 0u) {
        return;
    }
    let b = padded_box(bounds[i], frame.eye.xyz, pixel_angle(frame));
    if !box_in_frustum(frame.planes, b.min, b.max) {
        return;
    }
    if crosses_near(frame.near_plane, frame.near, b) {
        tested[i] = 1u;
        return;
    }
    list[atomicAdd(&args[1], 1u)] = i;
}

@compute @workgroup_size(256)
fn split(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= frame.object_count {
        return;
    }
    let t = tested[i];
    fresh[i] = select(0u, 1u, t != 0u && visible[i] == 0u);
    visible[i] = t;
}
