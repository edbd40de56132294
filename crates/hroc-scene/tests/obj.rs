//! The OBJ loader through the public API: groups become objects, and bad
//! files are one-line errors.

mod common;

use common::*;
use glam::Vec3;
use hroc_scene::Error;

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_groups_become_objects() {
    let dir = tmp("obj_groups");
    let text = "mtllib ../../../../etc/passwd\n\
                v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 2\n\
                o quad\nusemtl red\nf 1//1 2//1 3//1 4//1\n\
                g tri\nf 1 2 3\n\
                o empty\n";
    let s = load(write(&dir, "a.obj", text)).unwrap();
    assert_eq!((s.objects.len(), s.meshes.len()), (2, 2));
    assert_eq!(s.meshes[0].name, "quad");
    assert_eq!(s.meshes[0].triangle_count(), 2);
    assert_eq!(s.meshes[1].triangle_count(), 1);
    assert_eq!(Vec3::from(s.meshes[0].vertices[0].normal), Vec3::Z, "file normals, normalised");
    assert_close(s.bounds().max, Vec3::new(1.0, 1.0, 0.0));
    assert!(s.objects.iter().all(|o| o.transform == glam::Mat4::IDENTITY));
    assert_ne!(s.objects[0].color, s.objects[1].color);
    let again = load(dir.join("a.obj")).unwrap();
    assert_eq!(s.objects[1].color, again.objects[1].color, "deterministic colours");
    assert!(!s.path.keys.is_empty());
}

#[test]
fn empty_obj() {
    let dir = tmp("empty_obj");
    for (name, text) in [("empty.obj", ""), ("verts.obj", "# only vertices\nv 0 0 0\nv 1 0 0\n")] {
        let e = load(write(&dir, name, text)).unwrap_err();
        assert!(matches!(e, Error::EmptyScene(_)), "{name}: {e:?}");
        message(&e, "no drawable objects");
    }
}

#[test]
fn malformed_obj() {
    let dir = tmp("malformed_obj");
    for (name, text, needle) in [
        ("short.obj", "v 1 2\n", "position"),
        ("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", "face"),
        ("normal.obj", "v 0 0 0\nvn 0 1\n", "normal"),
        ("w.obj", "v 0 0 0 0\n", "scaling"),
    ] {
        let e = load(write(&dir, name, text)).unwrap_err();
        assert!(matches!(e, Error::Malformed { format: "OBJ", .. }), "{name}: {e:?}");
        message(&e, needle);
    }
    let e = load(write(&dir, "utf8.obj", b"v 0 0 0\n\xff\xfe\n")).unwrap_err();
    assert!(matches!(e, Error::Malformed { format: "OBJ", .. }), "{e:?}");
    message(&e, "UTF-8");
}

#[test]
fn obj_index_out_of_range() {
    let dir = tmp("obj_index");
    for text in ["v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"] {
        let e = load(write(&dir, "a.obj", text)).unwrap_err();
        assert!(matches!(e, Error::Malformed { format: "OBJ", .. }), "{text:?}: {e:?}");
        message(&e, "out of bounds");
    }
}

#[test]
fn obj_nan_coordinates() {
    let dir = tmp("obj_nan");
    for text in ["v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"] {
        let e = load(write(&dir, "a.obj", text)).unwrap_err();
        assert!(matches!(e, Error::Invalid(_)), "{text:?}: {e:?}");
        message(&e, "non-finite vertex");
    }
}
