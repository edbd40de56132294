//! Moving objects (`Culler::set_bounds`, BVH refit) on lavapipe: every
//! method that follows motion stays conservative against `noc` on every
//! frame while occluders move, occludees come out from behind them, and
//! objects teleport in front of the camera; the query methods, which keep
//! their own BVH, refuse the frame instead of culling wrongly.

use glam::{Mat4, Vec3};
use hroc::bvh::Bvh;
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const FRAMES: usize = 20;
const MOVING: [&str; 8] = ["vfc", "roc", "roc-all", "ioc", "hzb", "hroc", "hroc-na", "hroc-cr"];

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

/// Frame k's moves: every tenth object slides back and forth across the
/// view (occluders leave, occludees come out from behind them), and every
/// fourth frame a few objects teleport in front of the camera.
fn moves(s: &Session, base: &[Mat4], k: usize) -> Vec<(u32, Mat4)> {
    let n = base.len();
    let mut out: Vec<(u32, Mat4)> =
        (0..n).step_by(10).map(|i| (i as u32, Mat4::from_translation(Vec3::new(12.0 * (k as f32 * 0.6 + i as f32).sin(), 0.0, 9.0 * (k as f32 * 0.4).cos())) * base[i])).collect();
    if k % 4 == 3 {
        let cam = s.cameras[k.min(s.cameras.len() - 1)];
        let ahead = cam.eye + (cam.target - cam.eye).normalize() * 12.0;
        for (j, i) in (5..n).step_by(n / 4).take(3).enumerate() {
            out.push((i as u32, Mat4::from_translation(ahead + Vec3::new(j as f32 * 3.0 - 3.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.5))));
        }
    }
    out
}

#[test]
fn moving_objects_stay_conservative() {
    let scene = hroc_bench::scene::load("radial-city", Some(1500), 4).unwrap();
    let base: Vec<Mat4> = scene.objects.iter().map(|o| o.transform).collect();
    let mut s = Session::new(gpu(), scene, None, FRAMES, RES, Split::Sah).unwrap();
    let mut views: Vec<hroc::View> = MOVING.iter().map(|m| s.create(m.parse().unwrap()).unwrap()).collect();
    let mut chc = s.create("chc++".parse().unwrap()).unwrap();
    let n = s.renderer.object_count as usize;
    let (mut drawn, mut visible) = (0, 0);
    for k in 0..FRAMES {
        let m = moves(&s, &base, k);
        s.move_objects(&m).unwrap();
        // The refit BVH holds every moved box.
        let boxes: Vec<_> = s.scene.objects.iter().map(|o| o.bounds).collect();
        s.bvh().validate(&boxes).unwrap();
        let (_, truth) = s.truth(k).unwrap();
        visible += truth.visible.len();
        for v in views.iter_mut() {
            let r = s.run_frame(v, k).unwrap();
            let c = s.check(&r, &truth).unwrap();
            assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{} frame {k}: missed objects/pixels under motion", v.method());
            drawn += c.drawn;
        }
        let e = s.run_frame(&mut chc, k).err().expect("chc++ cannot follow motion").to_string();
        assert!(e.contains("static scenes only"), "{e}");
    }
    // Culling still happens while objects move.
    assert!(visible > 0 && drawn < n * FRAMES * MOVING.len() / 4, "drew {drawn} of {} (visible {visible})", n * FRAMES * MOVING.len());
}

#[test]
fn refit_equals_a_tree_holding_the_new_boxes() {
    let scene = hroc_bench::scene::load("satellites", Some(800), 2).unwrap();
    let mut boxes: Vec<_> = scene.objects.iter().map(|o| o.bounds).collect();
    let mut bvh = Bvh::build(&boxes, Split::Sah);
    let cost = bvh.sah_cost();
    for (i, b) in boxes.iter_mut().enumerate().step_by(3) {
        let d = Vec3::new((i as f32).sin(), 0.5, (i as f32).cos()) * 20.0;
        (b.min, b.max) = (b.min + d, b.max + d);
    }
    bvh.refit(&boxes);
    bvh.validate(&boxes).unwrap();
    // Every interior box is exactly the union of its children's.
    for n in 0..bvh.nodes.len() as u32 {
        if let Some([l, r]) = bvh.children(n) {
            assert_eq!(bvh.aabb(n), bvh.aabb(l).union(bvh.aabb(r)), "node {n}");
        }
    }
    assert!(bvh.sah_cost() > cost, "moving a third of the objects should degrade the tree");
}

/// Motion on the hard paths (frame 0, cuts, the eye inside object and group
/// boxes, boxes across the near plane): a third of the objects move as
/// their scene moves them, half of those DYNAMIC (the hybrid) and half
/// refit, under the default rebuild policy; a tenth of the objects leave at
/// the path's first third and come back at its second, where they were.
/// Every method that takes DYNAMIC objects stays at 0 false negatives and
/// 0 missing pixels on every frame.
#[test]
fn motion_on_hard_paths_stays_conservative() {
    const METHODS: [&str; 7] = ["vfc", "roc", "hzb", "hroc", "hroc-na", "hroc-cr", "hroc-of"];
    const FRAMES: usize = 24;
    for key in ["radial-city", "factory", "satellites"] {
        let scene = hroc_bench::scene::load(key, Some(1200), 6).unwrap();
        let path = hroc_bench::scene::paths::hard_path(&scene);
        let base: Vec<Mat4> = scene.objects.iter().map(|o| o.transform).collect();
        let centre = scene.bounds().center();
        let n = scene.objects.len();
        let mut s = Session::new(gpu(), scene, Some(path), FRAMES, RES, Split::Sah).unwrap();
        let movers = hroc_bench::scene::motion::moving_objects(n, 1.0 / 3.0);
        let flags: Vec<(u32, hroc::ObjectFlags)> = movers.iter().step_by(2).map(|&i| (i, hroc::ObjectFlags::DYNAMIC)).collect();
        s.culler.set_many_flags(&flags).unwrap();
        let leaving: Vec<u32> = (1..n as u32).step_by(10).collect();
        let mut views: Vec<hroc::View> = METHODS.iter().map(|m| s.create(m.parse().unwrap()).unwrap()).collect();
        let mut drawn = 0;
        for k in 0..FRAMES {
            let t = s.times[k];
            let gone = (FRAMES / 3..2 * FRAMES / 3).contains(&k);
            let moves: Vec<(u32, Mat4)> =
                movers.iter().filter(|i| !(gone && leaving.contains(i))).map(|&i| (i, hroc_bench::scene::motion::moved(key, centre, &base[i as usize], i, t))).collect();
            if k == FRAMES / 3 {
                s.remove_objects(&leaving).unwrap();
            }
            if k == 2 * FRAMES / 3 {
                let back: Vec<(u32, Mat4)> = leaving.iter().map(|&i| (i, hroc_bench::scene::motion::moved(key, centre, &base[i as usize], i, t))).collect();
                s.add_objects(&back).unwrap();
            }
            s.move_objects(&moves).unwrap();
            let (_, truth) = s.truth(k).unwrap();
            if gone {
                assert!(leaving.iter().all(|i| !truth.visible.contains(i)), "{key} frame {k}: a removed object is drawn");
            }
            for v in views.iter_mut() {
                let r = s.run_frame(v, k).unwrap();
                let c = s.check(&r, &truth).unwrap();
                assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{key} {} frame {k}: missed objects/pixels", v.method());
                drawn += c.drawn;
            }
        }
        assert!(drawn < n * FRAMES * METHODS.len(), "{key}: nothing culled");
    }
}
