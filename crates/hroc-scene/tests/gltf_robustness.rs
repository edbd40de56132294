//! The glTF loader on mutated files (never a panic) and on the extensions
//! it reads itself (KHR_mesh_quantization, EXT_mesh_gpu_instancing).

mod common;

use common::*;
use glam::Vec3;
use serde_json::{json, Value};
use std::fs;

// ---------------------------------------------------------------- robustness

/// Every numeric field that sizes or places data, set to edge values in the
/// sparse and interleaved samples: each load succeeds or fails with a clean
/// error, never through the loader's last-resort panic guard.
#[test]
fn mutated_sizes_and_offsets_never_panic() {
    let dir = tmp("mutated_sizes");
    let edges = [0u64, 1, 2, 3, 4, 5, 7, 12, 13, 255, 256, 65535, 1 << 31, u32::MAX as u64, u64::MAX];
    let fields: &[(&str, &[&str])] = &[
        ("accessors", &["count", "byteOffset", "bufferView", "componentType"]),
        ("bufferViews", &["byteOffset", "byteLength", "byteStride", "buffer"]),
        ("buffers", &["byteLength"]),
    ];
    let mut loads = 0;
    for name in ["SimpleSparseAccessor.gltf", "SimpleMeshes.gltf", "Box.gltf"] {
        let doc: Value = serde_json::from_str(&fs::read_to_string(sample(name)).unwrap()).unwrap();
        let mut variants = Vec::new();
        for (array, keys) in fields {
            for i in 0..doc[array].as_array().unwrap().len() {
                for key in *keys {
                    for v in edges.iter().copied().chain([5121, 5123, 5125, 5126]) {
                        let mut d = doc.clone();
                        d[array][i][key] = json!(v);
                        variants.push(d);
                    }
                }
            }
        }
        for sparse_path in [["count", ""], ["indices", "byteOffset"], ["values", "byteOffset"], ["indices", "componentType"]] {
            if doc["accessors"][1].get("sparse").is_none() {
                continue;
            }
            for v in edges.iter().copied().chain([5121, 5123, 5125]) {
                let mut d = doc.clone();
                let s = &mut d["accessors"][1]["sparse"];
                if sparse_path[1].is_empty() {
                    s[sparse_path[0]] = json!(v);
                } else {
                    s[sparse_path[0]][sparse_path[1]] = json!(v);
                }
                variants.push(d);
            }
        }
        for d in variants {
            let p = write_doc(&dir, "m.gltf", &d);
            if let Err(e) = load(&p) {
                let m = e.to_string();
                assert!(!m.contains('\n') && !m.contains("internal error"), "{name}: {m}");
            }
            loads += 1;
        }
    }
    assert!(loads > 300, "{loads}");
}

// ---------------------------------------------------------------- extensions

/// KHR_mesh_quantization and EXT_mesh_gpu_instancing together: u16 positions
/// (not normalized) under a node scale of 0.5, i8 normalized normals, and
/// three instances placed by a TRANSLATION accessor and turned by an i16
/// normalized ROTATION accessor. One shared mesh, one object per instance.
#[test]
fn quantized_and_gpu_instanced_meshes() {
    let mut bin: Vec<u8> = Vec::new();
    // Positions: u16 x 3 per vertex, padded to 8 bytes per element (stride 8).
    for p in [[0u16, 0, 0], [2, 0, 0], [0, 2, 0]] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        bin.extend([0, 0]);
    }
    let normals_at = bin.len();
    for _ in 0..3 {
        bin.extend([0u8, 0, 127, 0]); // i8 (0, 0, 1), stride 4
    }
    let indices_at = bin.len();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    let translations_at = bin.len();
    for t in [[0f32, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 0.0, -10.0]] {
        bin.extend(t.iter().flat_map(|c| c.to_le_bytes()));
    }
    let rotations_at = bin.len();
    // Identity, identity, and a half turn about Y: (0, 1, 0, 0).
    for q in [[0i16, 0, 0, 32767], [0, 0, 0, 32767], [0, 32767, 0, 0]] {
        bin.extend(q.iter().flat_map(|c| c.to_le_bytes()));
    }
    let doc = json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"],
        "extensionsRequired": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"],
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "scale": [0.5, 0.5, 0.5],
            "extensions": { "EXT_mesh_gpu_instancing": { "attributes": { "TRANSLATION": 3, "ROTATION": 4 } } } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2 }] }],
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 24, "byteStride": 8 },
            { "buffer": 0, "byteOffset": normals_at, "byteLength": 12, "byteStride": 4 },
            { "buffer": 0, "byteOffset": indices_at, "byteLength": 6 },
            { "buffer": 0, "byteOffset": translations_at, "byteLength": 36 },
            { "buffer": 0, "byteOffset": rotations_at, "byteLength": 24 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5123, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [2, 2, 0] },
            { "bufferView": 1, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR" },
            { "bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3" },
            { "bufferView": 4, "componentType": 5122, "normalized": true, "count": 3, "type": "VEC4" }
        ]
    });
    let dir = tmp("quantized_instanced");
    let s = load(write(&dir, "q.glb", glb(&doc, Some(&bin)))).unwrap();
    assert_eq!((s.meshes.len(), s.objects.len()), (1, 3));
    assert_close(Vec3::from(s.meshes[0].vertices[1].position), Vec3::new(2.0, 0.0, 0.0));
    assert_close(Vec3::from(s.meshes[0].vertices[0].normal), Vec3::Z);
    // Node scale 0.5 after the instance: the mesh spans [0, 1] around each translation.
    assert_close(s.objects[0].bounds.min, Vec3::ZERO);
    assert_close(s.objects[0].bounds.max, Vec3::new(1.0, 1.0, 0.0));
    assert_close(s.objects[1].bounds.min, Vec3::new(5.0, 0.0, 0.0));
    // Half turn about Y: x flips, then the node scale.
    assert_close(s.objects[2].bounds.min, Vec3::new(-1.0, 0.0, -5.0));
    assert_close(s.objects[2].bounds.max, Vec3::new(0.0, 1.0, -5.0));
}

#[test]
fn required_extensions_nobody_reads_are_named() {
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let dir = tmp("required_extensions");
    let e = load(write_doc(&dir, "draco.gltf", &doc)).unwrap_err();
    message(&e, "KHR_draco_mesh_compression");
}

#[test]
fn gpu_instancing_errors_are_clear() {
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"][0]["extensions"] = json!({ "EXT_mesh_gpu_instancing": { "attributes": { "TRANSLATION": 7 } } });
    let dir = tmp("instancing_errors");
    let e = load(write_doc(&dir, "bad.gltf", &doc)).unwrap_err();
    message(&e, "TRANSLATION accessor 7 does not exist");
    doc["nodes"][0]["extensions"] = json!({ "EXT_mesh_gpu_instancing": { "attributes": {} } });
    let e = load(write_doc(&dir, "empty.gltf", &doc)).unwrap_err();
    message(&e, "no TRANSLATION, ROTATION or SCALE");
}

/// One mesh of two primitives with two materials: two objects, each with its
/// own triangles, colour and box, both under the node's transform.
#[test]
fn primitives_and_materials_of_one_mesh_are_objects() {
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["meshes"][0]["primitives"] = json!([
        { "attributes": { "POSITION": 0 }, "indices": 1, "material": 0 },
        { "attributes": { "POSITION": 0 }, "material": 1 }
    ]);
    doc["materials"] = json!([
        { "pbrMetallicRoughness": { "baseColorFactor": [1.0, 0.0, 0.0, 1.0] } },
        { "pbrMetallicRoughness": { "baseColorFactor": [0.0, 0.0, 1.0, 1.0] } }
    ]);
    doc["nodes"][0]["translation"] = json!([0.0, 3.0, 0.0]);
    let dir = tmp("primitives_materials");
    let s = load(write_doc(&dir, "two.gltf", &doc)).unwrap();
    assert_eq!((s.objects.len(), s.meshes.len()), (2, 2));
    assert_eq!(s.objects[0].color, [1.0, 0.0, 0.0]);
    assert_eq!(s.objects[1].color, [0.0, 0.0, 1.0]);
    for o in &s.objects {
        assert_close(o.bounds.min, Vec3::new(0.0, 3.0, 0.0));
        assert_close(o.bounds.max, Vec3::new(1.0, 4.0, 0.0));
    }
}

/// An image with neither a URI nor a buffer view and MIME type (the `gltf`
/// crate would unwrap the missing URI) is a clear error.
#[test]
fn image_without_source_is_an_error() {
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["images"] = json!([{ "name": "nothing" }]);
    let dir = tmp("image_without_source");
    let e = load(write_doc(&dir, "img.gltf", &doc)).unwrap_err();
    message(&e, "image 0 has neither a URI");
    doc["images"] = json!([{ "bufferView": 0 }]);
    let e = load(write_doc(&dir, "img2.gltf", &doc)).unwrap_err();
    message(&e, "MIME type");
}
