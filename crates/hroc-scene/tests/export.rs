//! Scenes written out load back: the same objects and triangles, boxes that
//! hold the same geometry, and one object for a merged scene.

use hroc_scene::{export, load, CameraPath};

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hroc-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn written_scenes_load_back() {
    let s = load("rooms", Some(120), 3).unwrap();
    let merged = s.merged();
    assert_eq!((merged.objects.len(), merged.stats().triangles), (1, s.stats().triangles));
    let close = |a: glam::Vec3, b: glam::Vec3| (a - b).abs().max_element() < 1e-3 * (1.0 + a.abs().max_element());
    assert!(close(merged.bounds().min, s.bounds().min) && close(merged.bounds().max, s.bounds().max));
    for (scene, file) in [(&merged, "one.obj"), (&merged, "one.glb"), (&s, "all.glb"), (&s, "all.obj")] {
        let p = tmp(file);
        export::write(scene, &p).unwrap();
        let back = load(p.to_str().unwrap(), None, 0).unwrap();
        assert_eq!(back.objects.len(), scene.objects.len(), "{file}");
        assert_eq!(back.stats().triangles, scene.stats().triangles, "{file}");
        assert!(close(back.bounds().min, scene.bounds().min) && close(back.bounds().max, scene.bounds().max), "{file}: {:?} vs {:?}", back.bounds(), scene.bounds());
    }
    let p = tmp("path.json");
    export::write_path(&s.path, &p).unwrap();
    assert_eq!(CameraPath::from_file(&p).unwrap(), s.path);
    let e = export::write(&s, &tmp("x.fbx")).unwrap_err().to_string();
    assert!(e.contains(".obj or .glb"), "{e}");
}
