// The forward host's own shader: interleaved position/normal/uv, one
// transform and material per instance (instance_index = hroc's object
// index), Lambert lighting with a checker from the uvs, shadowed by the
// light's cascaded shadow map (shadows.rs). With hroc's
// early-Z marks, marked.wgsl and hroc's marks snippet (hroc::device::marks_wgsl(1),
// group 1) are appended; with ID marks, this file is the whole shader.

struct Camera {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
    // The light's cascades, finest first: view-projections, and how many.
    cascades: array<mat4x4<f32>, 4>,
    cascade_count: vec4<u32>,
}

// Multisampled targets hold IDs as Rg16Uint: the low 16 bits in r, the high in g.
override SPLIT_IDS: bool = false;

struct Instance {
    model: mat4x4<f32>,
    color: vec4<f32>, // rgb, alpha (1 opaque)
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
// The host's own instrumentation: 1 for every object with a fragment that
// passed the depth test this frame (exact for blended objects, drawn last).
@group(0) @binding(2) var<storage, read_write> seen: array<u32>;
@group(0) @binding(3) var shadow_map: texture_depth_2d_array;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) object: u32,
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) world: vec3<f32>,
}

@vertex
fn vs(v: VsIn) -> VsOut {
    let m = instances[v.object].model;
    var out: VsOut;
    out.world = (m * vec4<f32>(v.position, 1.0)).xyz;
    out.clip = camera.view_proj * vec4<f32>(out.world, 1.0);
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.object = v.object;
    return out;
}

// 1 where the light reaches `world`, 0 in shadow: the finest cascade that
// holds the point decides (the sampler compares as the depth test does).
fn lit(world: vec3<f32>) -> f32 {
    for (var i = 0u; i < camera.cascade_count.x; i++) {
        let p = camera.cascades[i] * vec4<f32>(world, 1.0);
        if all(abs(p.xy) <= vec2<f32>(1.0)) && p.z >= 0.0 && p.z <= 1.0 {
            return textureSampleCompareLevel(shadow_map, shadow_sampler, vec2<f32>(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y), i32(i), p.z);
        }
    }
    return 1.0;
}

fn shade(in: VsOut) -> vec4<f32> {
    let c = instances[in.object].color;
    let lambert = 0.3 + 0.7 * abs(dot(normalize(in.normal), camera.light_dir.xyz)) * lit(in.world);
    let checker = select(0.85, 1.0, (i32(floor(in.uv.x * 4.0)) + i32(floor(in.uv.y * 4.0))) % 2 == 0);
    return vec4<f32>(c.rgb * lambert * checker, c.a);
}

struct Opaque {
    @location(0) color: vec4<f32>,
    @location(1) id: vec4<u32>,
}

// An ID as its target holds it.
fn id_texel(id: u32) -> vec4<u32> {
    return select(vec4<u32>(id, 0u, 0u, 0u), vec4<u32>(id & 0xffffu, id >> 16u, 0u, 0u), SPLIT_IDS);
}

// Opaque: object IDs (hroc's ID marks and OF read them).
fn opaque(in: VsOut) -> Opaque {
    seen[in.object] = 1u;
    var out: Opaque;
    out.color = shade(in);
    out.id = id_texel(in.object + 1u);
    return out;
}

@fragment
fn fs_opaque(in: VsOut) -> Opaque {
    return opaque(in);
}

// Alpha-blended: depth test on, no depth writes; the pipeline masks the ID
// target off. Forced early-Z keeps `seen` exact; on a device without it
// (DX12, Metal) the attribute is dropped and `seen` may over-count.
@fragment @early_depth_test(force)
fn fs_blend(in: VsOut) -> Opaque {
    seen[in.object] = 1u;
    var out: Opaque;
    out.color = shade(in);
    out.id = vec4<u32>(0u);
    return out;
}
