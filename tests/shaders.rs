//! GPU-free: every WGSL pass parses and validates with naga (with the
//! shared header prepended, as the renderer compiles it), and every Rust
//! struct mirrored in WGSL has the WGSL size.

use hroc::render::{layout::mirrored_sizes, shader_source, SHADERS};

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
    let m = module("draw.wgsl");
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

#[test]
fn early_depth_test_is_forced_where_fragments_mark() {
    // Marking only means "passed the depth test" with forced early-Z (DESIGN.md).
    let m = module("draw.wgsl");
    let fs = m.entry_points.iter().find(|e| e.name == "fs").expect("fs");
    assert_eq!(fs.early_depth_test, Some(naga::EarlyDepthTest::Force));
}
