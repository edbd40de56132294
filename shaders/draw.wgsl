// The shared draw pass: one indirect command per object, instance_index =
// object id. MARK makes the fragment stage record which objects passed the
// depth test; forced early-Z keeps hidden fragments from running at all, so
// a mark means "owns at least one fragment that passed" (HROC §3.1, ROC).

override MARK: bool = false;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> objects: array<ObjectData>;
@group(1) @binding(0) var<storage, read_write> marks: array<u32>;

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
    out.clip = frame.view_proj * (m * vec4<f32>(v.position, 1.0));
    // Shading only: the model's 3x3 is close enough to the normal matrix.
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.object = v.object;
    return out;
}

struct FsOut {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
}

@fragment @early_depth_test(force)
fn fs(in: VsOut) -> FsOut {
    if MARK {
        marks[in.object] = 1u;
    }
    let n = normalize(in.normal);
    let base = objects[in.object].color.rgb;
    let lambert = 0.25 + 0.75 * abs(dot(n, frame.light_dir.xyz));
    var out: FsOut;
    out.color = vec4<f32>(base * lambert, 1.0);
    out.id = in.object + 1u; // 0 is background
    return out;
}

// Overdraw view: every rasterized fragment adds one (no depth test).
@fragment
fn fs_overdraw(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 0.0, 0.0, 1.0);
}
