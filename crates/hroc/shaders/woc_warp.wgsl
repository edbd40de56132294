// WOC (warping-based occlusion culling [LKE18]): last frame's depth buffer
// forward-splatted into the current view, one thread per old pixel, into
// level 0 of a Hi-Z pyramid (hzb_pyramid.wgsl) held as depth bits:
// non-negative floats order like their bits, so atomicMin keeps the
// nearest. Pixels nothing lands on stay at the far plane (1.0): holes never
// occlude. A splat lands on one pixel, so near silhouettes the warped depth
// can be nearer than what the pixel centre sees now: WOC may miss objects.
// splat — reproject;  save — keep this frame's depth, count the texels no
// splat reached (holes or sky) and reset level 0 to far for the next warp
// (level 0 starts at far).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> reproject: mat4x4<f32>; // current view-proj * inverse(previous)
@group(0) @binding(2) var<storage, read_write> prev_depth: array<f32>;
@group(0) @binding(3) var<storage, read_write> level0: array<atomic<u32>>;
@group(0) @binding(4) var depth: HostDepth;
@group(0) @binding(5) var<storage, read_write> holes: array<atomic<u32>>;

var<workgroup> wg_holes: atomic<u32>;

fn size() -> vec2<u32> {
    return vec2<u32>(frame.viewport.xy);
}

@compute @workgroup_size(16, 16)
fn splat(@builtin(global_invocation_id) gid: vec3<u32>) {
    let s = size();
    if gid.x >= s.x || gid.y >= s.y {
        return;
    }
    let d = prev_depth[gid.y * s.x + gid.x];
    if d >= 1.0 {
        return; // background: nothing to warp
    }
    let ndc = vec2<f32>((f32(gid.x) + 0.5) * frame.viewport.z * 2.0 - 1.0, 1.0 - (f32(gid.y) + 0.5) * frame.viewport.w * 2.0);
    let c = reproject * vec4<f32>(ndc, d, 1.0);
    if c.w <= 0.0 {
        return;
    }
    let p = c.xyz / c.w;
    if p.z < 0.0 || p.z > 1.0 {
        return;
    }
    let px = vec2<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5) * frame.viewport.xy;
    if px.x < 0.0 || px.y < 0.0 || px.x >= frame.viewport.x || px.y >= frame.viewport.y {
        return;
    }
    let q = vec2<u32>(px);
    atomicMin(&level0[q.y * s.x + q.x], bitcast<u32>(p.z));
}

@compute @workgroup_size(16, 16)
fn save(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let s = size();
    let far = bitcast<u32>(1.0);
    if gid.x < s.x && gid.y < s.y {
        let i = gid.y * s.x + gid.x;
        // woc takes standard depth only (Culler::view refuses reversed).
        prev_depth[i] = farthest_host_depth(depth, vec2<i32>(gid.xy), 0u);
        if atomicExchange(&level0[i], far) == far {
            atomicAdd(&wg_holes, 1u);
        }
    }
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&holes[0], atomicLoad(&wg_holes));
    }
}
