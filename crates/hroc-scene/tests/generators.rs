//! Built-in scene generators: exact counts, determinism, shared meshes,
//! sane camera paths, triangle budgets.

use glam::{Mat4, Vec3};
use hroc::geometry::{aabb_in_frustum, frustum_planes};
use hroc_scene::{generators, load, Aabb, Scene};
use std::time::Instant;

const EXPECTED: [&str; 11] = ["rooms", "downtown", "figures", "fantasy", "factory", "radial-city", "radial-city-fast", "satellites", "library", "teapots", "houses"];

fn gen(key: &str, n: usize, seed: u64) -> Scene {
    let g = generators::find(key).unwrap_or_else(|| panic!("no generator '{key}'"));
    generators::generate(g, n, seed).unwrap_or_else(|e| panic!("{key} x{n}: {e}"))
}

fn boxes(s: &Scene) -> Vec<(Vec3, Vec3)> {
    s.objects.iter().map(|o| (o.bounds.min, o.bounds.max)).collect()
}

#[test]
fn keys_and_table() {
    assert_eq!(generators::keys(), EXPECTED.to_vec());
    for k in EXPECTED {
        let g = generators::find(k).unwrap();
        assert_eq!(g.key, k);
        assert!(!g.description.is_empty());
        assert!(g.default_objects >= 1 && g.paper_objects >= g.default_objects, "{k}");
    }
    let paper = [
        ("rooms", 2_753),
        ("downtown", 31_392),
        ("figures", 72_000),
        ("fantasy", 7_437),
        ("factory", 46_600),
        ("radial-city", 73_812),
        ("satellites", 120_000),
        ("library", 40_000),
        ("teapots", 5_000),
    ];
    for (k, n) in paper {
        assert_eq!(generators::find(k).unwrap().paper_objects, n, "{k}");
    }
    assert!(generators::find("nope").is_none());
}

#[test]
fn load_uses_generators() {
    let s = load("teapots", Some(33), 5).unwrap();
    assert_eq!(s.objects.len(), 33);
    assert_eq!(s.name, "teapots");
}

/// The path is well formed, spans 10 s and (for scenes with some
/// structure, not just a handful of objects) stays inside or near the scene.
fn check_path(key: &str, s: &Scene) {
    let p = &s.path;
    p.validate().unwrap_or_else(|e| panic!("{key}: path {e}"));
    assert!(p.keys.len() >= 11, "{key}: {} keys", p.keys.len());
    assert_eq!(p.keys[0].t, 0.0, "{key}");
    assert!((p.duration() - 10.0).abs() < 1e-3, "{key}: duration {}", p.duration());
    if s.objects.len() < 100 {
        return;
    }
    let b = s.bounds();
    let margin = b.extent() * 0.05 + Vec3::splat(1.0);
    let grown = Aabb::new(b.min - margin, b.max + margin);
    for k in &p.keys {
        assert!(grown.contains_point(Vec3::from(k.eye)), "{key}: eye {:?} outside {:?}", k.eye, b);
    }
}

/// Fraction of path samples whose eye lies inside some object's box.
fn eye_inside_fraction(s: &Scene) -> f32 {
    let samples = 200;
    let inside = (0..samples)
        .filter(|&i| {
            let eye = s.path.sample(10.0 * i as f32 / (samples - 1) as f32, 0.1, 1000.0).eye;
            s.objects.iter().any(|o| o.bounds.contains_point(eye))
        })
        .count();
    inside as f32 / samples as f32
}

#[test]
fn every_scene_at_default_size() {
    for g in generators::all() {
        let t = Instant::now();
        let s = gen(g.key, g.default_objects, 1);
        let dt = t.elapsed();
        let st = s.stats();
        assert_eq!(st.objects, g.default_objects, "{}", g.key);
        s.validate().unwrap();
        check_path(g.key, &s);
        // Shared meshes: a few dozen at most, instanced.
        assert!(st.meshes <= 64 && st.meshes * 20 < st.objects, "{}: {} meshes", g.key, st.meshes);
        // Lavapipe budget: drawing everything stays a few million triangles.
        assert!(st.triangles <= 3_000_000, "{}: {} triangles", g.key, st.triangles);
        let per = st.triangles as f64 / st.objects as f64;
        assert!(per >= 12.0, "{}: {per:.1} triangles per object", g.key);
        let inside = eye_inside_fraction(&s);
        assert!(inside <= 0.05, "{}: eye inside an object box on {:.0}% of the path", g.key, inside * 100.0);
        println!(
            "{:17} objects {:6} meshes {:3} triangles {:8} ({:6.1}/object) bounds {:?} eye-in-box {:.0}% in {:?}",
            g.key,
            st.objects,
            st.meshes,
            st.triangles,
            per,
            s.bounds().extent(),
            inside * 100.0,
            dt
        );
    }
}

#[test]
fn small_counts_are_exact() {
    for k in EXPECTED {
        for n in [0, 1, 2, 7, 50, 500] {
            let s = gen(k, n, 3);
            assert_eq!(s.objects.len(), n.max(1), "{k} x{n}");
            s.validate().unwrap();
            check_path(k, &s);
        }
    }
}

#[test]
fn deterministic_per_seed() {
    for k in EXPECTED {
        let a = gen(k, 1500, 42);
        let b = gen(k, 1500, 42);
        let c = gen(k, 1500, 43);
        assert!(boxes(&a) == boxes(&b), "{k}: same seed, different objects");
        assert!(a.path == b.path, "{k}: same seed, different path");
        let colors = |s: &Scene| s.objects.iter().map(|o| o.color).collect::<Vec<_>>();
        assert!(colors(&a) == colors(&b), "{k}: same seed, different colours");
        assert!(boxes(&a) != boxes(&c), "{k}: seed ignored");
        assert!(a.path != c.path, "{k}: seed ignored by the path");
    }
}

#[test]
fn radial_city_fast_shares_the_scene() {
    let a = gen("radial-city", 3000, 9);
    let b = gen("radial-city-fast", 3000, 9);
    assert!(boxes(&a) == boxes(&b), "RC' must draw RC's objects");
    assert_eq!(a.meshes.len(), b.meshes.len());
    assert!(a.path != b.path, "RC' needs its own path");
    // RC' turns faster: compare total yaw change over the path.
    let turn = |s: &Scene| {
        let dirs: Vec<Vec3> = (0..=200)
            .map(|i| {
                let c = s.path.sample(i as f32 * 0.05, 0.1, 1e4);
                (c.target - c.eye).normalize()
            })
            .collect();
        dirs.windows(2).map(|w| w[0].dot(w[1]).clamp(-1.0, 1.0).acos()).sum::<f32>()
    };
    assert!(turn(&b) > 2.0 * turn(&a), "RC' turns {} vs {}", turn(&b), turn(&a));
}

#[test]
fn large_scenes_share_meshes_and_generate_fast() {
    for k in EXPECTED {
        let t = Instant::now();
        let s = gen(k, 120_000, 7);
        let dt = t.elapsed();
        assert_eq!(s.objects.len(), 120_000);
        assert!(s.meshes.len() <= 64, "{k}: {} meshes", s.meshes.len());
        // Release builds take a fraction of a second; leave room for a busy machine.
        assert!(dt.as_secs_f32() < 5.0, "{k}: 120k objects took {dt:?}");
        println!("{k:17} 120k objects in {dt:?}");
    }
}

#[test]
fn scenes_grow_with_object_count() {
    for k in EXPECTED {
        let (small, large) = (gen(k, 2_000, 1), gen(k, 32_000, 1));
        check_path(k, &small);
        check_path(k, &large);
        let (small, large) = (small.bounds().extent(), large.bounds().extent());
        let (sa, la) = (small.x * small.z, large.x * large.z);
        assert!(la > 2.0 * sa, "{k}: footprint {sa} -> {la}");
    }
}

// ---------------------------------------------------------------------------
// CPU ray-cast occlusion estimate, for tuning the generators by hand:
// `cargo test --release --test generators -- --ignored --nocapture occlusion`.

struct Caster<'a> {
    scene: &'a Scene,
    tris: Vec<Vec<[Vec3; 3]>>,
    inv: Vec<Mat4>,
    nodes: Vec<(Aabb, u32, u32)>, // box, first, count (count 0: children at first, first + 1)
    order: Vec<u32>,
}

impl<'a> Caster<'a> {
    fn new(scene: &'a Scene) -> Self {
        let tris = scene
            .meshes
            .iter()
            .map(|m| m.indices.chunks_exact(3).map(|t| t.iter().map(|&i| Vec3::from(m.vertices[i as usize].position)).collect::<Vec<_>>().try_into().unwrap()).collect())
            .collect();
        let inv = scene.objects.iter().map(|o| o.transform.inverse()).collect();
        let mut c = Caster { scene, tris, inv, nodes: vec![], order: (0..scene.objects.len() as u32).collect() };
        c.nodes.push((Aabb::EMPTY, 0, 0));
        c.build(0, 0, scene.objects.len());
        c
    }

    fn build(&mut self, node: usize, lo: usize, hi: usize) {
        let objs = &self.scene.objects;
        let b = self.order[lo..hi].iter().fold(Aabb::EMPTY, |b, &i| b.union(objs[i as usize].bounds));
        if hi - lo <= 4 {
            self.nodes[node] = (b, lo as u32, (hi - lo) as u32);
            return;
        }
        let cb = self.order[lo..hi].iter().fold(Aabb::EMPTY, |b, &i| b.grow_point(objs[i as usize].bounds.center()));
        let e = cb.extent();
        let axis = if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        };
        let mid = (lo + hi) / 2;
        self.order[lo..hi].select_nth_unstable_by(mid - lo, |&a, &b| objs[a as usize].bounds.center()[axis].total_cmp(&objs[b as usize].bounds.center()[axis]));
        let first = self.nodes.len();
        self.nodes.push((Aabb::EMPTY, 0, 0));
        self.nodes.push((Aabb::EMPTY, 0, 0));
        self.nodes[node] = (b, first as u32, 0);
        self.build(first, lo, mid);
        self.build(first + 1, mid, hi);
    }

    fn slab(b: &Aabb, o: Vec3, inv_d: Vec3, tmax: f32) -> Option<f32> {
        let t0 = (b.min - o) * inv_d;
        let t1 = (b.max - o) * inv_d;
        let tn = t0.min(t1).max_element().max(0.0);
        let tf = t0.max(t1).min_element().min(tmax);
        (tn <= tf).then_some(tn)
    }

    fn hit_object(&self, i: usize, o: Vec3, d: Vec3, tmax: f32) -> Option<(f32, Vec3)> {
        let m = &self.inv[i];
        let (lo, ld) = (m.transform_point3(o), m.transform_vector3(d));
        let mut best = tmax;
        let mut normal = Vec3::ZERO;
        for [a, b, c] in &self.tris[self.scene.objects[i].mesh as usize] {
            let (e1, e2) = (*b - *a, *c - *a);
            let p = ld.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-12 {
                continue;
            }
            let s = lo - *a;
            let u = s.dot(p) / det;
            if !(0.0..=1.0).contains(&u) {
                continue;
            }
            let q = s.cross(e1);
            let v = ld.dot(q) / det;
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            let t = e2.dot(q) / det;
            if t > 1e-4 && t < best {
                best = t;
                normal = e1.cross(e2);
            }
        }
        // World normal: inverse transpose of the object transform.
        let n = glam::Mat3::from_mat4(*m).transpose() * normal;
        (best < tmax).then_some((best, n.normalize_or_zero()))
    }

    /// Nearest hit: object and world normal of the triangle hit.
    fn cast(&self, o: Vec3, d: Vec3, near: f32) -> Option<(usize, Vec3)> {
        let inv_d = d.recip();
        let mut best = (f32::INFINITY, None);
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let (b, first, count) = self.nodes[n];
            if Self::slab(&b, o, inv_d, best.0).is_none() {
                continue;
            }
            if count > 0 {
                for &i in &self.order[first as usize..(first + count) as usize] {
                    if let Some((t, n)) = self.hit_object(i as usize, o, d, best.0) {
                        if t > near {
                            best = (t, Some((i as usize, n)));
                        }
                    }
                }
            } else {
                let (a, c) = (first as usize, first as usize + 1);
                let ta = Self::slab(&self.nodes[a].0, o, inv_d, best.0).unwrap_or(f32::INFINITY);
                let tc = Self::slab(&self.nodes[c].0, o, inv_d, best.0).unwrap_or(f32::INFINITY);
                if ta < tc {
                    stack.extend([c, a]);
                } else {
                    stack.extend([a, c]);
                }
            }
        }
        best.1
    }
}

#[test]
#[ignore = "a measurement for tuning the scenes, not a check: run with --ignored --nocapture"]
fn occlusion_estimate() {
    let only = std::env::var("SCENES").ok();
    let n: Option<usize> = std::env::var("OBJECTS").ok().and_then(|v| v.parse().ok());
    let w: usize = std::env::var("RES").ok().and_then(|v| v.parse().ok()).unwrap_or(240);
    let h = w * 9 / 16;
    for g in generators::all() {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|k| k == g.key)) {
            continue;
        }
        let s = gen(g.key, n.unwrap_or(g.default_objects), 1);
        let caster = Caster::new(&s);
        let (near, far) = hroc_scene::camera::clip_planes(&s.bounds(), &s.path);
        let (mut sum_hidden, mut sum_vis, mut frames) = (0.0, 0.0, 0);
        let (mut hits, mut back_hits) = (0usize, 0usize);
        let mut line = String::new();
        let img_dir = std::env::var("IMG").ok();
        let mut sheet = image::RgbImage::new(2 * w as u32, 2 * h as u32);
        let sheet_frames: Vec<usize> = std::env::var("SHEET").map(|v| v.split(',').filter_map(|f| f.parse().ok()).collect()).unwrap_or(vec![0, 3, 6, 9]);
        for (fi, cam) in s.path.frames(11, near, far).into_iter().enumerate() {
            let mut img = image::RgbImage::new(w as u32, h as u32);
            let vp = cam.view_proj(16.0 / 9.0);
            let planes = frustum_planes(&vp);
            let in_frustum = s.objects.iter().filter(|o| aabb_in_frustum(&planes, o.bounds.min, o.bounds.max)).count();
            let inv = vp.inverse();
            let mut seen = vec![false; s.objects.len()];
            for y in 0..h {
                for x in 0..w {
                    let ndc = Vec3::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / h as f32 * 2.0, 1.0);
                    let p = inv.project_point3(ndc);
                    let d = (p - cam.eye).normalize();
                    let mut px = [40u8, 50, 70];
                    if let Some((i, n)) = caster.cast(cam.eye, d, near) {
                        seen[i] = true;
                        hits += 1;
                        // Triangles are wound CCW seen from outside: a first hit
                        // on a back face means a flipped triangle (or an open mesh).
                        if n.dot(d) > 0.0 {
                            back_hits += 1;
                        }
                        let shade = 0.35 + 0.65 * n.dot(Vec3::new(0.4, 0.8, 0.3).normalize()).abs();
                        px = s.objects[i].color.map(|c| ((c * shade).clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8);
                    }
                    img.put_pixel(x as u32, y as u32, image::Rgb(px));
                }
            }
            if let Some(q) = sheet_frames.iter().position(|&f| f == fi) {
                image::imageops::replace(&mut sheet, &img, (q % 2 * w) as i64, (q / 2 * h) as i64);
            }
            let visible = seen.iter().filter(|&&v| v).count();
            let hidden = 1.0 - visible as f32 / in_frustum.max(1) as f32;
            line += &format!(" {:.0}%/{}", hidden * 100.0, in_frustum);
            sum_hidden += hidden;
            sum_vis += visible as f32 / s.objects.len() as f32;
            frames += 1;
        }
        if let Some(dir) = &img_dir {
            sheet.save(format!("{dir}/{}.png", g.key)).unwrap();
        }
        println!(
            "{:17} N {:6}: in-frustum objects hidden by occlusion avg {:.0}%, visible avg {:.1}% of N, back-face hits {:.2}%; per frame (hidden/in-frustum):{}",
            g.key,
            s.objects.len(),
            sum_hidden / frames as f32 * 100.0,
            sum_vis / frames as f32 * 100.0,
            back_hits as f32 / hits.max(1) as f32 * 100.0,
            line
        );
    }
}

/// Per-mesh triangle counts and instance counts, for tuning budgets:
/// `cargo test --release --test generators -- --ignored --nocapture mesh_report`.
#[test]
#[ignore = "a report for tuning budgets, not a check: run with --ignored --nocapture"]
fn mesh_report() {
    let only = std::env::var("SCENES").ok();
    for g in generators::all() {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|k| k == g.key)) {
            continue;
        }
        let s = gen(g.key, g.default_objects, 1);
        let mut uses = vec![0usize; s.meshes.len()];
        for o in &s.objects {
            uses[o.mesh as usize] += 1;
        }
        println!("{} ({} triangles):", g.key, s.stats().triangles);
        for (m, u) in s.meshes.iter().zip(uses) {
            let (lo, hi) = (m.bounds.min, m.bounds.max);
            println!("  {:20} {:6} tris x {:6} = {:8}  bounds {:.2?} .. {:.2?}", m.name, m.triangle_count(), u, m.triangle_count() * u, lo.to_array(), hi.to_array());
        }
    }
}

/// Object boxes are the tight boxes of the transformed vertices: they hold
/// every vertex (conservative), touch one on each side (tight), and are
/// never looser than the transformed mesh box they replace.
#[test]
fn object_boxes_are_tight() {
    for key in ["satellites", "factory", "fantasy"] {
        let s = gen(key, 400, 5);
        let mut tighter = 0;
        for (i, o) in s.objects.iter().enumerate() {
            let mesh = &s.meshes[o.mesh as usize];
            let pts: Vec<Vec3> = mesh.vertices.iter().map(|v| o.transform.transform_point3(Vec3::from(v.position))).collect();
            let exact = Aabb::from_points(pts.iter().copied());
            let eps = 1e-4 * exact.extent().max_element().max(1.0);
            assert!((o.bounds.min - exact.min).abs().max_element() <= eps, "{key} object {i}: min {:?} vs {:?}", o.bounds.min, exact.min);
            assert!((o.bounds.max - exact.max).abs().max_element() <= eps, "{key} object {i}: max {:?} vs {:?}", o.bounds.max, exact.max);
            let loose = mesh.bounds.transformed(&o.transform);
            assert!(loose.contains(&Aabb { min: o.bounds.min + eps, max: o.bounds.max - eps }), "{key} object {i}");
            if loose.area() > o.bounds.area() * 1.05 {
                tighter += 1;
            }
        }
        println!("{key}: {tighter} of {} boxes tighter than the transformed mesh box", s.objects.len());
        if key == "satellites" {
            assert!(tighter > s.objects.len() / 4, "satellites spin freely: most boxes should tighten");
        }
    }
}
