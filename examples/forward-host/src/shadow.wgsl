// The shadow pass: depth only, one cascade's view-projection, the same
// per-instance transforms as the main pass (instance_index = hroc's object
// index). Without a marking fragment stage (shadow_marked.wgsl) the pass
// has none.

struct Instance {
    model: mat4x4<f32>,
    color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> light_view_proj: mat4x4<f32>;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) object: u32,
}

@vertex
fn vs_shadow(@location(0) position: vec3<f32>, @builtin(instance_index) object: u32) -> ShadowOut {
    var out: ShadowOut;
    out.clip = light_view_proj * (instances[object].model * vec4<f32>(position, 1.0));
    out.object = object;
    return out;
}
