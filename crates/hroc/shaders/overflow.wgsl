// Stall-free counters (HROC §6 asks for counters without the stall): the
// first indirect draw of a list takes max_count = an estimate from earlier
// frames' counts; this pass hands a second draw whatever the estimate
// missed: count' = max(count - estimate, 0), and with `stride` > 0 the
// commands [estimate, count) copied to the front of `dst`, so the host
// draws them from offset 0. Nothing is dropped, and nothing waits.
// A grid of at most OVERFLOW_THREADS (stall_free.rs) strides over the
// commands: the pass costs what overflows, not the list's capacity.

struct Overflow {
    estimate: u32,
    stride: u32,   // u32 words per command; 0: the count alone
    capacity: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> p: Overflow;
@group(0) @binding(1) var<storage, read> src: array<u32>;
@group(0) @binding(2) var<storage, read> src_count: array<u32>;
@group(0) @binding(3) var<storage, read_write> dst: array<u32>;
@group(0) @binding(4) var<storage, read_write> dst_count: array<u32>;

@compute @workgroup_size(256)
fn overflow(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    let count = min(src_count[0], p.capacity);
    let extra = select(0u, count - p.estimate, count > p.estimate);
    if i == 0u {
        dst_count[0] = extra;
    }
    if p.stride == 0u {
        return;
    }
    for (var k = i; k < extra; k += nwg.x * nwg.y * 256u) {
        for (var w = 0u; w < p.stride; w += 1u) {
            dst[k * p.stride + w] = src[(p.estimate + k) * p.stride + w];
        }
    }
}
