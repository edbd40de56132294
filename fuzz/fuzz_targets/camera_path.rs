//! Camera-path JSON into the parser: a checked path or an error.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = hroc_scene::CameraPath::from_json(text, std::path::Path::new("fuzz/path.json"));
    }
});
