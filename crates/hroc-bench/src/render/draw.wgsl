// hroc's own renderer (src/render/mod.rs): one indirect command per object,
// instance_index = object index. The host contract of the `hroc` crate:
// forced early-Z, and `hroc_mark` (appended from hroc::device::marks_wgsl(1)) when
// the culler asks for marks, so a mark means "owns at least one fragment
// that passed" (HROC §3.1, ROC).

override MARK: bool = false;
// Multisampled targets hold IDs as Rg16Uint: the low 16 bits in r, the high in g.
override SPLIT_IDS: bool = false;

struct View {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>, // xyz: direction towards the light
}

struct ObjectData {
    model: mat4x4<f32>,
    color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read> objects: array<ObjectData>;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @builtin(instance_index) object: u32,
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) object: u32,
}

@vertex
fn vs(v: VsIn) -> VsOut {
    let m = objects[v.object].model;
    var out: VsOut;
    out.clip = view.view_proj * (m * vec4<f32>(v.position, 1.0));
    // Shading only: the model's 3x3 is close enough to the normal matrix.
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.object = v.object;
    return out;
}

struct FsOut {
    @location(0) color: vec4<f32>,
    @location(1) id: vec4<u32>,
}

@fragment @early_depth_test(force)
fn fs(in: VsOut) -> FsOut {
    if MARK {
        hroc_mark(in.object);
    }
    let n = normalize(in.normal);
    let base = objects[in.object].color.rgb;
    let lambert = 0.25 + 0.75 * abs(dot(n, view.light_dir.xyz));
    var out: FsOut;
    out.color = vec4<f32>(base * lambert, 1.0);
    out.id = id_texel(in.object + 1u); // 0 is background
    return out;
}

// An ID as its target holds it.
fn id_texel(id: u32) -> vec4<u32> {
    return select(vec4<u32>(id, 0u, 0u, 0u), vec4<u32>(id & 0xffffu, id >> 16u, 0u, 0u), SPLIT_IDS);
}

// Passes without colour that keep object IDs (the light's cascades).
@fragment @early_depth_test(force)
fn fs_ids(in: VsOut) -> @location(0) vec4<u32> {
    if MARK {
        hroc_mark(in.object);
    }
    return id_texel(in.object + 1u);
}

// Overdraw view: every rasterized fragment adds one (no depth test).
@fragment
fn fs_overdraw(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 0.0, 0.0, 1.0);
}
