// HROC step 5, the next frame's occluders V (Lee et al. 2021 §3.1, §4.2),
// the last compute pass of the frame, one dispatch:
// merge  — next V = O ∪ D (D alone without OCCLUDERS_STAY);
// filter — next V = the objects owning a pixel of the ID target (OF).
// Its threads also record, with COVER, the cells of the seed's grid the
// frame's final depth covers (for the next frame's refill of V's holes,
// hroc_seed.wgsl), and reset the walk's counts and launch for the next
// frame's step 2 (hroc_groups.wgsl), so no clear or copy is recorded for
// them. Bindings as in hroc_groups.wgsl.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(3) var<storage, read> occluders: array<u32>;      // O marks
@group(0) @binding(8) var<storage, read> drawn: array<u32>;           // D marks
@group(0) @binding(9) var<storage, read_write> visible: array<atomic<u32>>; // next V
@group(0) @binding(10) var ids: HostIds;
@group(0) @binding(12) var depth: HostDepth;
@group(0) @binding(16) var<storage, read_write> covered: array<u32>;  // per cell: this frame drew there
@group(0) @binding(18) var<storage, read_write> collect_launch: array<u32>;
@group(0) @binding(19) var<storage, read_write> work: array<u32>;
// With MEASURE: [0] objects the filter keeps, [1] objects O ∪ D holds
// (what the merge would keep), for the view's filter gate
// (`cull/hroc/gate.rs`).
@group(0) @binding(20) var<storage, read_write> filter_tally: array<atomic<u32>, 7>;

// Record the covered cells (the refill runs: `Seed::Cuts`).
override COVER: bool = true;
override SEED_COLS: u32 = 64u;
override SEED_ROWS: u32 = 36u;

// The end-of-frame duties of thread `t` (a flat index): its cell of the
// seed's grid, and with thread 0 the reset of step 2's counts.
fn end_of_frame(t: u32) {
    if t == 0u {
        // The collection's launch: the root's thread alone until a walk lists a candidate.
        collect_launch[0] = 1u;
        collect_launch[1] = 1u;
        collect_launch[2] = 1u;
        // This frame's walk (objects walked from, candidates), kept for debugging.
        work[2] = work[0];
        work[3] = work[1];
        work[0] = 0u;
        work[1] = 0u;
    }
    if COVER && t < SEED_COLS * SEED_ROWS {
        let p = grid_cell_pixel(t, vec2<u32>(SEED_COLS, SEED_ROWS), frame.viewport.xy);
        covered[t] = u32(farthest_host_depth(depth, p, frame.reversed) < 1.0);
    }
}

// O joins next V (else D alone is next V: with marks from boxes at the
// end of the frame, D holds V's objects in front of the final depth, and O
// is all of V).
override OCCLUDERS_STAY: bool = true;

@compute @workgroup_size(256)
fn merge(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = flat_id(wid, nwg, lid, 256u);
    end_of_frame(i);
    if i < frame.object_count {
        atomicStore(&visible[i], select(0u, 1u, (OCCLUDERS_STAY && occluders[i] != 0u) || drawn[i] != 0u));
    }
}

// Occluder filtering (§4.2): the item buffer decides the next occluders.
// Each thread reads the centre pixel of each FILTER_STRIDE² square in a
// tile of FILTER_TILE² such squares, every sample of it, and marks an
// object once for each run of pixels it owns: neighbours mostly belong to
// one object, so a quarter of the threads and few stores do the work of
// one thread per pixel.
override FILTER_STRIDE: u32 = 1u;
override FILTER_TILE: u32 = 2u;
// Count what the filter keeps against what the merge would keep.
override MEASURE: bool = false;

@compute @workgroup_size(16, 16)
fn filter_occluders(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let t = gid.y * nwg.x * 16u + gid.x;
    end_of_frame(t);
    if MEASURE {
        // O ∪ D, the threads striding over the objects.
        let threads = nwg.x * nwg.y * 256u;
        var merged = 0u;
        for (var i = t; i < frame.object_count; i += threads) {
            merged += u32(occluders[i] != 0u || drawn[i] != 0u);
        }
        if merged > 0u {
            atomicAdd(&filter_tally[1], merged);
        }
    }
    let size = textureDimensions(ids);
    var last = 0u;
    for (var ty = 0u; ty < FILTER_TILE; ty++) {
        for (var tx = 0u; tx < FILTER_TILE; tx++) {
            let px = (gid.xy * FILTER_TILE + vec2<u32>(tx, ty)) * FILTER_STRIDE + vec2<u32>(FILTER_STRIDE / 2u);
            if px.x >= size.x || px.y >= size.y {
                continue;
            }
            for (var s = 0; s < i32(HOST_SAMPLES); s++) {
                let id = host_id(ids, vec2<i32>(px), s);
                if id != 0u && id != last {
                    if MEASURE {
                        if atomicExchange(&visible[id - 1u], 1u) == 0u {
                            atomicAdd(&filter_tally[0], 1u);
                        }
                    } else {
                        atomicStore(&visible[id - 1u], 1u);
                    }
                    last = id;
                }
            }
        }
    }
}
