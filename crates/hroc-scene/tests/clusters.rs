//! Clusters: every triangle lands in exactly one cluster, clusters respect
//! their size, and every cluster's box holds its triangles, in mesh space
//! and as an object's world box.

use glam::{Mat4, Quat, Vec3};
use hroc_scene::{load, Aabb, ClusterOptions, Mesh, Scene};
use proptest::prelude::*;

/// Triangles as a sorted multiset of their corners' positions (bit
/// patterns), each rotated to start at its smallest corner (winding kept):
/// independent of how vertices and triangles are ordered.
fn triangle_set(m: &Mesh) -> Vec<[[u32; 3]; 3]> {
    let corner = |i: u32| m.vertices[i as usize].position.map(f32::to_bits);
    let mut t: Vec<[[u32; 3]; 3]> = m
        .indices
        .chunks_exact(3)
        .map(|t| {
            let c = [corner(t[0]), corner(t[1]), corner(t[2])];
            let r = (0..3).min_by_key(|&i| c[i]).unwrap_or(0);
            [c[r], c[(r + 1) % 3], c[(r + 2) % 3]]
        })
        .collect();
    t.sort_unstable();
    t
}

/// `b` grown by a rounding margin.
fn grow(b: Aabb) -> Aabb {
    Aabb::new(b.min - Vec3::splat(1e-3), b.max + Vec3::splat(1e-3))
}

fn check_clusters(mesh: &Mesh, before: &Mesh, max: u32) {
    assert_eq!(triangle_set(mesh), triangle_set(before), "{}: triangles changed", mesh.name);
    // Vertices are in first-use order: every vertex is used, and vertex i
    // is first used before vertex i + 1.
    let mut seen = 0u32;
    for &i in &mesh.indices {
        assert!(i <= seen, "{}: vertex {i} used before vertex {seen}", mesh.name);
        seen = seen.max(i + 1);
    }
    assert_eq!(seen as usize, mesh.vertices.len(), "{}: unused vertices kept", mesh.name);
    let mut next = 0;
    for c in &mesh.clusters {
        assert_eq!(c.first_index, next, "{}: clusters are not consecutive runs", mesh.name);
        assert!(c.index_count > 0 && c.index_count % 3 == 0 && c.index_count / 3 <= max, "{}: cluster of {} indices", mesh.name, c.index_count);
        next += c.index_count;
        for &i in &mesh.indices[c.first_index as usize..next as usize] {
            let p = Vec3::from(mesh.vertices[i as usize].position);
            assert!(c.bounds.min.cmple(p).all() && p.cmple(c.bounds.max).all(), "{}: vertex {i} outside its cluster's box", mesh.name);
        }
    }
    assert_eq!(next as usize, mesh.indices.len(), "{}: clusters do not cover the mesh", mesh.name);
}

#[test]
fn clusters_partition_every_mesh() {
    for (key, max) in [("rooms", 64), ("factory", 128), ("satellites", 512), ("rooms", 2048)] {
        let scene = load(key, Some(200), 1).unwrap();
        for mesh in scene.meshes.iter().filter(|m| m.triangle_count() >= 8) {
            let mut m = mesh.clone();
            m.clusterize(max);
            check_clusters(&m, mesh, max);
            assert!(m.clusters.len() >= m.triangle_count().div_ceil(max as usize), "{key}: {} clusters for {} triangles", m.clusters.len(), m.triangle_count());
        }
    }
}

#[test]
fn clustered_scenes_keep_every_triangle_once() {
    let whole = load("rooms", Some(300), 4).unwrap();
    let c = whole.clone().clustered(ClusterOptions::new(64)).unwrap();
    assert_eq!(c.stats().triangles, whole.stats().triangles);
    // Vertex fetch order drops vertices no triangle uses, and no other.
    assert!(c.stats().vertices <= whole.stats().vertices);
    assert!(c.objects.len() > whole.objects.len());
    // Every object's box holds its cluster's vertices under its transform.
    for o in &c.objects {
        let m = &c.meshes[o.mesh as usize];
        let (first, count) = m.range(o.cluster);
        for &i in &m.indices[first as usize..(first + count) as usize] {
            let p = o.transform.transform_point3(Vec3::from(m.vertices[i as usize].position));
            assert!(grow(o.bounds).contains_point(p), "vertex outside its object's box");
        }
    }
    // Clustering twice changes nothing.
    let again = c.clone().clustered(ClusterOptions::new(64)).unwrap();
    assert_eq!(again.objects.len(), c.objects.len());
}

#[test]
fn bad_cluster_sizes_are_errors() {
    let s = load("rooms", Some(50), 0).unwrap();
    for bad in [0, 2, 6, 1 << 21] {
        let e = s.clone().clustered(ClusterOptions::new(bad)).unwrap_err().to_string();
        assert!(e.contains("multiple of 4"), "{bad}: {e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Random triangle soups under a random rotation: clusters partition the
    /// triangles and their world boxes hold every transformed vertex.
    #[test]
    fn random_meshes_cluster_and_bound(seed in 0u64..1000, tris in 1usize..700, max in prop::sample::select(vec![4u32, 64, 128, 512, 1024])) {
        let mut rng = hroc_scene::rng::Rng::new(seed);
        let n = tris * 2 + 3;
        let positions: Vec<[f32; 3]> = (0..n).map(|_| [rng.range(-10.0, 10.0), rng.range(-10.0, 10.0), rng.range(-10.0, 10.0)]).collect();
        let indices: Vec<u32> = (0..tris * 3).map(|_| rng.below(n) as u32).collect();
        let soup = Mesh::new("soup", positions, None, indices);
        let mut scene = Scene { name: "soup".into(), meshes: vec![soup.clone()], ..Default::default() };
        let t = Mat4::from_rotation_translation(Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.7), Vec3::new(5.0, -2.0, 1.0));
        scene.push_object(0, t, [1.0; 3]);
        let min = if tris >= 2 * max as usize { 2 * max } else { 1 };
        let c = scene.clustered(ClusterOptions { triangles: max, min_mesh_triangles: min }).unwrap();
        if c.meshes[0].clusters.is_empty() {
            prop_assert_eq!(&c.meshes[0].indices, &soup.indices);
        } else {
            check_clusters(&c.meshes[0], &soup, max);
        }
        for o in &c.objects {
            let m = &c.meshes[0];
            let (first, count) = m.range(o.cluster);
            let b: Aabb = grow(o.bounds);
            for &i in &m.indices[first as usize..(first + count) as usize] {
                prop_assert!(b.contains_point(t.transform_point3(Vec3::from(m.vertices[i as usize].position))));
            }
        }
    }
}
