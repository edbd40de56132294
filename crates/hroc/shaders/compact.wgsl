// Ordered stream compaction of per-object draw commands by a flag per item:
// a three-pass prefix sum (block sums, scan of block sums, scatter). Object
// order is kept so equal-depth surfaces never flicker (HROC §4.1).

const WG: u32 = 256u;

struct Params {
    n: u32,
    blocks: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> flags: array<u32>;
@group(0) @binding(2) var<storage, read> src: array<DrawCommand>;
@group(0) @binding(3) var<storage, read_write> dst: array<DrawCommand>;
@group(0) @binding(4) var<storage, read_write> block_sums: array<u32>;
@group(0) @binding(5) var<storage, read_write> count: array<u32>;

var<workgroup> scan: array<u32, WG>;

// Inclusive scan of `v` across the workgroup (Hillis–Steele).
fn workgroup_scan(lid: u32, v: u32) -> u32 {
    scan[lid] = v;
    workgroupBarrier();
    for (var d = 1u; d < WG; d = d << 1u) {
        var x = 0u;
        if lid >= d {
            x = scan[lid - d];
        }
        workgroupBarrier();
        scan[lid] += x;
        workgroupBarrier();
    }
    return scan[lid];
}

fn flag(i: u32) -> u32 {
    if i < params.n && flags[i] != 0u {
        return 1u;
    }
    return 0u;
}

@compute @workgroup_size(256)
fn block_sum(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let block = wid.y * nwg.x + wid.x;
    let total = workgroup_scan(lid, flag(block * WG + lid));
    if lid == WG - 1u && block < params.blocks {
        block_sums[block] = total;
    }
}

// One workgroup turns block sums into exclusive block offsets and writes the count.
@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_index) lid: u32) {
    var carry = 0u;
    for (var base = 0u; base < params.blocks; base += WG) {
        let i = base + lid;
        var v = 0u;
        if i < params.blocks {
            v = block_sums[i];
        }
        let inclusive = workgroup_scan(lid, v);
        if i < params.blocks {
            block_sums[i] = carry + inclusive - v;
        }
        carry += scan[WG - 1u];
        workgroupBarrier();
    }
    if lid == 0u {
        count[0] = carry;
    }
}

@compute @workgroup_size(256)
fn scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let block = wid.y * nwg.x + wid.x;
    let i = block * WG + lid;
    let f = flag(i);
    let inclusive = workgroup_scan(lid, f);
    if f == 1u {
        dst[block_sums[block] + inclusive - 1u] = src[i];
    }
}
