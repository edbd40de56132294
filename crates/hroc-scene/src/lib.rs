//! Scene model: shared meshes + object instances.
//!
//! Meshes are shared between objects (instancing), so scenes with hundreds of
//! millions of triangles fit in memory. Every object is one draw: one mesh, one
//! transform, one colour, one world-space AABB.

pub mod camera;
pub mod clusters;
pub mod error;
pub mod export;
pub mod generators;
pub mod gltf;
pub mod motion;
pub mod obj;
pub mod paths;
pub mod rng;

use glam::{Mat4, Vec3};
use std::path::Path;

pub use camera::{Camera, CameraKey, CameraPath};
pub use clusters::{Cluster, ClusterOptions};
pub use error::{Error, Result};
pub use hroc::Aabb;

/// Vertex of the shared pool: position and normal, 24 bytes, mirrored in
/// `shaders/draw.wgsl` as two storage arrays would cost more fetches.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// Triangle mesh in its own object space.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub bounds: Aabb,
    /// Contiguous runs of `indices` that objects may draw alone
    /// ([`Mesh::clusterize`]); empty when the mesh is only drawn whole.
    pub clusters: Vec<Cluster>,
}

impl Mesh {
    /// Builds a mesh, computing its bounds; smooth normals are computed when
    /// `normals` is `None` (area-weighted face normals per vertex).
    pub fn new(name: impl Into<String>, positions: Vec<[f32; 3]>, normals: Option<Vec<[f32; 3]>>, indices: Vec<u32>) -> Self {
        let normals = normals.unwrap_or_else(|| compute_normals(&positions, &indices));
        let bounds = Aabb::from_points(positions.iter().map(|p| Vec3::from(*p)));
        let vertices = positions.into_iter().zip(normals).map(|(position, normal)| Vertex { position, normal }).collect();
        Mesh { name: name.into(), vertices, indices, bounds, clusters: Vec::new() }
    }

    /// Tight world box of the mesh under an affine transform. A transform
    /// that keeps axes on axes (scale, translation, quarter turns) maps the
    /// mesh box exactly; any other rotation needs the vertices themselves.
    pub fn world_bounds(&self, m: &Mat4) -> Aabb {
        if keeps_axes(m) || self.vertices.is_empty() {
            return self.bounds.transformed(m);
        }
        Aabb::from_points(self.vertices.iter().map(|v| m.transform_point3(Vec3::from(v.position))))
    }
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// True when `m` maps axes onto axes (scale, translation, quarter turns):
/// it maps a box onto a box exactly.
pub fn keeps_axes(m: &Mat4) -> bool {
    [m.x_axis, m.y_axis, m.z_axis].iter().all(|c| c.truncate().to_array().iter().filter(|v| **v != 0.0).count() <= 1)
}

/// Area-weighted vertex normals; degenerate vertices get +Y.
pub fn compute_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let (Some(a), Some(b), Some(c)) = (positions.get(t[0] as usize), positions.get(t[1] as usize), positions.get(t[2] as usize)) else {
            continue;
        };
        let (a, b, c) = (Vec3::from(*a), Vec3::from(*b), Vec3::from(*c));
        let f = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += f;
        }
    }
    n.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Y).to_array()).collect()
}

/// One drawable instance: a mesh, or one cluster of it, under a transform.
#[derive(Clone, Debug)]
pub struct Object {
    pub mesh: u32,
    /// The cluster of the mesh this object draws ([`Mesh::clusters`]);
    /// `None`: the whole mesh.
    pub cluster: Option<u32>,
    pub transform: Mat4,
    /// Linear RGB in [0, 1].
    pub color: [f32; 3],
    /// World-space bounds of the transformed mesh.
    pub bounds: Aabb,
}

/// A scene: meshes, objects, and the camera path it is benchmarked on.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub objects: Vec<Object>,
    /// Default 10 s path; loaders build one from the scene bounds.
    pub path: CameraPath,
}

/// Scene statistics (the columns of Lee's thesis, Table 1, that do not need a BVH).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct SceneStats {
    pub objects: usize,
    pub meshes: usize,
    /// Triangles drawn when every object is drawn once (instancing counted).
    pub triangles: u64,
    pub vertices: u64,
    /// Triangles stored in the shared mesh pool.
    pub unique_triangles: u64,
}

impl Scene {
    pub fn bounds(&self) -> Aabb {
        self.objects.iter().fold(Aabb::EMPTY, |b, o| b.union(o.bounds))
    }

    pub fn stats(&self) -> SceneStats {
        let triangles = self.objects.iter().map(|o| self.triangles(o) as u64).sum();
        // A clustered instance's vertices count once, at its first cluster.
        let vertices = self.objects.iter().filter(|o| o.cluster.unwrap_or(0) == 0).map(|o| self.meshes[o.mesh as usize].vertices.len() as u64).sum();
        SceneStats { objects: self.objects.len(), meshes: self.meshes.len(), triangles, vertices, unique_triangles: self.meshes.iter().map(|m| m.triangle_count() as u64).sum() }
    }

    /// Triangles `o` draws: its cluster's, or its mesh's.
    pub fn triangles(&self, o: &Object) -> u32 {
        self.meshes[o.mesh as usize].range(o.cluster).1 / 3
    }

    /// Adds an object drawing `mesh` under `transform`; its world box is the
    /// tight box of the transformed vertices. Every box test culls by this
    /// box, so slack here is culling lost: a rotated mesh's transformed
    /// mesh box can be twice as wide as the mesh itself.
    pub fn push_object(&mut self, mesh: u32, transform: Mat4, color: [f32; 3]) {
        let bounds = self.meshes[mesh as usize].world_bounds(&transform);
        self.objects.push(Object { mesh, cluster: None, transform, color, bounds });
    }

    /// Checks everything the renderer relies on; loaders and generators call
    /// it so that bad data is an error here, never a wrong picture later.
    pub fn validate(&self) -> Result<()> {
        if self.objects.is_empty() {
            return Err(Error::EmptyScene(format!("'{}' has no drawable objects", self.name)));
        }
        for (mi, m) in self.meshes.iter().enumerate() {
            if m.indices.len() % 3 != 0 {
                return Err(Error::Invalid(format!("mesh {mi} ('{}'): index count {} is not a multiple of 3", m.name, m.indices.len())));
            }
            if let Some(&i) = m.indices.iter().find(|&&i| i as usize >= m.vertices.len()) {
                return Err(Error::Invalid(format!("mesh {mi} ('{}'): index {i} out of range ({} vertices)", m.name, m.vertices.len())));
            }
            if let Some(v) = m.vertices.iter().find(|v| !v.position.iter().chain(&v.normal).all(|c| c.is_finite())) {
                return Err(Error::Invalid(format!("mesh {mi} ('{}'): non-finite vertex {:?}", m.name, v.position)));
            }
        }
        for (oi, o) in self.objects.iter().enumerate() {
            if o.mesh as usize >= self.meshes.len() {
                return Err(Error::Invalid(format!("object {oi}: mesh {} out of range", o.mesh)));
            }
            if !o.transform.is_finite() {
                return Err(Error::Invalid(format!("object {oi}: non-finite transform")));
            }
            let mesh = &self.meshes[o.mesh as usize];
            if mesh.indices.is_empty() {
                return Err(Error::Invalid(format!("object {oi}: mesh {} has no triangles", o.mesh)));
            }
            if let Some(c) = o.cluster {
                let ok = mesh
                    .clusters
                    .get(c as usize)
                    .is_some_and(|c| c.index_count > 0 && c.index_count % 3 == 0 && c.first_index as u64 + c.index_count as u64 <= mesh.indices.len() as u64);
                if !ok {
                    return Err(Error::Invalid(format!("object {oi}: cluster {c} of mesh {} is not a run of its triangles", o.mesh)));
                }
            }
            if !(o.bounds.min.is_finite() && o.bounds.max.is_finite()) || o.bounds.is_empty() {
                return Err(Error::Invalid(format!("object {oi}: invalid bounds {:?}", o.bounds)));
            }
        }
        Ok(())
    }
}

/// Loads a built-in scene key or a `.gltf`/`.glb`/`.obj` path.
/// `objects` scales generated scenes (ignored for files).
pub fn load(spec: &str, objects: Option<usize>, seed: u64) -> Result<Scene> {
    if let Some(g) = generators::find(spec) {
        return generators::generate(g, objects.unwrap_or(g.default_objects), seed);
    }
    let path = Path::new(spec);
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("gltf") | Some("glb") | Some("obj") if !path.exists() => Err(Error::NotFound(path.to_path_buf())),
        Some("gltf") | Some("glb") => gltf::load(path),
        Some("obj") => obj::load(path),
        _ if path.exists() => Err(Error::UnsupportedFormat(path.to_path_buf())),
        _ if spec.contains('/') || spec.contains('.') => Err(Error::NotFound(path.to_path_buf())),
        _ => Err(Error::UnknownScene(spec.to_string(), generators::keys().join(", "))),
    }
}
