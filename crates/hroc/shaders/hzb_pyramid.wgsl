// Hi-Z pyramid (two-phase Hi-Z culling; WOC reuses it): every level in one
// storage buffer, level 0 at full resolution. MAX reduction of standard
// depth (near 0, far 1; a reversed attachment is read as 1 - d): a texel holds the farthest
// depth of its footprint, so a box nearer than it may be visible.
// Non-power-of-two sizes: level i+1 is floor(size_i / 2) (at least 1) and
// its last texel on a side also takes the extra row/column of an odd level
// i, so each texel covers its whole footprint and pixel p of level 0 lies
// in texel min(p >> i, size_i - 1) of level i.

struct Mip {
    offset: u32,
    width: u32,
    height: u32,
    _pad: u32,
}

struct Step {
    level: u32,
    reversed: u32, // 1: the depth attachment is reversed (read as 1 - d)

    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> step: Step;
@group(0) @binding(1) var<storage, read> mips: array<Mip>;
@group(0) @binding(2) var<storage, read_write> hiz: array<f32>;
@group(0) @binding(3) var depth: HostDepth;

fn load_depth(p: vec2<u32>) -> f32 {
    return farthest_host_depth(depth, vec2<i32>(p), step.reversed);
}

// The texels [lo, hi] of level `src` that texel t of the next level `dst`
// covers: 2t and 2t + 1, and the rest of the row/column when t is last.
fn footprint(t: vec2<u32>, dst: Mip, src: Mip) -> array<vec2<u32>, 2> {
    let last = vec2<u32>(src.width, src.height) - 1u;
    let lo = min(2u * t, last);
    let hi = select(min(2u * t + 1u, last), last, t == vec2<u32>(dst.width, dst.height) - 1u);
    return array<vec2<u32>, 2>(lo, hi);
}

// Levels 0 and 1 in one pass: one thread per level-1 texel copies its
// footprint of the depth target into level 0 and writes the maximum.
@compute @workgroup_size(16, 16)
fn from_depth(@builtin(global_invocation_id) gid: vec3<u32>) {
    let src = mips[0];
    if arrayLength(&mips) == 1u {
        if all(gid.xy == vec2<u32>(0u)) {
            hiz[src.offset] = load_depth(vec2<u32>(0u));
        }
        return;
    }
    let dst = mips[1];
    if gid.x >= dst.width || gid.y >= dst.height {
        return;
    }
    let f = footprint(gid.xy, dst, src);
    var far = 0.0;
    for (var y = f[0].y; y <= f[1].y; y++) {
        for (var x = f[0].x; x <= f[1].x; x++) {
            let d = load_depth(vec2<u32>(x, y));
            hiz[src.offset + y * src.width + x] = d;
            far = max(far, d);
        }
    }
    hiz[dst.offset + gid.y * dst.width + gid.x] = far;
}

@compute @workgroup_size(16, 16)
fn reduce(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dst = mips[step.level];
    let src = mips[step.level - 1u];
    if gid.x >= dst.width || gid.y >= dst.height {
        return;
    }
    let f = footprint(gid.xy, dst, src);
    var far = 0.0;
    for (var y = f[0].y; y <= f[1].y; y++) {
        for (var x = f[0].x; x <= f[1].x; x++) {
            far = max(far, hiz[src.offset + y * src.width + x]);
        }
    }
    hiz[dst.offset + gid.y * dst.width + gid.x] = far;
}

// Levels step.level.. to the top in one workgroup, level after level with
// a barrier between: small levels cost less than a dispatch each.
@compute @workgroup_size(256)
fn reduce_tail(@builtin(local_invocation_index) lid: u32) {
    let levels = arrayLength(&mips);
    for (var l = step.level; l < levels; l++) {
        let dst = mips[l];
        let src = mips[l - 1u];
        for (var i = lid; i < dst.width * dst.height; i += 256u) {
            let t = vec2<u32>(i % dst.width, i / dst.width);
            let f = footprint(t, dst, src);
            var far = 0.0;
            for (var y = f[0].y; y <= f[1].y; y++) {
                for (var x = f[0].x; x <= f[1].x; x++) {
                    far = max(far, hiz[src.offset + y * src.width + x]);
                }
            }
            hiz[dst.offset + i] = far;
        }
        storageBarrier();
    }
}
