//! Moving objects (`Culler::set_bounds`, BVH refit) on lavapipe: every
//! method that follows motion stays conservative against `noc` on every
//! frame while occluders move, occludees come out from behind them, and
//! objects teleport in front of the camera; the query methods, which keep
//! their own BVH, refuse the frame instead of culling wrongly.

use glam::{Mat4, Vec3};
use hroc::bvh::Bvh;
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Gpu;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const FRAMES: usize = 20;
const MOVING: [&str; 8] = ["vfc", "roc", "roc-all", "ioc", "hzb", "hroc", "hroc-na", "hroc-cr"];

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
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
    let mut views: Vec<hroc::View> = MOVING.iter().map(|m| s.create(m).unwrap()).collect();
    let mut chc = s.create("chc++").unwrap();
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
