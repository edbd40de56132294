// IOC level step (Lee & Lee, HPG 2020 poster), one thread per node of the
// level's queue, after the queue's boxes were rasterized (roc_boxes.wgsl
// marked the nodes with a passing fragment):
// - outside the frustum, or rasterized without a passing fragment: culled,
//   its whole subtree stays occluded (nothing is marked);
// - otherwise (a passing fragment, or a box reaching the near plane, which
//   is visible without a test): a leaf marks its object visible; an
//   interior node enqueues its children for the next level, or at the
//   bottom level (BOTTOM) marks every object below it visible.
// Decisions are kept in the node marks for statistics and the CPU check:
// 1 = a box fragment passed, 2 = box rasterized, 4 = visible untested.

override BOTTOM: bool = false;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read_write> marks: array<u32>;     // per node
@group(0) @binding(3) var<storage, read> queue_in: array<u32>;
@group(0) @binding(4) var<storage, read> count_in: array<u32>;
@group(0) @binding(5) var<storage, read_write> queue_out: array<u32>;
@group(0) @binding(6) var<storage, read_write> count_out: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read> visible: array<u32>;        // V (drawn already)
@group(0) @binding(8) var<storage, read_write> fresh: array<u32>;    // visible, not in V: to draw
@group(0) @binding(9) var<storage, read> leaf_objects: array<u32>;   // objects in depth-first leaf order
@group(0) @binding(10) var<storage, read> leaf_range: array<vec2<u32>>; // per node: first, count

fn mark_object(o: u32) {
    if visible[o] == 0u {
        fresh[o] = 1u;
    }
}

@compute @workgroup_size(256)
fn expand(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    if i >= count_in[0] {
        return;
    }
    let n = queue_in[i];
    let node = nodes[n];
    let b = padded_box(node, frame.eye.xyz, pixel_angle(frame));
    if !box_in_frustum(frame.planes, b.min, b.max) {
        return;
    }
    let m = marks[n];
    let near = crosses_near(frame.near_plane, frame.near, b);
    marks[n] = m | select(2u, 4u, near);
    if !near && (m & 1u) == 0u {
        return; // occluded: the subtree stays unmarked
    }
    if (node.child & LEAF_BIT) != 0u {
        mark_object(node.child & ~LEAF_BIT);
    } else if BOTTOM {
        let r = leaf_range[n];
        for (var k = 0u; k < r.y; k++) {
            mark_object(leaf_objects[r.x + k]);
        }
    } else {
        let slot = atomicAdd(&count_out[0], 2u);
        queue_out[slot] = node.child;
        queue_out[slot + 1u] = node.child + 1u;
    }
}
