//! Writing scenes out: Wavefront OBJ, binary glTF 2.0 (`.glb`) and camera
//! paths, so that generated scenes can be measured as the files real
//! assets come in (one mesh for a whole interior, millions of triangles).

use glam::{Mat3, Mat4, Vec3};
use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::{CameraPath, Mesh, Scene};

/// The triangles `o` draws in world space: the positions and normals of
/// the vertices they use (in first-use order) and indices into those.
fn world_geometry(scene: &Scene, o: &crate::Object) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
    let m = &scene.meshes[o.mesh as usize];
    let (first, count) = m.range(o.cluster);
    let normal_m = Mat3::from_mat4(o.transform).inverse().transpose();
    let (mut positions, mut normals, mut indices) = (Vec::new(), Vec::new(), Vec::with_capacity(count as usize));
    let mut local = std::collections::HashMap::new();
    for &i in &m.indices[first as usize..(first + count) as usize] {
        let at = *local.entry(i).or_insert_with(|| {
            let v = &m.vertices[i as usize];
            positions.push(o.transform.transform_point3(Vec3::from(v.position)).to_array());
            normals.push((normal_m * Vec3::from(v.normal)).normalize_or(Vec3::Y).to_array());
            positions.len() as u32 - 1
        });
        indices.push(at);
    }
    (positions, normals, indices)
}

impl Scene {
    /// The whole scene as one mesh in world space, drawn by one object:
    /// how interiors and city blocks often come in files.
    pub fn merged(&self) -> Scene {
        let (mut positions, mut normals, mut indices) = (Vec::new(), Vec::new(), Vec::new());
        for o in &self.objects {
            let (p, n, i) = world_geometry(self, o);
            let base = positions.len() as u32;
            indices.extend(i.iter().map(|i| base + i));
            positions.extend(p);
            normals.extend(n);
        }
        let mut s = Scene { name: format!("{}-merged", self.name), path: self.path.clone(), ..Default::default() };
        s.meshes.push(Mesh::new(format!("{} (one mesh)", self.name), positions, Some(normals), indices));
        s.push_object(0, Mat4::IDENTITY, [0.8, 0.8, 0.8]);
        s
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Write { path: path.to_path_buf(), source }
}

/// Writes `scene` as OBJ: one `o` group per object, with the vertices its
/// triangles use, in world space.
pub fn write_obj(scene: &Scene, path: &Path) -> Result<()> {
    let f = std::fs::File::create(path).map_err(io(path))?;
    let mut w = std::io::BufWriter::new(f);
    let mut base = 1u64;
    for (k, o) in scene.objects.iter().enumerate() {
        let (positions, normals, indices) = world_geometry(scene, o);
        writeln!(w, "o object{k}").map_err(io(path))?;
        for p in &positions {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2]).map_err(io(path))?;
        }
        for n in &normals {
            writeln!(w, "vn {} {} {}", n[0], n[1], n[2]).map_err(io(path))?;
        }
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|i| base + t[i] as u64);
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}").map_err(io(path))?;
        }
        base += positions.len() as u64;
    }
    w.flush().map_err(io(path))
}

/// Writes `scene` as binary glTF 2.0: one mesh per scene mesh (positions,
/// normals, 32-bit indices), one node per object with its matrix.
/// Objects that draw one cluster are written as their whole mesh's node
/// once (the file has no notion of clusters).
pub fn write_glb(scene: &Scene, path: &Path) -> Result<()> {
    use serde_json::json;
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes) = (Vec::new(), Vec::new(), Vec::new());
    let mut view = |bin: &mut Vec<u8>, bytes: &[u8]| {
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() }));
        views.len() - 1
    };
    for m in &scene.meshes {
        let pos: Vec<[f32; 3]> = m.vertices.iter().map(|v| v.position).collect();
        let nrm: Vec<[f32; 3]> = m.vertices.iter().map(|v| v.normal).collect();
        let (min, max) = (m.bounds.min, m.bounds.max);
        let p = view(&mut bin, bytemuck::cast_slice(&pos));
        accessors.push(json!({ "bufferView": p, "componentType": 5126, "count": pos.len(), "type": "VEC3", "min": [min.x, min.y, min.z], "max": [max.x, max.y, max.z] }));
        let n = view(&mut bin, bytemuck::cast_slice(&nrm));
        accessors.push(json!({ "bufferView": n, "componentType": 5126, "count": nrm.len(), "type": "VEC3" }));
        let i = view(&mut bin, bytemuck::cast_slice(&m.indices));
        accessors.push(json!({ "bufferView": i, "componentType": 5125, "count": m.indices.len(), "type": "SCALAR" }));
        let a = accessors.len();
        meshes.push(json!({ "name": m.name, "primitives": [{ "attributes": { "POSITION": a - 3, "NORMAL": a - 2 }, "indices": a - 1 }] }));
    }
    let nodes: Vec<_> = scene
        .objects
        .iter()
        .filter(|o| o.cluster.unwrap_or(0) == 0)
        .map(|o| if o.transform == Mat4::IDENTITY { json!({ "mesh": o.mesh }) } else { json!({ "mesh": o.mesh, "matrix": o.transform.to_cols_array() }) })
        .collect();
    let doc = json!({
        "asset": { "version": "2.0", "generator": "hroc" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": views,
        "accessors": accessors,
        "meshes": meshes,
        "nodes": nodes,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "scene": 0,
    });
    let mut text = serde_json::to_vec(&doc).map_err(|e| Error::Write { path: path.to_path_buf(), source: std::io::Error::other(e) })?;
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let total = u32::try_from(total).map_err(|_| Error::Invalid(format!("{} bytes do not fit one .glb (4 GiB)", total)))?;
    let f = std::fs::File::create(path).map_err(io(path))?;
    let mut w = std::io::BufWriter::new(f);
    let mut put = |b: &[u8]| w.write_all(b).map_err(io(path));
    put(b"glTF")?;
    put(&2u32.to_le_bytes())?;
    put(&total.to_le_bytes())?;
    put(&(text.len() as u32).to_le_bytes())?;
    put(b"JSON")?;
    put(&text)?;
    put(&(bin.len() as u32).to_le_bytes())?;
    put(b"BIN\0")?;
    put(&bin)?;
    w.flush().map_err(io(path))
}

/// Writes a camera path as the JSON [`CameraPath::from_file`] reads.
pub fn write_path(p: &CameraPath, path: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(p).map_err(|e| Error::Write { path: path.to_path_buf(), source: std::io::Error::other(e) })?;
    std::fs::write(path, text).map_err(io(path))
}

/// Writes `scene` by the file's extension: `.obj` or `.glb`.
pub fn write(scene: &Scene, path: &Path) -> Result<()> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("obj") => write_obj(scene, path),
        Some("glb") => write_glb(scene, path),
        _ => Err(Error::UnknownExport(path.to_path_buf())),
    }
}
