//! Renders for real (lavapipe in CI): noc vs ref pixel for pixel, vfc
//! conservative on the hard paths, and GPU passes against CPU references.

use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use hroc_bench::scene::{camera::aabb_in_frustum, paths, CameraPath, Scene};
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);

/// One device for the whole binary: opening lavapipe costs time.
fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

fn scene(key: &str, n: usize) -> Scene {
    hroc_bench::scene::load(key, Some(n), 7).unwrap()
}

/// Runs `method` over every frame, checking each against noc.
fn assert_conservative(s: &mut Session, method: &str) -> (usize, usize) {
    let mut c = s.create(method.parse().unwrap()).unwrap();
    let (mut drawn, mut visible) = (0, 0);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        if c.wants_oracle() {
            c.set_oracle(&s.culler, &truth.visible).unwrap();
        }
        let r = s.run_frame(&mut c, k).unwrap();
        let chk = s.check(&r, &truth).unwrap();
        assert_eq!(chk.false_negatives, 0, "{method}: false negatives at frame {k} ({:?})", s.cameras[k]);
        assert_eq!(chk.missing_pixels, 0, "{method}: missing pixels at frame {k} ({:?})", s.cameras[k]);
        drawn += chk.drawn;
        visible += truth.visible.len();
    }
    (drawn, visible)
}

#[test]
fn ref_matches_noc_pixel_for_pixel() {
    let gpu = gpu();
    let mut s = Session::new(gpu, scene("radial-city", 3000), None, 8, RES, Split::Sah).unwrap();
    let mut r = s.create("ref".parse().unwrap()).unwrap();
    let mut any_culled = false;
    for k in 0..s.cameras.len() {
        s.truth(k).unwrap();
        let noc_ids: Vec<u32> = gpu.read_texture(&s.renderer.targets.id, wgpu::TextureAspect::All).unwrap();
        let truth = s.read_truth().unwrap();
        r.set_oracle(&s.culler, &truth.visible).unwrap();
        let res = s.run_frame(&mut r, k).unwrap();
        let ref_ids: Vec<u32> = gpu.read_texture(&s.renderer.targets.id, wgpu::TextureAspect::All).unwrap();
        let diff = noc_ids.iter().zip(&ref_ids).filter(|(a, b)| a != b).count();
        assert_eq!(diff, 0, "frame {k}: {diff} ID pixels differ");
        let chk = s.check(&res, &truth).unwrap();
        assert_eq!(chk.drawn, truth.visible.len());
        any_culled |= chk.drawn < s.renderer.object_count as usize;
        assert!(noc_ids.iter().any(|&i| i != 0), "frame {k} drew nothing");
    }
    assert!(any_culled, "ref never culled anything: the test scene shows no occlusion");
}

#[test]
fn vfc_is_conservative_on_hard_paths() {
    for key in ["radial-city", "rooms", "satellites"] {
        let sc = scene(key, 1500);
        let path = paths::hard_path(&sc);
        assert!(paths::cut_times(&path).len() >= 3);
        let mut s = Session::new(gpu(), sc, Some(path), 24, RES, Split::Sah).unwrap();
        let (drawn, _) = assert_conservative(&mut s, "vfc");
        assert!(drawn < 24 * s.renderer.object_count as usize, "{key}: vfc culled nothing on the whole path");
    }
}

#[test]
fn vfc_and_ref_are_conservative_on_every_scene_path() {
    for key in hroc_bench::scene::generators::keys() {
        let mut s = Session::new(gpu(), scene(key, 800), None, 6, RES, Split::Sah).unwrap();
        for m in ["vfc", "ref"] {
            assert_conservative(&mut s, m);
        }
    }
}

#[test]
fn frame_zero_and_a_camera_cut_from_a_file() {
    let dir = std::env::temp_dir().join(format!("hroc-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("cut.json");
    std::fs::write(
        &f,
        r#"{"keys":[{"t":0,"eye":[0,2,-60],"target":[0,2,0]},{"t":5,"eye":[0,2,-20],"target":[0,2,0]},
                    {"t":5,"eye":[40,30,40],"target":[0,0,0]},{"t":10,"eye":[-40,3,40],"target":[0,3,0]}]}"#,
    )
    .unwrap();
    let path = CameraPath::from_file(&f).unwrap();
    let mut s = Session::new(gpu(), scene("radial-city", 1000), Some(path), 11, RES, Split::Mid).unwrap();
    assert_conservative(&mut s, "vfc");
}

#[test]
fn gpu_frustum_culling_matches_cpu_reference() {
    let gpu = gpu();
    let sc = scene("satellites", 4000);
    let path = paths::hard_path(&sc);
    let mut s = Session::new(gpu, sc, Some(path), 10, RES, Split::Sah).unwrap();
    let mut vfc = s.create("vfc".parse().unwrap()).unwrap();
    for k in 0..s.cameras.len() {
        let r = s.run_frame(&mut vfc, k).unwrap();
        let gpu_set = s.drawn(&r.lists).unwrap();
        let planes = hroc_bench::scene::camera::frustum_planes(&s.cameras[k].view_proj(s.renderer.aspect()));
        for (i, o) in s.scene.objects.iter().enumerate() {
            let cpu = aabb_in_frustum(&planes, o.bounds.min, o.bounds.max);
            if cpu != gpu_set[i] {
                // Only a box touching a plane within float rounding may differ.
                let margin = planes
                    .iter()
                    .map(|p| {
                        let v = glam::Vec3::select(p.truncate().cmpge(glam::Vec3::ZERO), o.bounds.max, o.bounds.min);
                        (p.truncate().dot(v) + p.w).abs()
                    })
                    .fold(f32::INFINITY, f32::min);
                assert!(margin < 1e-3, "frame {k} object {i}: cpu {cpu} gpu {} (margin {margin})", gpu_set[i]);
            }
        }
    }
}

#[test]
fn gpu_compaction_keeps_order_and_counts() {
    use hroc::testing::{compact::Compactor, layout::DrawCommand};
    use wgpu::BufferUsages as U;
    let gpu = gpu();
    // Sizes around a thread's run of 8, the 2048-item blocks and the
    // block scan's chunks of 256 blocks.
    for n in [1u32, 7, 8, 9, 255, 256, 257, 1000, 2047, 2048, 2049, 70_000, 600_000] {
        let flags: Vec<u32> = (0..n).map(|i| ((i.wrapping_mul(2654435761) >> 7) % 3 == 0) as u32).collect();
        let src: Vec<DrawCommand> = (0..n).map(|i| DrawCommand { index_count: 3, instance_count: 1, first_index: i * 3, base_vertex: 0, first_instance: i }).collect();
        let fb = gpu.buffer_init("flags", bytemuck::cast_slice(&flags), U::STORAGE);
        let sb = gpu.buffer_init("src", bytemuck::cast_slice(&src), U::STORAGE);
        let db = gpu.buffer("dst", n as u64 * 20, U::STORAGE | U::COPY_SRC);
        let cb = gpu.buffer("count", 4, U::STORAGE | U::COPY_SRC);
        let c = Compactor::new(&core_gpu(gpu), n);
        let job = c.job(&core_gpu(gpu), &fb, &sb, &db, &cb);
        let mut enc = gpu.encoder("test");
        c.record(&mut enc, &hroc::testing::gpu::PassCount::NONE, &job);
        gpu.queue.submit([enc.finish()]);
        let expect: Vec<DrawCommand> = src.iter().zip(&flags).filter(|(_, f)| **f != 0).map(|(c, _)| *c).collect();
        let count = gpu.read::<u32>(&cb, 0, 1).unwrap()[0];
        assert_eq!(count as usize, expect.len(), "n = {n}");
        assert_eq!(gpu.read::<DrawCommand>(&db, 0, count as u64).unwrap(), expect, "n = {n}");
    }
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
