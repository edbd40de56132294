//! Helpers of the loader tests: the Khronos samples, scratch folders,
//! glTF documents and GLB containers written by hand.
#![allow(dead_code)] // each test file uses some of them

use glam::Vec3;
use hroc_scene::Error;
use hroc_scene::{self as scene, Scene};
use serde_json::{json, Value};
use std::fs;
use std::path::{Path, PathBuf};

pub fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf-samples").join(name)
}

pub fn load(path: impl AsRef<Path>) -> hroc_scene::Result<Scene> {
    scene::load(path.as_ref().to_str().unwrap(), None, 0)
}

pub fn load_sample(name: &str) -> Scene {
    load(sample(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A fresh, empty directory for one test.
pub fn tmp(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("loaders").join(test);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    fs::create_dir_all(p.parent().unwrap()).unwrap();
    fs::write(&p, bytes).unwrap();
    p
}

/// The error's message, checked to be one line and to mention `needle`.
pub fn message(e: &Error, needle: &str) -> String {
    let m = e.to_string();
    println!("{m}"); // shown with --nocapture, to read the messages
    assert!(!m.contains('\n'), "multi-line message: {m}");
    assert!(m.to_lowercase().contains(&needle.to_lowercase()), "message {m:?} does not mention {needle:?}");
    m
}

pub fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-4, "{a} != {b}");
}

pub fn b64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            s.push(if i <= c.len() { T[(n >> (18 - 6 * i) & 63) as usize] as char } else { '=' });
        }
    }
    s
}

pub fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", b64(bytes))
}

pub const TRI: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// Buffer bytes: f32 positions, then u16 indices (padded to 4).
pub fn tri_bytes(positions: &[f32], indices: &[u16]) -> Vec<u8> {
    let mut b: Vec<u8> = positions.iter().flat_map(|f| f.to_le_bytes()).collect();
    b.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    b
}

/// A one-node glTF document drawing `positions` with `indices`; its single
/// buffer is embedded as a data URI (callers may replace the URI).
pub fn tri_doc(positions: &[f32], indices: &[u16]) -> Value {
    let bytes = tri_bytes(positions, indices);
    let pos_len = positions.len() * 4;
    json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "buffers": [{ "uri": data_uri(&bytes), "byteLength": bytes.len() }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": pos_len },
            { "buffer": 0, "byteOffset": pos_len, "byteLength": indices.len() * 2 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": positions.len() / 3, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 1.0] },
            { "bufferView": 1, "componentType": 5123, "count": indices.len(), "type": "SCALAR" }
        ]
    })
}

pub fn write_doc(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    write(dir, name, serde_json::to_vec_pretty(doc).unwrap())
}

/// A GLB container: JSON chunk (space padded) and optional BIN chunk.
pub fn glb(json: &Value, bin: Option<&[u8]>) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut chunks = Vec::new();
    chunks.extend((j.len() as u32).to_le_bytes());
    chunks.extend(b"JSON");
    chunks.extend(&j);
    if let Some(bin) = bin {
        chunks.extend((bin.len() as u32).to_le_bytes());
        chunks.extend(b"BIN\0");
        chunks.extend(bin);
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((12 + chunks.len() as u32).to_le_bytes());
    out.extend(chunks);
    out
}
