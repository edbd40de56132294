// Frustum culling of a set of views (`Culler::cull_views`, set_frustum.rs):
// every view of the set that culls by its frustum alone this frame gets
// one workgroup, one dispatch each in one compute pass for the whole set.
// The workgroup tests the objects' boxes against the view's frustum (the
// test `vfc.wgsl` makes) and packs the commands of those inside, 2,048
// objects at a time, in object order, carrying the count from block to
// block: `compact.wgsl`'s ordered compaction without its block sums, which
// one workgroup does not need. Then it writes the list's count, and what
// the list draws (objects and triangles, as `tally.wgsl` counts them) to
// the view's tally. With an emulated draw count (`ZERO_TAIL`) it empties
// the commands past the count too, as `tail.wgsl` does.

override ZERO_TAIL: bool = false;

const WG: u32 = SCAN_WG;
// Objects per thread and block, as in compact.wgsl.
const ITEMS: u32 = 8u;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> bounds: array<ObjectBounds>;
@group(0) @binding(2) var<storage, read> src: array<DrawCommand>;
@group(0) @binding(3) var<storage, read_write> dst: array<DrawCommand>;
@group(0) @binding(4) var<storage, read_write> count: array<u32>;
// The view's tally: [objects, triangles].
@group(0) @binding(5) var<storage, read_write> totals: array<u32>;

var<workgroup> sums: array<atomic<u32>, 2>;

fn inside(i: u32) -> bool {
    if i >= frame.object_count {
        return false;
    }
    let b = bounds[i];
    return box_in_frustum(frame.planes, b.min, b.max);
}

@compute @workgroup_size(256)
fn pack(@builtin(local_invocation_index) lid: u32) {
    let n = frame.object_count;
    // Packed so far (the same in every thread).
    var carry = 0u;
    var objects = 0u;
    var triangles = 0u;
    for (var base = 0u; base < n; base += WG * ITEMS) {
        let first = base + lid * ITEMS;
        var mask = 0u;
        var c = 0u;
        for (var k = 0u; k < ITEMS; k++) {
            if inside(first + k) {
                mask |= 1u << k;
                c += 1u;
            }
        }
        let inclusive = workgroup_scan(lid, c);
        var out = carry + inclusive - c;
        for (var k = 0u; k < ITEMS; k++) {
            if (mask & (1u << k)) != 0u {
                let command = src[first + k];
                dst[out] = command;
                out += 1u;
                if command.instance_count > 0u && command.index_count > 0u {
                    objects += 1u;
                    triangles += command.index_count / 3u;
                }
            }
        }
        carry += scan[WG - 1u];
        // The next block's scan overwrites `scan`.
        workgroupBarrier();
    }
    if ZERO_TAIL {
        for (var i = carry + lid; i < n; i += WG) {
            dst[i].instance_count = 0u;
        }
    }
    if objects > 0u {
        atomicAdd(&sums[0], objects);
        atomicAdd(&sums[1], triangles);
    }
    workgroupBarrier();
    if lid == 0u {
        count[0] = carry;
        totals[0] = atomicLoad(&sums[0]);
        totals[1] = atomicLoad(&sums[1]);
    }
}
