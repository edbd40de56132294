//! OBJ bytes into the loader: a scene or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hroc_scene::obj::load_bytes(data, std::path::Path::new("fuzz/input.obj"));
});
