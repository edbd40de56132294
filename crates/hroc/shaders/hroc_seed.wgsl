// HROC step 0 after a camera cut: seed the occluders V from a coarse
// grid of rays. Bindings as in hroc_groups.wgsl.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(9) var<storage, read_write> visible: array<u32>;   // V

// Occluder seed (HROC §6 names incoherent frames as a limit: after a cut,
// last frame's V occludes nothing here). One ray per cell of a coarse
// screen grid walks the BVH and marks the object whose box it enters first;
// those objects are V. For speed only: V may be any set of objects, and no
// culling decision rests on it.
override SEED_COLS: u32 = 64u;
override SEED_ROWS: u32 = 36u;

@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>) {
    let cell = gid.x;
    if cell >= SEED_COLS * SEED_ROWS || frame.node_count == 0u {
        return;
    }
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
    if hit != NO_HIT {
        visible[hit] = 1u;
    }
}

const NO_HIT: u32 = 0xffffffffu;
