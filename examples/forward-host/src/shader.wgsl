// The forward host's own shader: interleaved position/normal/uv, one
// transform and material per instance (instance_index = hroc's object
// index), Lambert lighting with a checker from the uvs. With hroc's
// early-Z marks, marked.wgsl and hroc's marks snippet (hroc::marks_wgsl(1),
// group 1) are appended; with ID marks, this file is the whole shader.

struct Camera {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
}

struct Instance {
    model: mat4x4<f32>,
    color: vec4<f32>, // rgb, alpha (1 opaque)
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
// The host's own instrumentation: 1 for every object with a fragment that
// passed the depth test this frame (exact for blended objects, drawn last).
@group(0) @binding(2) var<storage, read_write> seen: array<u32>;

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
}

@vertex
fn vs(v: VsIn) -> VsOut {
    let m = instances[v.object].model;
    var out: VsOut;
    out.clip = camera.view_proj * (m * vec4<f32>(v.position, 1.0));
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.object = v.object;
    return out;
}

fn shade(in: VsOut) -> vec4<f32> {
    let c = instances[in.object].color;
    let lambert = 0.3 + 0.7 * abs(dot(normalize(in.normal), camera.light_dir.xyz));
    let checker = select(0.85, 1.0, (i32(floor(in.uv.x * 4.0)) + i32(floor(in.uv.y * 4.0))) % 2 == 0);
    return vec4<f32>(c.rgb * lambert * checker, c.a);
}

struct Opaque {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
}

// Opaque: object IDs (hroc's ID marks and OF read them).
fn opaque(in: VsOut) -> Opaque {
    seen[in.object] = 1u;
    var out: Opaque;
    out.color = shade(in);
    out.id = in.object + 1u;
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
    out.id = 0u;
    return out;
}
