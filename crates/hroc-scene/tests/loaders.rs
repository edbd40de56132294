//! The glTF loader through the public API: the Khronos samples load with
//! the right facts, and every kind of bad file is a one-line error, never a
//! panic or a file read outside the asset's folder.

mod common;

use common::*;
use glam::Vec3;
use hroc_scene::Error;
use serde_json::{json, Value};
use std::fs;

// ---------------------------------------------------------------- samples

#[test]
fn sample_triangle() {
    let s = load_sample("Triangle.gltf"); // no `scene` property: scene 0
    assert_eq!((s.objects.len(), s.meshes.len()), (1, 1));
    assert_eq!(s.meshes[0].indices, [0, 1, 2]);
    assert_eq!(s.meshes[0].vertices.len(), 3);
    assert_close(s.bounds().min, Vec3::ZERO);
    assert_close(s.bounds().max, Vec3::new(1.0, 1.0, 0.0));
    // No NORMAL attribute: computed, facing +Z for this counter-clockwise triangle.
    assert_close(Vec3::from(s.meshes[0].vertices[0].normal), Vec3::Z);
    assert_eq!(s.objects[0].color, [0.8, 0.8, 0.8], "no material: light grey");
    assert!(!s.path.keys.is_empty());
}

#[test]
fn sample_triangle_without_indices() {
    let s = load_sample("TriangleWithoutIndices.gltf");
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.meshes[0].indices, [0, 1, 2]);
    assert_eq!(s.stats().triangles, 1);
}

#[test]
fn sample_box() {
    let s = load_sample("Box.gltf");
    assert_eq!((s.objects.len(), s.meshes.len()), (1, 1));
    let m = &s.meshes[0];
    assert_eq!((m.vertices.len(), m.triangle_count()), (24, 12));
    assert_close(m.bounds.min, Vec3::splat(-0.5));
    assert_close(m.bounds.max, Vec3::splat(0.5));
    // The root matrix turns Z-up into Y-up; the cube stays [-0.5, 0.5]^3.
    assert_close(s.bounds().min, Vec3::splat(-0.5));
    assert_close(s.bounds().max, Vec3::splat(0.5));
    let t = s.objects[0].transform;
    assert_close(t.transform_vector3(Vec3::Z), Vec3::Y);
    assert_close(t.transform_vector3(Vec3::Y), Vec3::NEG_Z);
    // File normals are used and unit length.
    assert!(m.vertices.iter().all(|v| (Vec3::from(v.normal).length() - 1.0).abs() < 1e-5));
    assert_close(Vec3::from(s.objects[0].color), Vec3::new(0.8, 0.0, 0.0));
}

#[test]
fn sample_box_textured() {
    let s = load_sample("BoxTextured.gltf"); // embedded PNG, empty node
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.stats().triangles, 12);
    assert_close(s.bounds().max, Vec3::splat(0.5));
}

#[test]
fn sample_simple_meshes_share_one_mesh() {
    let s = load_sample("SimpleMeshes.gltf");
    assert_eq!((s.objects.len(), s.meshes.len()), (2, 1));
    assert!(s.objects.iter().all(|o| o.mesh == 0));
    assert_close(s.objects[1].transform.w_axis.truncate(), Vec3::X);
    assert_close(s.bounds().min, Vec3::ZERO);
    assert_close(s.bounds().max, Vec3::new(2.0, 1.0, 0.0));
    let st = s.stats();
    assert_eq!((st.triangles, st.unique_triangles), (2, 1));
}

#[test]
fn sample_sparse_accessor() {
    let s = load_sample("SimpleSparseAccessor.gltf");
    assert_eq!(s.objects.len(), 1);
    let m = &s.meshes[0];
    assert_eq!((m.vertices.len(), m.triangle_count()), (14, 12));
    // Without the sparse substitution the top row would stay at y = 1.
    assert_close(m.bounds.min, Vec3::ZERO);
    assert_close(m.bounds.max, Vec3::new(6.0, 4.0, 0.0));
    assert_close(Vec3::from(m.vertices[8].position), Vec3::new(1.0, 2.0, 0.0));
}

#[test]
fn sample_multiple_scenes_uses_default_scene() {
    let s = load_sample("MultipleScenes.gltf"); // `scene: 1` draws mesh 1, a quad
    assert_eq!((s.objects.len(), s.meshes.len()), (1, 1));
    assert_eq!(s.stats().triangles, 2);
    assert_eq!(s.meshes[0].vertices.len(), 4);
}

#[test]
fn sample_cameras() {
    let s = load_sample("Cameras.gltf"); // camera nodes draw nothing
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.stats().triangles, 2);
    // Rotation of about -45 degrees around X, from a slightly non-unit quaternion.
    let t = s.objects[0].transform;
    assert!((t.determinant() - 1.0).abs() < 1e-4);
    let y = t.transform_vector3(Vec3::Y);
    assert!((y - Vec3::new(0.0, std::f32::consts::FRAC_1_SQRT_2, -std::f32::consts::FRAC_1_SQRT_2)).abs().max_element() < 1e-3, "{y}");
}

#[test]
fn sample_duck() {
    let s = load_sample("Duck.gltf");
    assert_eq!(s.objects.len(), 1);
    let m = &s.meshes[0];
    assert_eq!((m.vertices.len(), m.triangle_count()), (2399, 4212));
    // Root matrix scales by 0.01.
    let b = s.bounds();
    assert_close(b.min, Vec3::new(-0.692_985, 0.099_293_7, -0.613_282));
    assert_close(b.max, Vec3::new(0.961_799, 1.639_7, 0.539_252));
}

#[test]
fn sample_orientation_test() {
    let s = load_sample("OrientationTest.gltf");
    assert_eq!((s.objects.len(), s.meshes.len()), (13, 13));
    // 6 arrows of 38, 6 targets of 26, a base cube of 140 triangles.
    assert_eq!(s.stats().triangles, 6 * 38 + 6 * 26 + 140);
    let colors: std::collections::HashSet<_> = s.objects.iter().map(|o| o.color.map(f32::to_bits)).collect();
    assert_eq!(colors.len(), 7, "7 materials");
    // Transposed matrices would swing the arrows elsewhere; the scene is
    // symmetric around the base cube.
    let b = s.bounds();
    assert!(b.min.cmplt(Vec3::splat(-5.0)).all() && b.max.cmpgt(Vec3::splat(5.0)).all(), "{b:?}");
    assert!(b.min.cmpgt(Vec3::splat(-9.0)).all() && b.max.cmplt(Vec3::splat(9.0)).all(), "{b:?}");
    // Node 1 (matrix) puts its arrow at x = -5; node 0 (TRS) at x = +5.
    let arrow_x1 = s.meshes.iter().position(|m| m.name == "ArrowMeshX1").unwrap() as u32;
    let arrow_x2 = s.meshes.iter().position(|m| m.name == "ArrowMeshX2").unwrap() as u32;
    let at = |mi: u32| s.objects.iter().find(|o| o.mesh == mi).unwrap().transform.w_axis.truncate();
    assert_close(at(arrow_x1), Vec3::new(5.0, 0.0, 0.0));
    assert_close(at(arrow_x2), Vec3::new(-5.0, 0.0, 0.0));
}

#[test]
fn every_sample_loads_and_validates() {
    let dir = sample("");
    let mut n = 0;
    for e in fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "gltf") {
            let s = load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            s.validate().unwrap();
            n += 1;
        }
    }
    assert_eq!(n, 10);
}

// ---------------------------------------------------------------- glTF: valid variants

#[test]
fn glb_with_bin_chunk_loads() {
    let dir = tmp("glb_with_bin_chunk_loads");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    let bin = tri_bytes(&TRI, &[0, 1, 2]);
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let s = load(write(&dir, "tri.glb", glb(&doc, Some(&bin)))).unwrap();
    assert_eq!((s.objects.len(), s.stats().triangles), (1, 1));
}

#[test]
fn external_buffer_inside_folder_loads() {
    let dir = tmp("external_buffer_inside_folder_loads");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    write(&dir, "bin/tri data.bin", tri_bytes(&TRI, &[0, 1, 2]));
    doc["buffers"][0]["uri"] = json!("bin/tri%20data.bin");
    let s = load(write_doc(&dir, "tri.gltf", &doc)).unwrap();
    assert_eq!(s.stats().triangles, 1);
}

#[test]
fn strips_and_fans_become_lists_and_points_are_skipped() {
    let dir = tmp("strips_and_fans");
    let quad = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
    // Accessor 1: strip order 0 1 2 3; accessor 2: fan order 0 1 3 2.
    let mut doc = tri_doc(&quad, &[0, 1, 2, 3, 0, 1, 3, 2]);
    doc["accessors"][1]["count"] = json!(4);
    doc["accessors"].as_array_mut().unwrap().push(json!({ "bufferView": 1, "byteOffset": 8, "componentType": 5123, "count": 4, "type": "SCALAR" }));
    let prim = |mode: u32, indices: u32| json!({ "attributes": { "POSITION": 0 }, "indices": indices, "mode": mode });
    doc["meshes"][0]["primitives"] = json!([prim(5, 1), prim(6, 2), prim(0, 1), prim(1, 1)]);
    let s = load(write_doc(&dir, "modes.gltf", &doc)).unwrap();
    assert_eq!(s.objects.len(), 2, "points and lines are skipped");
    assert_eq!(s.meshes[0].indices, [0, 1, 2, 1, 3, 2], "strip");
    assert_eq!(s.meshes[1].indices, [1, 3, 0, 3, 2, 0], "fan");
    // Both keep one winding: every face normal points the same way (+Z).
    for m in &s.meshes {
        for t in m.indices.chunks(3) {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
            assert!((p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).z > 0.0);
        }
    }
}

#[test]
fn nodes_without_scene_show_root_nodes() {
    let dir = tmp("nodes_without_scene");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    let o = doc.as_object_mut().unwrap();
    o.remove("scene");
    o.remove("scenes");
    doc["nodes"] = json!([{ "children": [1], "translation": [0.0, 0.0, 2.0] }, { "mesh": 0 }]);
    let s = load(write_doc(&dir, "lib.gltf", &doc)).unwrap();
    assert_eq!(s.objects.len(), 1);
    assert_close(s.objects[0].transform.w_axis.truncate(), Vec3::new(0.0, 0.0, 2.0));
}

// ---------------------------------------------------------------- glTF: bad input

#[test]
fn missing_file_is_not_found() {
    for name in ["nope.gltf", "nope.glb", "nope.obj"] {
        let e = load(tmp("missing_file").join(name)).unwrap_err();
        assert!(matches!(e, Error::NotFound(_)), "{e:?}");
        message(&e, name);
    }
}

#[test]
fn malformed_json() {
    let dir = tmp("malformed_json");
    for (name, text) in [("cut.gltf", "{ \"asset\": { \"version\": \"2.0\" "), ("empty.gltf", ""), ("junk.gltf", "not json")] {
        let e = load(write(&dir, name, text)).unwrap_err();
        assert!(matches!(e, Error::Malformed { format: "glTF", .. }), "{name}: {e:?}");
        message(&e, "JSON");
    }
    // Well-formed JSON that is not valid glTF: no asset, wrong types.
    let e = load(write(&dir, "noasset.gltf", "{\"meshes\": 3}")).unwrap_err();
    assert!(matches!(e, Error::Malformed { format: "glTF", .. }), "{e:?}");
    message(&e, "noasset.gltf");
}

#[test]
fn truncated_glb() {
    let dir = tmp("truncated_glb");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let full = glb(&doc, Some(&tri_bytes(&TRI, &[0, 1, 2])));
    let e = load(write(&dir, "cut.glb", &full[..full.len() - 10])).unwrap_err();
    assert!(matches!(e, Error::Malformed { format: "glTF", .. }), "{e:?}");
    message(&e, "truncated");
    // Every prefix, and a header that lies about the length, fails cleanly.
    for n in 0..full.len() {
        let e = load(write(&dir, "prefix.glb", &full[..n])).unwrap_err();
        assert!(matches!(e, Error::Malformed { .. }), "{n} bytes: {e:?}");
        assert!(!e.to_string().contains('\n'));
    }
    let mut lying = full.clone();
    lying[8..12].copy_from_slice(&5u32.to_le_bytes());
    let e = load(write(&dir, "lying.glb", &lying)).unwrap_err();
    message(&e, "length");
    // A BIN chunk shorter than the buffer it backs.
    let short = glb(&doc, Some(&tri_bytes(&TRI, &[0, 1, 2])[..20]));
    let e = load(write(&dir, "short.glb", short)).unwrap_err();
    assert!(matches!(e, Error::Malformed { .. }), "{e:?}");
    message(&e, "byteLength");
}

#[test]
fn buffer_uri_with_parent_dir_is_unsafe() {
    let dir = tmp("buffer_uri_parent");
    write(&dir, "secret.bin", tri_bytes(&TRI, &[0, 1, 2])); // a real file: it must not be read
    for uri in ["../secret.bin", "sub/../../secret.bin", "%2E%2E/secret.bin", "..\\secret.bin", "./../secret.bin"] {
        let mut doc = tri_doc(&TRI, &[0, 1, 2]);
        doc["buffers"][0]["uri"] = json!(uri);
        let e = load(write_doc(&dir, "model/a.gltf", &doc)).unwrap_err();
        assert!(matches!(e, Error::UnsafeUri { .. }), "{uri}: {e:?}");
        message(&e, uri);
    }
}

#[cfg(unix)]
#[test]
fn symlink_out_of_folder_is_unsafe() {
    let dir = tmp("symlink_out");
    write(&dir, "secret.bin", tri_bytes(&TRI, &[0, 1, 2]));
    fs::create_dir_all(dir.join("model")).unwrap();
    std::os::unix::fs::symlink(dir.join("secret.bin"), dir.join("model/link.bin")).unwrap();
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["buffers"][0]["uri"] = json!("link.bin");
    let e = load(write_doc(&dir, "model/a.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::UnsafeUri { .. }), "{e:?}");
}

#[test]
fn absolute_or_scheme_uri_is_unsafe() {
    let dir = tmp("absolute_uri");
    for uri in ["/etc/passwd", "file:///etc/passwd", "http://example.com/a.bin", "C:/Windows/win.ini", "\\\\server\\share\\a.bin", "%2Fetc%2Fpasswd"] {
        let mut doc = tri_doc(&TRI, &[0, 1, 2]);
        doc["buffers"][0]["uri"] = json!(uri);
        let e = load(write_doc(&dir, "a.gltf", &doc)).unwrap_err();
        assert!(matches!(e, Error::UnsafeUri { .. }), "{uri}: {e:?}");
        message(&e, uri);
    }
}

#[test]
fn image_uri_outside_folder_is_unsafe() {
    let dir = tmp("image_uri_outside");
    for uri in ["../texture.png", "/tmp/texture.png", "https://example.com/t.png"] {
        let mut doc = tri_doc(&TRI, &[0, 1, 2]);
        doc["images"] = json!([{ "uri": uri }]);
        let e = load(write_doc(&dir, "model/a.gltf", &doc)).unwrap_err();
        assert!(matches!(e, Error::UnsafeUri { .. }), "{uri}: {e:?}");
        message(&e, uri);
    }
}

#[test]
fn missing_external_buffer_is_not_found() {
    let dir = tmp("missing_external_buffer");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["buffers"][0]["uri"] = json!("gone.bin");
    let e = load(write_doc(&dir, "a.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::NotFound(_)), "{e:?}");
    message(&e, "gone.bin");
}

#[test]
fn bad_data_uri() {
    let dir = tmp("bad_data_uri");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@not base64@@@");
    let e = load(write_doc(&dir, "a.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::Malformed { .. }), "{e:?}");
    message(&e, "buffer 0");
}

#[test]
fn accessor_count_larger_than_its_buffer() {
    let dir = tmp("accessor_count");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["accessors"][0]["count"] = json!(1000);
    let e = load(write_doc(&dir, "count.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::Malformed { format: "glTF", .. }), "{e:?}");
    let m = message(&e, "accessor 0");
    assert!(m.contains("1000 elements of 12 bytes") && m.contains("exceed buffer view 0 (36 bytes)"), "{m}");

    // An offset pushing the data past the view.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["accessors"][1]["byteOffset"] = json!(4);
    let e = load(write_doc(&dir, "offset.gltf", &doc)).unwrap_err();
    message(&e, "accessor 1");

    // A buffer view reaching past its buffer.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["bufferViews"][1]["byteLength"] = json!(4000);
    let e = load(write_doc(&dir, "view.gltf", &doc)).unwrap_err();
    message(&e, "exceed buffer 0");

    // byteLength larger than the data behind the URI.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["buffers"][0]["byteLength"] = json!(4000);
    let e = load(write_doc(&dir, "bytelength.gltf", &doc)).unwrap_err();
    message(&e, "byteLength");

    // Absurd counts overflow no arithmetic.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["accessors"][0]["count"] = json!(u64::MAX / 2);
    let e = load(write_doc(&dir, "huge.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::Malformed { .. }), "{e:?}");
}

#[test]
fn sparse_accessor_out_of_range() {
    let dir = tmp("sparse_out_of_range");
    let text = fs::read_to_string(sample("SimpleSparseAccessor.gltf")).unwrap();
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["accessors"][1]["sparse"]["count"] = json!(30); // more substitutions than elements
    let e = load(write_doc(&dir, "count.gltf", &doc)).unwrap_err();
    message(&e, "sparse count 30");
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["accessors"][1]["sparse"]["indices"]["byteOffset"] = json!(2);
    let e = load(write_doc(&dir, "indices.gltf", &doc)).unwrap_err();
    message(&e, "sparse indices: 3 elements of 2 bytes at offset 2 exceed buffer view 2 (6 bytes)");
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["accessors"][1]["sparse"]["values"]["byteOffset"] = json!(8);
    let e = load(write_doc(&dir, "values.gltf", &doc)).unwrap_err();
    let m = message(&e, "sparse values");
    assert!(matches!(e, Error::Malformed { .. }), "{m}");
}

#[test]
fn wrong_accessor_types() {
    let dir = tmp("wrong_accessor_types");
    // POSITION as VEC2: the reader would misread it as VEC3.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["accessors"][0]["type"] = json!("VEC2");
    let e = load(write_doc(&dir, "vec2.gltf", &doc)).unwrap_err();
    message(&e, "POSITION");
    // Float indices: the reader would hit `unreachable!()`.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["accessors"][1]["componentType"] = json!(5126);
    let e = load(write_doc(&dir, "float_indices.gltf", &doc)).unwrap_err();
    message(&e, "indices");
    // A POSITION accessor that does not exist (gltf's validator would index out of bounds).
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    let e = load(write_doc(&dir, "no_accessor.gltf", &doc)).unwrap_err();
    message(&e, "POSITION accessor 7");
    // Dangling references elsewhere are caught by validation.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"][0]["mesh"] = json!(9);
    let e = load(write_doc(&dir, "no_mesh.gltf", &doc)).unwrap_err();
    message(&e, "nodes[0].mesh");
}

#[test]
fn index_out_of_range() {
    let dir = tmp("index_out_of_range");
    let doc = tri_doc(&TRI, &[0, 1, 5]);
    let e = load(write_doc(&dir, "a.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::Invalid(_)), "{e:?}");
    message(&e, "index 5 out of range");
}

#[test]
fn nan_vertex_position() {
    let dir = tmp("nan_vertex");
    let mut p = TRI;
    p[4] = f32::NAN;
    let e = load(write_doc(&dir, "a.gltf", &tri_doc(&p, &[0, 1, 2]))).unwrap_err();
    assert!(matches!(e, Error::Invalid(_)), "{e:?}");
    message(&e, "non-finite vertex");
}

#[test]
fn non_finite_node_transform() {
    let dir = tmp("non_finite_node");
    // JSON has no NaN literal; 1e39 overflows f32 to infinity.
    let mut m = [0.0f64; 16];
    (m[0], m[5], m[10], m[15]) = (1e39, 1.0, 1.0, 1.0);
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"][0]["matrix"] = json!(m);
    let e = load(write_doc(&dir, "matrix.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::Malformed { .. }), "{e:?}");
    message(&e, "node 0");
    message(&e, "non-finite");

    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"][0]["translation"] = json!([0.0, -1e40, 0.0]);
    let e = load(write_doc(&dir, "translation.gltf", &doc)).unwrap_err();
    message(&e, "non-finite");

    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"][0]["rotation"] = json!([0.0, 0.0, 0.0, 0.0]);
    let e = load(write_doc(&dir, "rotation.gltf", &doc)).unwrap_err();
    message(&e, "quaternion");

    // Finite locals whose product overflows: inf * 0 gives NaN in the world matrix.
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"] = json!([{ "children": [1], "scale": [3e38, 3e38, 3e38] }, { "mesh": 0, "scale": [3e38, 3e38, 3e38] }]);
    let e = load(write_doc(&dir, "product.gltf", &doc)).unwrap_err();
    message(&e, "node 1");
}

#[test]
fn node_cycle() {
    let dir = tmp("node_cycle");
    let mut doc = tri_doc(&TRI, &[0, 1, 2]);
    doc["nodes"] = json!([{ "mesh": 0, "children": [1] }, { "children": [0] }]);
    let e = load(write_doc(&dir, "cycle.gltf", &doc)).unwrap_err();
    message(&e, "reached twice");
}

#[test]
fn empty_gltf() {
    let dir = tmp("empty_gltf");
    let doc = json!({ "asset": { "version": "2.0" }, "scenes": [{ "nodes": [0] }], "nodes": [{}] });
    let e = load(write_doc(&dir, "empty.gltf", &doc)).unwrap_err();
    assert!(matches!(e, Error::EmptyScene(_)), "{e:?}");
    message(&e, "no drawable objects");
    let e = load(write_doc(&dir, "bare.gltf", &json!({ "asset": { "version": "2.0" } }))).unwrap_err();
    assert!(matches!(e, Error::EmptyScene(_)), "{e:?}");
}
