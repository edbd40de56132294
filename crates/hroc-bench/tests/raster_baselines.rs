//! Raster and image-space baselines on lavapipe: roc, roc-all, ioc and hzb
//! conservative against noc on every scene's path, RC' and the hard paths;
//! woc runs and reports what it misses; the GPU passes against their CPU
//! references (Hi-Z pyramid on non-power-of-two sizes, the Hi-Z object
//! test, IOC's level queues).

use hroc::testing::cull::hzb::{cpu as hzb_cpu, Hzb, Pyramid};
use hroc::testing::cull::ioc::{cpu as ioc_cpu, Ioc};
use hroc_bench::bench::{self, BenchOptions, Session};
use hroc_bench::bvh::{Bvh, Split};
use hroc_bench::gpu::Headless;
use hroc_bench::scene::{paths, Aabb};
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const CONSERVATIVE: [&str; 4] = ["roc", "roc-all", "ioc", "hzb"];

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

/// Runs the conservative methods and woc side by side over the session's
/// path: every frame of the conservative ones must have 0 false negatives
/// and 0 missing pixels. Returns woc's (false negatives, missing pixels).
fn assert_conservative(s: &mut Session, label: &str) -> (usize, usize) {
    let mut cullers: Vec<hroc::View> = CONSERVATIVE.iter().chain(&["woc"]).map(|m| s.create(m.parse().unwrap()).unwrap()).collect();
    let mut woc = (0, 0);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        for c in cullers.iter_mut() {
            let r = s.run_frame(c, k).unwrap();
            let chk = s.check(&r, &truth).unwrap();
            if c.method() == hroc::Method::Woc {
                woc.0 += chk.false_negatives;
                woc.1 += chk.missing_pixels;
                continue;
            }
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "{label} {}: frame {k} missed objects/pixels, camera {:?}", c.method(), s.cameras[k]);
        }
    }
    woc
}

#[test]
fn conservative_on_every_scene_path() {
    for key in hroc_bench::scene::generators::keys() {
        let scene = hroc_bench::scene::load(key, Some(1000), 3).unwrap();
        let mut s = Session::new(gpu(), scene, None, 10, RES, Split::Sah).unwrap();
        let (fneg, missing) = assert_conservative(&mut s, key);
        eprintln!("{key}: woc missed {fneg} objects, {missing} pixels over 10 frames");
    }
}

#[test]
fn conservative_on_hard_paths() {
    // Cuts, eye inside object and group boxes, boxes across the near plane.
    for key in ["radial-city", "factory", "satellites", "library"] {
        let scene = hroc_bench::scene::load(key, Some(1500), 5).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 20, RES, Split::Sah).unwrap();
        assert_conservative(&mut s, key);
    }
    let scene = hroc_bench::scene::load("radial-city-fast", Some(1500), 1).unwrap();
    let mut s = Session::new(gpu(), scene, None, 16, RES, Split::Sah).unwrap();
    assert_conservative(&mut s, "radial-city-fast");
}

#[test]
fn ioc_conservative_over_depth_ranges() {
    // The root alone, a start deeper than any leaf (every leaf is in the
    // start queue), start = bottom, and a wide range.
    let scene = hroc_bench::scene::load("satellites", Some(1200), 2).unwrap();
    let path = paths::hard_path(&scene);
    let mut s = Session::new(gpu(), scene, Some(path), 12, RES, Split::Mid).unwrap();
    let depth = s.bvh().depth();
    for range in [(0, 0), (0, 3), (3, 3), (depth + 2, depth + 4), (2, depth)] {
        s.options.ioc_range = Some(range);
        let mut view = s.create("ioc".parse().unwrap()).unwrap();
        for k in 0..s.cameras.len() {
            let (_, truth) = s.truth(k).unwrap();
            let r = s.run_frame(&mut view, k).unwrap();
            let chk = s.check(&r, &truth).unwrap();
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "ioc {range:?}: frame {k}");
        }
    }
}

#[test]
fn ioc_start_queue_is_a_cut() {
    let scene = hroc_bench::scene::load("factory", Some(900), 4).unwrap();
    let boxes: Vec<Aabb> = scene.objects.iter().map(|o| o.bounds).collect();
    for split in [Split::Sah, Split::Mid, Split::Eq] {
        let bvh = Bvh::build(&boxes, split);
        let depth = bvh.depth();
        for start in [0, 1, depth / 2, depth, depth + 1] {
            let q = ioc_cpu::start_queue(&bvh, start);
            let mut in_q = vec![false; bvh.nodes.len()];
            for &n in &q {
                in_q[n as usize] = true;
            }
            for o in 0..boxes.len() {
                let mut n = bvh.leaf_of_object[o];
                let mut hits = in_q[n as usize] as u32;
                while let Some(p) = bvh.parent(n) {
                    n = p;
                    hits += in_q[n as usize] as u32;
                }
                assert_eq!(hits, 1, "{split} start {start}: object {o} under {hits} start nodes");
            }
        }
        // Leaf ranges: each node's range holds exactly the objects below it.
        let (order, ranges) = ioc_cpu::leaf_ranges(&bvh);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..boxes.len() as u32).collect::<Vec<_>>());
        for n in 0..bvh.nodes.len() as u32 {
            let [first, count] = ranges[n as usize];
            let mut below = Vec::new();
            let mut stack = vec![n];
            while let Some(m) = stack.pop() {
                match bvh.children(m) {
                    Some([l, r]) => stack.extend([l, r]),
                    None => below.push(bvh.object(m).unwrap()),
                }
            }
            below.sort_unstable();
            let mut got = order[first as usize..(first + count) as usize].to_vec();
            got.sort_unstable();
            assert_eq!(got, below, "node {n}");
        }
    }
}

#[test]
fn ioc_level_queues_match_cpu_reference() {
    for (key, range) in [("radial-city", None), ("satellites", Some((2, 6)))] {
        let scene = hroc_bench::scene::load(key, Some(1500), 9).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 10, RES, Split::Sah).unwrap();
        s.options.ioc_range = range;
        // V is read before each frame: a detected cut would clear it inside the frame.
        (s.options.cut_turn_deg, s.options.cut_move) = (f32::INFINITY, f32::INFINITY);
        let mut view = s.create("ioc".parse().unwrap()).unwrap();
        view.method_state_mut::<Ioc>().unwrap().set_debug(true);
        let (start, bottom) = ioc(&view).range();
        let mut deeper = 0;
        for k in 0..s.cameras.len() {
            let (v, _) = ioc(&view).sets(&core_gpu(s.gpu)).unwrap();
            s.run_frame(&mut view, k).unwrap();
            let marks = ioc(&view).node_marks(&core_gpu(s.gpu)).unwrap();
            let (_, fresh) = ioc(&view).sets(&core_gpu(s.gpu)).unwrap();
            let passed = |n: u32| {
                let m = marks[n as usize];
                m & 4 != 0 || (m & 2 != 0 && m & 1 != 0)
            };
            let cpu = ioc_cpu::levels(s.bvh(), start, bottom, passed);
            assert_eq!(cpu.queues.len(), ioc(&view).debug_queues().len(), "{key} frame {k}: levels");
            for (l, (c, g)) in cpu.queues.iter().zip(ioc(&view).debug_queues()).enumerate() {
                assert_eq!(c, g, "{key} frame {k}: queue of level {}", start as usize + l);
            }
            let want: Vec<bool> = cpu.visible.iter().zip(&v).map(|(&vis, &in_v)| vis && !in_v).collect();
            assert_eq!(want, fresh, "{key} frame {k}: objects drawn after the test");
            // A read-back after every level but the bottom one.
            let (reads, levels) = (ioc(&view).counts().readbacks as usize, ioc(&view).debug_queues().len());
            assert!(reads + 1 == levels || (reads == levels && levels <= (bottom - start) as usize), "{key} frame {k}: {reads} read-backs, {levels} levels");
            deeper += (ioc(&view).debug_queues().len() > 1) as u32;
        }
        assert!(deeper > 0, "{key}: no frame went below the start level");
    }
}

/// Level 0 of the pyramid at texel (x, y) of level l covers pixel p iff
/// min(p >> l, size - 1) is that texel: every texel must hold at least the
/// depth of every pixel it covers, and the top must be the maximum.
fn assert_footprints_covered(depth: &[f32], w: u32, h: u32, hiz: &[f32]) {
    let mips = hzb_cpu::mip_chain(w, h);
    assert_eq!((mips[0].width, mips[0].height), (w, h));
    let top = mips.last().unwrap();
    assert_eq!((top.width, top.height), (1, 1));
    for m in &mips {
        let l = mips.iter().position(|x| x == m).unwrap();
        for y in 0..h {
            for x in 0..w {
                let (tx, ty) = ((x >> l).min(m.width - 1), (y >> l).min(m.height - 1));
                let t = hiz[(m.offset + ty * m.width + tx) as usize];
                assert!(t >= depth[(y * w + x) as usize], "{w}x{h} level {l}: texel ({tx}, {ty}) {t} below pixel ({x}, {y})");
            }
        }
    }
    let max = depth.iter().copied().fold(0.0f32, f32::max);
    assert_eq!(hiz[top.offset as usize], max);
}

#[test]
fn hi_z_pyramid_matches_cpu_on_npot_sizes() {
    let gpu = gpu();
    // Odd sides at various levels, one side of 1, a power of two, and one
    // large enough that level 2 is reduced by its own dispatch.
    for (w, h) in [(160, 96), (37, 23), (1, 7), (64, 64), (701, 403)] {
        let scene = hroc_bench::scene::load("figures", Some(600), 1).unwrap();
        let mut s = Session::new(gpu, scene, None, 3, (w, h), Split::Sah).unwrap();
        let pyramid = Pyramid::new(&core_gpu(gpu), &s.renderer.targets.depth_view, (w, h, 1), hroc::DepthRange::Standard);
        for k in 0..s.cameras.len() {
            let (_, truth) = s.truth(k).unwrap();
            let mut enc = gpu.encoder("pyramid");
            pyramid.record_from_depth(&mut enc, &hroc::testing::gpu::PassCount::NONE);
            gpu.queue.submit([enc.finish()]);
            let got = pyramid.read(&core_gpu(gpu)).unwrap();
            let want = hzb_cpu::build(&truth.depth, w, h);
            assert_eq!(got.len(), want.len());
            let diff = got.iter().zip(&want).filter(|(a, b)| a != b).count();
            assert_eq!(diff, 0, "{w}x{h} frame {k}: {diff} texels differ from the CPU max-reduction");
            assert_footprints_covered(&truth.depth, w, h, &want);
            // The reduction alone (WOC writes level 0 itself), over stale levels.
            if pyramid.mips.len() > 1 {
                let junk = vec![0.5f32; want.len() - pyramid.mips[1].offset as usize];
                gpu.queue.write_buffer(&pyramid.levels, pyramid.mips[1].offset as u64 * 4, bytemuck::cast_slice(&junk));
                let mut enc = gpu.encoder("pyramid");
                pyramid.record_reduce(&mut enc, &hroc::testing::gpu::PassCount::NONE);
                gpu.queue.submit([enc.finish()]);
                assert!(pyramid.read(&core_gpu(gpu)).unwrap() == want, "{w}x{h} frame {k}: reduction from level 0 differs");
            }
            assert!(truth.depth.iter().any(|&d| d < 1.0), "{w}x{h}: nothing drawn");
        }
    }
}

#[test]
fn hzb_object_test_matches_cpu_reference() {
    for (key, res) in [("radial-city", RES), ("figures", (37, 23)), ("factory", (97, 61))] {
        let scene = hroc_bench::scene::load(key, Some(1500), 6).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 12, res, Split::Sah).unwrap();
        let mut view = s.create("hzb".parse().unwrap()).unwrap();
        let boxes: Vec<Aabb> = s.scene.objects.iter().map(|o| o.bounds).collect();
        let (mut occluded, mut tested) = (0, 0);
        for k in 0..s.cameras.len() {
            s.run_frame(&mut view, k).unwrap();
            let hiz = hzb(&view).pyramid().read(&core_gpu(s.gpu)).unwrap();
            let mips = &hzb(&view).pyramid().mips;
            let gpu_vis = hzb(&view).test_result(&core_gpu(s.gpu)).unwrap();
            let u =
                s.view_desc(&s.cameras[k]).geometry().unwrap().uniform((s.renderer.targets.width, s.renderer.targets.height), s.renderer.object_count, s.bvh().nodes.len() as u32);
            for (o, b) in boxes.iter().enumerate() {
                let strict = hzb_cpu::test(mips, &hiz, &u, *b, -0.02, -2e-6);
                let loose = hzb_cpu::test(mips, &hiz, &u, *b, 0.02, 2e-6);
                if strict.visible() {
                    assert!(gpu_vis[o], "{key} frame {k}: object {o} culled, CPU says {strict:?}");
                }
                if gpu_vis[o] {
                    assert!(loose.visible(), "{key} frame {k}: object {o} kept, CPU says {loose:?}");
                }
                if let hzb_cpu::Outcome::Tested(v) = loose {
                    tested += 1;
                    occluded += !v as u32;
                }
            }
        }
        assert!(occluded > 0 && tested > 0, "{key}: the test never culled ({occluded} of {tested})");
    }
}

#[test]
fn bench_rows_carry_stats_and_woc_reports() {
    let methods = hroc_bench::bench::parse_methods("noc,roc,roc-all,ioc,hzb,woc").unwrap();
    let o = BenchOptions { frames: 8, resolution: RES, timestamps: true, ..BenchOptions::new("downtown", Some(1200), methods) };
    let report = bench::run(gpu(), &o).unwrap();
    let row = |m: &str| report.rows.iter().find(|r| r.method == m.parse().unwrap()).unwrap();
    for m in CONSERVATIVE {
        assert_eq!((row(m).false_negatives, row(m).missing_pixels), (0, 0), "{m}");
        assert!(row(m).c_over_n > 0.0, "{m} culled nothing");
        assert!(row(m).stats.contains_key(&hroc::stats::Stat::Readbacks), "{m}: {:?}", row(m).stats);
    }
    assert!(row("roc").stats[&hroc::stats::Stat::Boxes] > 0.0);
    assert!(row("roc-all").stats[&hroc::stats::Stat::Boxes] >= row("roc").stats[&hroc::stats::Stat::Boxes]);
    assert!(row("ioc").stats[&hroc::stats::Stat::NodesTested] > 0.0 && row("ioc").stats[&hroc::stats::Stat::Levels] >= 1.0);
    assert!(row("hzb").stats[&hroc::stats::Stat::Tested] > 0.0);
    // woc is not conservative: it runs, culls, and its misses are reported
    // as they are (whatever they are), never hidden.
    let w = row("woc");
    assert!(w.c_over_n > 0.0 && w.drawn_mean > 0.0);
    assert!(w.stats.contains_key(&hroc::stats::Stat::FarTexels), "{:?}", w.stats);
    eprintln!("woc: {} false negatives, {} missing pixels, C/R {:.3}", w.false_negatives, w.missing_pixels, w.c_over_r);
    let json = serde_json::to_string(&report).unwrap();
    assert!(json.contains("\"nodes_tested\""));
}

fn ioc(v: &hroc::View) -> &Ioc {
    v.method_state().expect("an ioc view")
}

fn hzb(v: &hroc::View) -> &Hzb {
    v.method_state().expect("an hzb view")
}

/// Depth at the precision limit: on radial-city's hard path sampled at 5
/// frames per path second, frame 2 looks at the city from 3 km, where a
/// kiosk's front stands one ulp of standard depth in front of the ground.
/// The Hi-Z test compares its box's depth, computed in the shader, with
/// the slack HROC's rays have (`DEPTH_SLACK`); without it, hzb culled the
/// kiosk (1 false negative, 1 missing pixel, on lavapipe and an H200).
#[test]
fn hzb_keeps_a_far_object_one_ulp_in_front() {
    let o = BenchOptions { fps: Some(5.0), camera_path: Some("hard".into()), ..BenchOptions::new("radial-city", Some(5000), vec![hroc::Method::Hzb]) };
    let (scene, path) = bench::load_inputs(&o).unwrap();
    let frames = bench::frame_count(&o, path.as_ref().unwrap()).unwrap();
    let mut s = Session::new(gpu(), scene, path, frames, (640, 360), Split::Sah).unwrap();
    let mut v = s.create(hroc::Method::Hzb).unwrap();
    for k in 0..=2 {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut v, k).unwrap();
        let c = s.check(&r, &truth).unwrap();
        assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "frame {k}");
    }
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
