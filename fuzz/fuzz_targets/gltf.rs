//! `.gltf` and `.glb` bytes into the loader: it must return a scene or an
//! error, never panic, hang or allocate without bound.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hroc_scene::gltf::load_bytes(data, std::path::Path::new("fuzz/input.glb"));
});
