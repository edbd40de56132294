// What occlusion culls in a view, and HROC's frames of frustum culling
// alone where it culls little (`cull/hroc/gate.rs`). Bindings numbered as
// in hroc_groups.wgsl.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(7) var<storage, read_write> occludees: array<u32>; // U flags
@group(0) @binding(9) var<storage, read_write> visible: array<u32>;   // V flags (read)
@group(0) @binding(11) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(13) var<storage, read> commands: array<DrawCommand>;
// The gate's tally: [0], [1] the filter's (hroc_next.wgsl); [2] objects
// in the frustum, [3] of those neither in V nor in U: culled by
// occlusion, [4] their triangles (at least DRAW_TRIANGLES each), [5] the
// frustum's objects the batch test takes (not in V), [6] the culled
// objects' own triangles.
@group(0) @binding(20) var<storage, read_write> tally: array<atomic<u32>, 7>;

// Triangles an object culled saves at least: its draw costs about as
// much, whatever it holds (a box has 12).
const DRAW_TRIANGLES: u32 = 64u;

var<workgroup> inside_sum: atomic<u32>;
var<workgroup> culled_sum: atomic<u32>;
var<workgroup> triangles_sum: atomic<u32>;
var<workgroup> tested_sum: atomic<u32>;
var<workgroup> own_sum: atomic<u32>;

// After the batch test (U final): counts the objects in the frustum and
// those the frame culls by occlusion. A refill's objects, drawn but not
// in V, count as culled: the measure errs toward occlusion culling.
@compute @workgroup_size(256)
fn measure(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i < frame.object_count {
        let b = bounds[i];
        if box_in_frustum(frame.planes, b.min, b.max) {
            atomicAdd(&inside_sum, 1u);
            if visible[i] == 0u {
                atomicAdd(&tested_sum, 1u);
                if occludees[i] == 0u {
                    let own = commands[i].index_count / 3u;
                    atomicAdd(&culled_sum, 1u);
                    atomicAdd(&triangles_sum, max(own, DRAW_TRIANGLES));
                    atomicAdd(&own_sum, own);
                }
            }
        }
    }
    workgroupBarrier();
    if lid == 0u {
        let inside = atomicLoad(&inside_sum);
        if inside > 0u {
            atomicAdd(&tally[2], inside);
            atomicAdd(&tally[3], atomicLoad(&culled_sum));
            atomicAdd(&tally[4], atomicLoad(&triangles_sum));
            atomicAdd(&tally[5], atomicLoad(&tested_sum));
            atomicAdd(&tally[6], atomicLoad(&own_sum));
        }
    }
}

// A frame of frustum culling alone: U = every object whose box meets the
// frustum (the test `vfc.wgsl` makes), packed and drawn as one list.
@compute @workgroup_size(256)
fn frustum(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i < frame.object_count {
        let b = bounds[i];
        occludees[i] = select(0u, 1u, box_in_frustum(frame.planes, b.min, b.max));
    }
}
