//! Wavefront OBJ loader: one object per OBJ group/object (tobj model), each
//! with its own mesh, identity transform and a colour hashed from its index.
//!
//! Materials are ignored and `mtllib` never opens a file: an OBJ may only
//! make us read the OBJ itself.

use glam::Mat4;
use std::path::Path;

use super::{CameraPath, Mesh, Scene};
use crate::error::{Error, Result};

pub fn load(path: &Path) -> Result<Scene> {
    let bytes = std::fs::read(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => Error::NotFound(path.to_path_buf()),
        _ => Error::Io { path: path.to_path_buf(), source: e },
    })?;
    load_bytes(&bytes, path)
}

/// Loads an OBJ file's `bytes`; errors name `path`.
pub fn load_bytes(bytes: &[u8], path: &Path) -> Result<Scene> {
    let bad = |msg: String| Error::Malformed { format: "OBJ", path: path.to_path_buf(), msg };

    // `..Default::default()` covers fields that tobj features may add.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true, ..Default::default() };
    // tobj can overflow integer arithmetic on absurd face indices; debug
    // builds would panic there, so a panic is reported as a malformed file.
    let parsed = std::panic::catch_unwind(|| tobj::load_obj_buf(&mut &bytes[..], &options, |_mtllib| Err(tobj::LoadError::GenericFailure)));
    let (models, _materials) = match parsed {
        Ok(Ok(r)) => r,
        Ok(Err(tobj::LoadError::ReadError)) => return Err(bad("not a text file (invalid UTF-8)".into())),
        Ok(Err(e)) => return Err(bad(e.to_string())),
        Err(_) => return Err(bad("face indices out of range".into())),
    };

    let name = path.file_stem().map_or_else(|| "OBJ".to_string(), |s| s.to_string_lossy().into_owned());
    let mut scene = Scene { name, ..Default::default() };
    for (i, model) in models.into_iter().enumerate() {
        let m = model.mesh;
        // tobj emits empty models (e.g. for `o` lines without faces).
        if m.indices.is_empty() {
            continue;
        }
        let positions: Vec<[f32; 3]> = m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        // Faces may give normals for some corners only; then compute them all.
        let normals = (m.normals.len() == m.positions.len()).then(|| m.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]).collect()).and_then(super::gltf::unit_normals);
        let mesh_name = if model.name.is_empty() { format!("object{i}") } else { model.name };
        scene.meshes.push(Mesh::new(mesh_name, positions, normals, m.indices));
        scene.push_object(scene.meshes.len() as u32 - 1, Mat4::IDENTITY, color(i as u64));
    }

    scene.validate()?;
    scene.path = CameraPath::orbit(&scene.bounds());
    Ok(scene)
}

/// A stable, well-spread colour per object index (SplitMix64 finaliser),
/// kept away from black and white so that objects stay distinguishable.
fn color(i: u64) -> [f32; 3] {
    let mut z = i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    [0, 16, 32].map(|s| 0.25 + 0.65 * ((z >> s) & 0xFFFF) as f32 / 65535.0)
}
