//! Clusters: meshes split into spatially compact runs of triangles, each a
//! cullable object with a tight box, drawn from the mesh's own vertices.
//!
//! Real files rarely come at the papers' object granularity (HROC §6): a
//! room in one mesh is one box, and no box test can cull inside it. Like
//! Nanite's and niagara's clusters, each cluster here is a leaf of the
//! culler's BVH. meshoptimizer's spatial clustering
//! (`meshopt_buildMeshletsSpatial`, which splits by the surface area
//! heuristic, the cost the BVH minimises too) builds clusters of up to 512
//! triangles; larger clusters are groups of those, partitioned by
//! `meshopt_partitionClusters` with positions. Each cluster's triangles are
//! then ordered for the vertex cache (`meshopt_optimizeVertexCache`), and the
//! mesh's vertices for fetch (`meshopt_optimizeVertexFetch`).

use glam::{Mat4, Vec3};

use crate::{Aabb, Mesh, Object, Scene};

/// A run of a mesh's triangles: `indices[first_index..first_index + index_count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cluster {
    pub first_index: u32,
    pub index_count: u32,
    /// Box of the cluster's vertices in the mesh's space.
    pub bounds: Aabb,
}

/// How a scene is split ([`Scene::clustered`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClusterOptions {
    /// Triangles per cluster, at most; a multiple of 4 from 4 up. Up to 512
    /// a cluster is one meshoptimizer meshlet; above, a group of 256-triangle
    /// meshlets.
    pub triangles: u32,
    /// Meshes with fewer triangles than this stay whole (a cluster of a
    /// small prop culls no better than the prop, and costs a draw).
    pub min_mesh_triangles: u32,
}

impl ClusterOptions {
    /// Clusters of up to `triangles`; meshes of under two clusters stay whole.
    pub fn new(triangles: u32) -> Self {
        ClusterOptions { triangles, min_mesh_triangles: 2 * triangles }
    }

    fn check(&self) -> crate::Result<()> {
        if self.triangles < 4 || !self.triangles.is_multiple_of(4) || self.triangles > 1 << 20 {
            return Err(crate::Error::Invalid(format!("clusters of {} triangles: use a multiple of 4 from 4 to 1048576", self.triangles)));
        }
        Ok(())
    }
}

/// meshoptimizer's limits for one meshlet (`meshopt_buildMeshletsSpatial`).
const MESHLET_MAX_TRIANGLES: u32 = 512;
const MESHLET_MAX_VERTICES: usize = 255;
/// Meshlet size grouped into larger clusters.
const GROUPED_MESHLET_TRIANGLES: u32 = 256;

impl Mesh {
    /// Splits the mesh into clusters of at most `triangles` (a multiple of
    /// 4): reorders `indices` so that each cluster is one contiguous run,
    /// reorders `vertices` in first-use order (dropping unused ones), and
    /// sets [`Mesh::clusters`]. The triangles are the same, each once.
    pub fn clusterize(&mut self, triangles: u32) {
        let positions: Vec<[f32; 3]> = self.vertices.iter().map(|v| v.position).collect();
        let adapter = meshopt::VertexDataAdapter::new(bytemuck::cast_slice(&positions), 12, 0).expect("12-byte positions");
        let meshlet_max = if triangles > MESHLET_MAX_TRIANGLES { GROUPED_MESHLET_TRIANGLES } else { triangles };
        // Fill clusters to at least half (fewer, larger draws), SAH-split.
        let min = (meshlet_max / 2).max(4) / 4 * 4;
        let m = meshopt::build_meshlets_spatial(&self.indices, &adapter, MESHLET_MAX_VERTICES, min as usize, meshlet_max as usize, 0.5);
        // Each meshlet's triangles as the mesh's own indices.
        let meshlet_indices: Vec<Vec<u32>> = m.iter().map(|ml| ml.triangles.iter().map(|&t| ml.vertices[t as usize]).collect()).collect();
        let groups: Vec<Vec<usize>> = if triangles > MESHLET_MAX_TRIANGLES && meshlet_indices.len() > 1 {
            let flat: Vec<u32> = meshlet_indices.iter().flatten().copied().collect();
            let counts: Vec<u32> = meshlet_indices.iter().map(|c| c.len() as u32).collect();
            let mut part = vec![0u32; counts.len()];
            let target = (triangles / GROUPED_MESHLET_TRIANGLES).max(1) as usize;
            let n = meshopt::partition_clusters_with_positions(&mut part, &flat, &counts, &adapter, target);
            let mut groups = vec![Vec::new(); n];
            for (c, &p) in part.iter().enumerate() {
                groups[p as usize].push(c);
            }
            groups.retain(|g| !g.is_empty());
            groups
        } else {
            (0..meshlet_indices.len()).map(|c| vec![c]).collect()
        };
        let mut indices = Vec::with_capacity(self.indices.len());
        let mut clusters = Vec::with_capacity(groups.len());
        for g in groups {
            let first = indices.len() as u32;
            for &c in &g {
                indices.extend_from_slice(&meshlet_indices[c]);
            }
            // Each cluster is its own draw: order its triangles for the
            // post-transform vertex cache (meshopt_optimizeVertexCache).
            meshopt::optimize_vertex_cache_in_place(&mut indices[first as usize..], positions.len());
            let run = &indices[first as usize..];
            let bounds = Aabb::from_points(run.iter().map(|&i| Vec3::from(positions[i as usize])));
            clusters.push(Cluster { first_index: first, index_count: run.len() as u32, bounds });
        }
        // Vertices in the order the clusters first use them
        // (meshopt_optimizeVertexFetch): a cluster's draw reads a compact
        // run of the vertex buffer. Unused vertices go; positions, and so
        // every box, stay as they were.
        let used = meshopt::optimize_vertex_fetch_in_place(&mut indices, &mut self.vertices);
        self.vertices.truncate(used);
        self.bounds = Aabb::from_points(self.vertices.iter().map(|v| Vec3::from(v.position)));
        self.indices = indices;
        self.clusters = clusters;
    }

    /// The index range `cluster` draws (`None`: the whole mesh).
    pub fn range(&self, cluster: Option<u32>) -> (u32, u32) {
        match cluster {
            Some(c) => {
                let c = &self.clusters[c as usize];
                (c.first_index, c.index_count)
            }
            None => (0, self.indices.len() as u32),
        }
    }

    /// Box of `cluster` (or of the whole mesh) in the mesh's space.
    pub fn part_local_bounds(&self, cluster: Option<u32>) -> Aabb {
        cluster.map_or(self.bounds, |c| self.clusters[c as usize].bounds)
    }

    /// Tight world box of `cluster` (or of the whole mesh) under `m`, as
    /// [`Mesh::world_bounds`].
    pub fn part_bounds(&self, cluster: Option<u32>, m: &Mat4) -> Aabb {
        let Some(c) = cluster else { return self.world_bounds(m) };
        let c = &self.clusters[c as usize];
        if crate::keeps_axes(m) {
            return c.bounds.transformed(m);
        }
        let run = &self.indices[c.first_index as usize..(c.first_index + c.index_count) as usize];
        Aabb::from_points(run.iter().map(|&i| m.transform_point3(Vec3::from(self.vertices[i as usize].position))))
    }
}

impl Scene {
    /// The scene with every mesh of at least `o.min_mesh_triangles`
    /// triangles split into clusters, and every object on such a mesh
    /// replaced by one object per cluster (same transform and colour, the
    /// cluster's tight box). Objects on smaller meshes stay whole.
    pub fn clustered(mut self, o: ClusterOptions) -> crate::Result<Scene> {
        o.check()?;
        let used: Vec<bool> = {
            let mut u = vec![false; self.meshes.len()];
            for ob in &self.objects {
                u[ob.mesh as usize] = true;
            }
            u
        };
        let split: Vec<bool> = self.meshes.iter().zip(&used).map(|(m, &u)| u && m.clusters.is_empty() && m.triangle_count() as u64 >= o.min_mesh_triangles as u64).collect();
        {
            use rayon::prelude::*;
            self.meshes.par_iter_mut().zip(&split).filter(|(_, &s)| s).for_each(|(m, _)| m.clusterize(o.triangles));
        }
        let objects = std::mem::take(&mut self.objects);
        for ob in objects {
            let mesh = &self.meshes[ob.mesh as usize];
            if !split[ob.mesh as usize] || ob.cluster.is_some() {
                self.objects.push(ob);
                continue;
            }
            for c in 0..mesh.clusters.len() as u32 {
                let bounds = mesh.part_bounds(Some(c), &ob.transform);
                self.objects.push(Object { cluster: Some(c), bounds, ..ob.clone() });
            }
        }
        self.validate()?;
        Ok(self)
    }
}
