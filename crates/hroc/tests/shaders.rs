//! GPU-free: every WGSL pass parses and validates with naga (with the
//! shared header prepended, as the renderer compiles it), and every Rust
//! struct mirrored in WGSL has the WGSL size.

use hroc::testing::shaders::mirrored_sizes;
use hroc::testing::shaders::{source as shader_source, SHADERS};

fn module(name: &str) -> naga::Module {
    naga::front::wgsl::parse_str(&shader_source(name)).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&shader_source(name))))
}

fn validate(name: &str, m: &naga::Module) -> naga::valid::ModuleInfo {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(m)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&shader_source(name))))
}

#[test]
fn every_shader_validates() {
    assert!(!SHADERS.is_empty());
    for (name, _) in SHADERS {
        let m = module(name);
        validate(name, &m);
        assert!(!m.entry_points.is_empty(), "{name} has no entry point");
    }
}

/// Compiled for multisampled host targets (the host's depth and IDs as
/// `texture_multisampled_2d`), every pass validates too, and the passes
/// that load the host's targets bind them multisampled.
#[test]
fn every_shader_validates_for_msaa_targets() {
    use hroc::testing::reflect::entries_for;
    use hroc::testing::shaders::source_for;
    let mut multisampled = Vec::new();
    for (name, _) in SHADERS {
        let source = source_for(name, 4);
        let m = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&m)
            .unwrap_or_else(|e| panic!("{name} (4 samples): {}", e.emit_to_string(&source)));
        if entries_for(&[(name, &[])], 0, 4).iter().any(|e| matches!(e.ty, wgpu::BindingType::Texture { multisampled: true, .. })) {
            multisampled.push(*name);
        }
    }
    for name in ["hzb_pyramid.wgsl", "hroc_test.wgsl", "hroc_next.wgsl", "roc_boxes.wgsl", "woc_warp.wgsl", "id_marks.wgsl"] {
        assert!(multisampled.contains(&name), "{name} loads the host's targets: {multisampled:?}");
    }
}

/// Without early-Z (DX12 and Metal lack `SHADER_EARLY_DEPTH_TEST`, and
/// wgpu then rejects the attribute), every pass still validates once the
/// attribute is dropped, as the culler drops it there; with it left in,
/// the passes that use it fail, so the check can fail.
#[test]
fn every_shader_validates_without_early_z() {
    use hroc::testing::gpu::without_early_z;
    let caps = naga::valid::Capabilities::all() - naga::valid::Capabilities::EARLY_DEPTH_TEST;
    let check = |source: &str| naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps).validate(&naga::front::wgsl::parse_str(source).unwrap()).is_ok();
    let mut using = 0;
    for (name, _) in SHADERS {
        let source = shader_source(name);
        assert!(check(&without_early_z(&source)), "{name} fails to validate without early-Z");
        if source.contains("@early_depth_test(force)") {
            using += 1;
            assert!(!check(&source), "{name} validates with early-Z on a device without it");
        }
    }
    assert!(using >= 2, "roc_boxes.wgsl and hroc_test.wgsl force early-Z");
}

/// Every pass's layouts come from its WGSL: each reflects, a binding has
/// one type in all of a pass's entry points, and an entry is visible to
/// exactly the stages that use it.
#[test]
fn layouts_come_from_the_shaders() {
    use hroc::testing::reflect::{entries, Layout};
    use wgpu::{BindingType, BufferBindingType, ShaderStages, TextureSampleType};
    for (name, _) in SHADERS {
        assert!(!entries(&[(name, &[])], 0).is_empty(), "{name} binds nothing");
    }
    for layout in Layout::ALL {
        assert!(!layout.entries().is_empty(), "{layout:?} binds nothing");
        println!("{layout:?}: {} storage buffers in one stage", layout.storage_buffers_per_stage());
    }
    let test = entries(&[("hroc_test.wgsl", &["box_vs", "box_fs"])], 0);
    let entry = |b: u32| test.iter().find(|e| e.binding == b).unwrap_or_else(|| panic!("no binding {b}: {test:?}"));
    // The occlusion map is depth the fragment stage loads (as an
    // unfilterable float texture: GLSL has no textureLoad of depth
    // textures); the ray counters are written there too; the frame uniform
    // is read by both.
    assert!(matches!(entry(4).ty, BindingType::Texture { sample_type: TextureSampleType::Float { filterable: false }, .. }), "{:?}", entry(4));
    assert_eq!(entry(4).visibility, ShaderStages::FRAGMENT);
    assert!(matches!(entry(5).ty, BindingType::Buffer { ty: BufferBindingType::Storage { read_only: false }, .. }), "{:?}", entry(5));
    assert_eq!(entry(0).visibility, ShaderStages::VERTEX | ShaderStages::FRAGMENT);
    // The reduction to blocks loads the same depth at the same binding: it
    // is the test pass's first draw, with one layout for both.
    let reduce = entries(&[("hroc_test.wgsl", &["reduce_vs", "reduce_fs"])], 0);
    assert_eq!(reduce.iter().map(|e| e.binding).collect::<Vec<_>>(), [0, 4]);
    assert_eq!(reduce[1].ty, entry(4).ty);
    // Steps 0, 2 and 5 and the gate's passes number their bindings from
    // one list of resources (12 to 17: the seed's refill of V's holes; 18
    // and 19: the walk's launch and counts; 20: the gate's tally).
    let groups = entries(&[("hroc_seed.wgsl", &[]), ("hroc_groups.wgsl", &[]), ("hroc_next.wgsl", &[]), ("hroc_yield.wgsl", &[])], 0);
    assert_eq!(groups.iter().map(|e| e.binding).collect::<Vec<_>>(), (0..21).collect::<Vec<_>>());
    // HROC runs on wgpu's default limits: 8 storage buffers a stage.
    for layout in [Layout::HrocSeed, Layout::HrocWalk, Layout::HrocGroups, Layout::HrocNext, Layout::HrocYield, Layout::HrocTest] {
        assert!(layout.storage_buffers_per_stage() <= 8, "{layout:?}");
    }
}

#[test]
fn shader_folder_is_complete() {
    // A WGSL file the renderer does not list would never be validated.
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    for e in std::fs::read_dir(dir).unwrap() {
        let f = e.unwrap().file_name().into_string().unwrap();
        if f.ends_with(".wgsl") && f != "common.wgsl" {
            assert!(SHADERS.iter().any(|(n, _)| *n == f), "{f} is not in render::SHADERS");
        }
    }
}

#[test]
fn rust_structs_match_wgsl_layout() {
    let m = module("compact.wgsl");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(m.to_ctx()).unwrap();
    for (wgsl, rust_size) in mirrored_sizes() {
        let (handle, ty) = m.types.iter().find(|(_, t)| t.name.as_deref() == Some(wgsl)).unwrap_or_else(|| panic!("no WGSL struct {wgsl}"));
        let naga::TypeInner::Struct { span, .. } = ty.inner else { panic!("{wgsl} is not a struct") };
        assert_eq!(span as usize, rust_size, "{wgsl}: WGSL {span} bytes, Rust {rust_size}");
        // Arrays of it have the same stride on both sides.
        assert_eq!(layouter[handle].to_stride() as usize, rust_size, "{wgsl} stride");
    }
}

/// A host fragment shader that includes the marks snippet, as the crate
/// docs tell hosts to write it.
fn host_shader(group: u32) -> String {
    format!(
        "{}\n@vertex fn vs(@builtin(instance_index) i: u32) -> @builtin(position) vec4<f32> {{ return vec4<f32>(f32(i)); }}\n\
         @fragment @early_depth_test(force) fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {{ hroc_mark(u32(p.x)); return p; }}\n",
        hroc::device::marks_wgsl(group)
    )
}

#[test]
fn marks_snippet_validates_and_matches_the_marks_layout() {
    for group in [0, 1, 3] {
        let src = host_shader(group);
        let m = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all()).validate(&m).unwrap();
        // The one global the snippet declares is what `Culler::marks_layout`
        // describes: a read-write storage array of u32 at (group, 0).
        let globals: Vec<_> = m.global_variables.iter().map(|(_, g)| g).collect();
        assert_eq!(globals.len(), 1);
        let g = globals[0];
        assert_eq!(g.binding, Some(naga::ResourceBinding { group, binding: 0 }));
        assert_eq!(g.space, naga::AddressSpace::Storage { access: naga::StorageAccess::LOAD | naga::StorageAccess::STORE });
        let naga::TypeInner::Array { base, .. } = m.types[g.ty].inner else { panic!("marks is not an array") };
        assert_eq!(m.types[base].inner, naga::TypeInner::Scalar(naga::Scalar::U32));
    }
}
