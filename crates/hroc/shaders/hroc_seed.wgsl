// HROC's occluder seed from a coarse grid of rays: V after a camera cut
// (step 0, `seed`), and where V's depth left holes (step 1,
// `refill_holes`, against the cells the last frame's depth covered, which
// hroc_next.wgsl records).
// Bindings as in hroc_groups.wgsl, and 12-17 of the refill's own.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(9) var<storage, read_write> visible: array<atomic<u32>>;   // V
@group(0) @binding(12) var depth: HostDepth;
@group(0) @binding(13) var<storage, read> commands: array<DrawCommand>;
@group(0) @binding(14) var<storage, read_write> refill: array<DrawCommand>;
@group(0) @binding(15) var<storage, read_write> refill_count: atomic<u32>;
@group(0) @binding(16) var<storage, read_write> covered: array<u32>;  // per cell: last frame drew there
@group(0) @binding(17) var<storage, read_write> occluders: array<u32>;  // O (read-only at 3 in hroc_groups.wgsl)

// Occluder seed (HROC §6 names incoherent frames as a limit: after a cut,
// last frame's V occludes nothing here). One ray per cell of a coarse
// screen grid walks the BVH and marks the object whose box it enters first;
// those objects are V. For speed only: V may be any set of objects, and no
// culling decision rests on it.
override SEED_COLS: u32 = 64u;
override SEED_ROWS: u32 = 36u;

// The ray through the centre of `cell`: the object whose box it enters
// first, or NO_HIT.
fn first_hit(cell: u32) -> u32 {
    let ndc = vec2<f32>((f32(cell % SEED_COLS) + 0.5) / f32(SEED_COLS) * 2.0 - 1.0, 1.0 - (f32(cell / SEED_COLS) + 0.5) / f32(SEED_ROWS) * 2.0);
    let origin = ray_origin(frame, ndc);
    let dir = (frame.ray_dirs * vec4<f32>(ndc, 1.0, 0.0)).xyz;
    let inv = vec3<f32>(safe_inv(dir.x), safe_inv(dir.y), safe_inv(dir.z));
    var best = 3.0e38;
    var hit = NO_HIT;
    var stack: array<u32, STACK>;
    stack[0] = 0u;
    var sp = 1u;
    while sp > 0u {
        sp -= 1u;
        let node = nodes[stack[sp]];
        let span = ray_box(origin, inv, node.min, node.max);
        let t = max(span.x, 1.0); // t = 1 on the near plane
        if span.y < t || t >= best {
            continue;
        }
        if (node.child & LEAF_BIT) != 0u {
            best = t;
            hit = node.child & ~LEAF_BIT;
        } else if sp + 2u <= STACK {
            stack[sp] = node.child;
            stack[sp + 1u] = node.child + 1u;
            sp += 2u;
        }
    }
    return hit;
}

@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>) {
    let cell = gid.x;
    if cell >= SEED_COLS * SEED_ROWS || frame.node_count == 0u {
        return;
    }
    let hit = first_hit(cell);
    if hit != NO_HIT {
        atomicStore(&visible[hit], 1u);
    }
}

// The pixel at the centre of `cell`.
fn cell_pixel(cell: u32) -> vec2<i32> {
    return grid_cell_pixel(cell, vec2<u32>(SEED_COLS, SEED_ROWS), frame.viewport.xy);
}

// No collapse: V may be too weak to cull (the eye just left the building
// whose wall was last frame's whole view: V is that wall). After V is
// drawn, each cell whose centre pixel V left at the far plane (in any
// sample), where last frame's depth was not (sky stays sky, and costs a
// texel read), casts its ray; the object it enters first, if V did not
// draw it, joins V, O (it is drawn now, so the test may skip it) and the
// refill list, which the host draws as occluders before the test. For
// speed only, as the seed.
@compute @workgroup_size(64)
fn refill_holes(@builtin(global_invocation_id) gid: vec3<u32>) {
    let cell = gid.x;
    if cell >= SEED_COLS * SEED_ROWS || frame.node_count == 0u {
        return;
    }
    if covered[cell] == 0u || farthest_host_depth(depth, cell_pixel(cell), frame.reversed) < 1.0 {
        return;
    }
    let hit = first_hit(cell);
    if hit != NO_HIT && atomicExchange(&visible[hit], 1u) == 0u {
        occluders[hit] = 1u;
        refill[atomicAdd(&refill_count, 1u)] = commands[hit];
    }
}

const NO_HIT: u32 = 0xffffffffu;
