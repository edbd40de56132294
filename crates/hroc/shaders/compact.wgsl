// Ordered stream compaction of per-object draw commands by a flag per item
// (non-zero, or equal to `select` when that is not 0):
// a three-pass prefix sum (block sums, scan of block sums, scatter). Object
// order is kept so equal-depth surfaces never flicker (HROC §4.1).

const WG: u32 = SCAN_WG;
// Items per thread, consecutive: a block is WG * ITEMS items. Counting a
// run of flags serially costs no barrier, and the scans' barriers (what a
// CPU rasterizer pays most for, one coroutine switch per SIMD lane group)
// are paid once per block of 2048 items instead of once per 256.
const ITEMS: u32 = 8u;

struct Params {
    n: u32,
    blocks: u32,
    select: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> flags: array<u32>;
@group(0) @binding(2) var<storage, read> src: array<DrawCommand>;
@group(0) @binding(3) var<storage, read_write> dst: array<DrawCommand>;
@group(0) @binding(4) var<storage, read_write> block_sums: array<u32>;
@group(0) @binding(5) var<storage, read_write> count: array<u32>;

var<workgroup> block_total: atomic<u32>;

fn flag(i: u32) -> u32 {
    if i < params.n && flags[i] != 0u && (params.select == 0u || flags[i] == params.select) {
        return 1u;
    }
    return 0u;
}

// Flags set among this thread's ITEMS items from `first`.
fn run_count(first: u32) -> u32 {
    var c = 0u;
    for (var k = 0u; k < ITEMS; k++) {
        c += flag(first + k);
    }
    return c;
}

@compute @workgroup_size(256)
fn block_sum(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let block = wid.y * nwg.x + wid.x;
    atomicAdd(&block_total, run_count((block * WG + lid) * ITEMS));
    workgroupBarrier();
    if lid == 0u && block < params.blocks {
        block_sums[block] = atomicLoad(&block_total);
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
    let first = (block * WG + lid) * ITEMS;
    let c = run_count(first);
    let inclusive = workgroup_scan(lid, c);
    if block >= params.blocks {
        return;
    }
    var out = block_sums[block] + inclusive - c;
    for (var k = 0u; k < ITEMS; k++) {
        if flag(first + k) == 1u {
            dst[out] = src[first + k];
            out += 1u;
        }
    }
}

// The whole compaction in one workgroup, when the items fit one block
// (`blocks` is 1): the block's scan gives each thread its offset and the
// count, so no block sums are written or scanned.
@compute @workgroup_size(256)
fn compact_block(@builtin(local_invocation_index) lid: u32) {
    let first = lid * ITEMS;
    let c = run_count(first);
    let inclusive = workgroup_scan(lid, c);
    var out = inclusive - c;
    for (var k = 0u; k < ITEMS; k++) {
        if flag(first + k) == 1u {
            dst[out] = src[first + k];
            out += 1u;
        }
    }
    if lid == WG - 1u {
        count[0] = inclusive;
    }
}
