//! `auto` on lavapipe: every frame is one candidate's whole frame, so it
//! is as conservative as they are, across switches too. Made to switch
//! every few frames, it has 0 false negatives and 0 missing pixels against
//! `noc` on every frame of the own, hard (the eye inside boxes, boxes
//! across the near plane) and cut paths of three scenes, with objects
//! moving, added and removed, and runs every candidate. Leaving a
//! building, HROC's refill keeps its worst frame below `hzb`'s.

use glam::{Mat4, Vec3};
use hroc::testing::cull::auto::{Auto, Params};
use hroc::Method;
use hroc_bench::bench::{self, BenchOptions, Session};
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use hroc_bench::scene::paths;
use std::collections::BTreeSet;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (scripts/ensure-vulkan.sh)"))
}

/// A switch every two or three frames: probes of every candidate, each
/// plausible, each stale after two frames.
fn restless() -> Params {
    Params { margin: 0.0, confirm: 1, dwell: 0, probe_every: 2, stale: 2, plausible: f64::INFINITY, forced: 4, cut_probe_every: 2, probe_share: 1.0, ..Params::default() }
}

#[test]
fn auto_switching_often_stays_conservative_on_every_path() {
    let mut ran = BTreeSet::new();
    for key in ["radial-city", "factory", "satellites"] {
        let scene = hroc_bench::scene::load(key, Some(1200), 3).unwrap();
        let hard = paths::hard_path(&scene);
        let cuts = paths::cut_path(&scene, 3);
        for (label, path) in [("own", None), ("hard", Some(hard)), ("cuts", Some(cuts))] {
            let mut s = Session::new(gpu(), scene.clone(), path, 16, RES, Split::Sah).unwrap();
            let mut v = s.create(Method::Auto).unwrap();
            v.method_state_mut::<Auto>().unwrap().chooser_mut().set_params(restless());
            for k in 0..s.cameras.len() {
                let (_, truth) = s.truth(k).unwrap();
                let r = s.run_frame(&mut v, k).unwrap();
                let c = s.check(&r, &truth).unwrap();
                assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{key} {label} frame {k}: auto ran {}", v.culled_by());
                ran.insert(v.culled_by().name());
            }
        }
    }
    assert_eq!(ran.into_iter().collect::<Vec<_>>(), ["hroc", "hzb", "noc", "vfc"], "auto ran every candidate");
}

#[test]
fn auto_follows_moving_added_and_removed_objects() {
    let scene = hroc_bench::scene::load("radial-city", Some(1500), 4).unwrap();
    let base: Vec<Mat4> = scene.objects.iter().map(|o| o.transform).collect();
    let mut s = Session::new(gpu(), scene, None, 20, RES, Split::Sah).unwrap();
    let mut v = s.create(Method::Auto).unwrap();
    v.method_state_mut::<Auto>().unwrap().chooser_mut().set_params(restless());
    let n = base.len();
    for k in 0..20 {
        // Every tenth object slides across the view; every fifth frame a
        // few leave the scene, and come back in front of the camera.
        let mut moves: Vec<(u32, Mat4)> =
            (0..n).step_by(10).map(|i| (i as u32, Mat4::from_translation(Vec3::new(10.0 * (k as f32 * 0.5 + i as f32).sin(), 0.0, 0.0)) * base[i])).collect();
        let gone: Vec<u32> = (7..n as u32).step_by(n / 5).take(4).collect();
        if k % 5 == 2 {
            s.remove_objects(&gone).unwrap();
        }
        if k % 5 == 4 {
            let cam = s.cameras[k];
            let ahead = cam.eye + (cam.target - cam.eye).normalize() * 10.0;
            let adds: Vec<(u32, Mat4)> = gone.iter().enumerate().map(|(j, &i)| (i, Mat4::from_translation(ahead + Vec3::X * (j as f32 * 2.0 - 3.0)))).collect();
            s.add_objects(&adds).unwrap();
        }
        moves.retain(|(i, _)| !gone.contains(i) || k % 5 == 4 || k % 5 < 2);
        s.move_objects(&moves).unwrap();
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut v, k).unwrap();
        let c = s.check(&r, &truth).unwrap();
        assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "frame {k}: auto ran {}", v.culled_by());
    }
}

/// The bench's `auto` row: shares of what it ran, 0 false negatives with
/// the default constants (its calibration switches among every plausible
/// candidate), with shadow cascades (a chooser per view) and 4× MSAA.
#[test]
fn auto_in_the_bench_with_views() {
    let methods = hroc_bench::bench::parse_methods("noc,vfc,hzb,hroc,auto").unwrap();
    for (cascades, msaa) in [(0, 1), (2, 1), (0, 4)] {
        let o = BenchOptions {
            frames: 24,
            resolution: (160, 90),
            shadow_cascades: cascades,
            msaa,
            camera_path: Some("hard".into()),
            ..BenchOptions::new("factory", Some(1500), methods.clone())
        };
        let r = bench::run(gpu(), &o).unwrap();
        for row in &r.rows {
            assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} with {cascades} cascades, {msaa}x MSAA", row.method);
        }
        let auto = r.rows.iter().find(|row| row.method == Method::Auto).unwrap();
        assert_eq!(auto.frame_methods.len(), r.frames);
        let share: f64 = auto.choices().iter().map(|c| c.1).sum();
        assert!((share - 1.0).abs() < 1e-9 && auto.choices().len() >= 2, "{:?}", auto.choices());
    }
}

/// The houses path enters two buildings and leaves them: with the refill
/// of V's holes, HROC's worst frame draws no more than hzb's worst, and
/// fewer than HROC seeding on cuts only.
#[test]
fn leaving_a_building_does_not_collapse_hroc() {
    let methods = hroc_bench::bench::parse_methods("hzb,hroc").unwrap();
    let run = |seed: hroc::options::Seed| {
        let o = BenchOptions {
            fps: Some(24.0),
            method_options: hroc::MethodOptions { hroc_seed: seed, ..Default::default() },
            ..BenchOptions::new("houses", Some(3000), methods.clone())
        };
        bench::run(gpu(), &o).unwrap()
    };
    let (refill, cuts_only) = (run(hroc::options::Seed::Cuts), run(hroc::options::Seed::CutsOnly));
    let most = |r: &bench::BenchReport, m: Method| r.rows.iter().find(|row| row.method == m).unwrap().drawn_max;
    for r in [&refill, &cuts_only] {
        assert!(r.rows.iter().all(|row| (row.false_negatives, row.missing_pixels) == (0, 0)));
    }
    assert!(most(&refill, Method::HROC) <= most(&refill, Method::Hzb), "hroc's worst frame {} against hzb's {}", most(&refill, Method::HROC), most(&refill, Method::Hzb));
    assert!(most(&refill, Method::HROC) < most(&cuts_only, Method::HROC), "refill {} against cuts only {}", most(&refill, Method::HROC), most(&cuts_only, Method::HROC));
}

/// A method taking over from another starts from the other's visible set
/// (`CullMethod::take_over`): `hzb` handed HROC's V holds it as its own
/// (the copy), draws fewer objects than an `hzb` starting from nothing
/// (which draws the frustum), and both stay conservative; HROC handed
/// `hzb`'s V does not seed, and is conservative too.
#[test]
fn a_method_taking_over_starts_from_the_visible_set_handed_over() {
    use hroc::testing::cull::hroc::Hroc;
    use hroc::testing::cull::hzb::Hzb;
    use hroc::testing::cull::CullMethod;
    let scene = hroc_bench::scene::load("radial-city", Some(2000), 5).unwrap();
    let mut s = Session::new(gpu(), scene, None, 12, RES, Split::Sah).unwrap();
    let (mut from_hroc, mut hzb_handed, mut hzb_cold) = (s.create(Method::HROC).unwrap(), s.create(Method::Hzb).unwrap(), s.create(Method::Hzb).unwrap());
    let frame = |s: &mut Session, v: &mut hroc::View, k: usize| {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(v, k).unwrap();
        let c = s.check(&r, &truth).unwrap();
        assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{} frame {k}", v.culled_by());
        c.drawn
    };
    for k in 0..6 {
        frame(&mut s, &mut from_hroc, k);
    }
    let set = from_hroc.method_state::<Hroc>().unwrap().visible_set().unwrap().clone();
    let mut enc = gpu().device.create_command_encoder(&Default::default());
    hzb_handed.method_state_mut::<Hzb>().unwrap().take_over(&mut enc, Some(&set));
    hzb_cold.method_state_mut::<Hzb>().unwrap().take_over(&mut enc, None);
    gpu().queue.submit([enc.finish()]);
    let handed: Vec<bool> = gpu().read::<u32>(&set, 0, s.scene.objects.len() as u64).unwrap().iter().map(|&x| x != 0).collect();
    assert_eq!(hzb_handed.method_state::<Hzb>().unwrap().test_result(&core_gpu(gpu())).unwrap(), handed, "hzb's V is HROC's");
    assert!(hzb_cold.method_state::<Hzb>().unwrap().test_result(&core_gpu(gpu())).unwrap().iter().all(|&v| !v), "a cold hzb starts from nothing");
    let (warm, cold) = (frame(&mut s, &mut hzb_handed, 6), frame(&mut s, &mut hzb_cold, 6));
    assert!(2 * warm < cold, "handed over: {warm} objects; from nothing: {cold}");
    // And back: HROC handed hzb's V.
    let set = hzb_handed.method_state::<Hzb>().unwrap().visible_set().unwrap().clone();
    let mut enc = gpu().device.create_command_encoder(&Default::default());
    from_hroc.method_state_mut::<Hroc>().unwrap().take_over(&mut enc, Some(&set));
    gpu().queue.submit([enc.finish()]);
    for k in 7..12 {
        frame(&mut s, &mut from_hroc, k);
        if k == 7 {
            let seeded = from_hroc.stats(&s.culler).unwrap().iter().find(|(st, _)| *st == hroc::stats::Stat::Seeded).map(|x| x.1);
            assert_eq!(seeded, Some(0.0), "HROC handed a visible set does not seed");
        }
    }
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
