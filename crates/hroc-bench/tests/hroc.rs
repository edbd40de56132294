//! HROC on lavapipe: every variant conservative against noc on every
//! scene's path, RC', and the hard paths; GPU passes against the CPU
//! references (group extraction, ray marking).

use hroc::testing::cull::hroc::{cpu, Hroc};
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use hroc_bench::scene::paths;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const VARIANTS: [&str; 7] = ["hroc-na", "hroc-cr", "hroc-of", "hroc-cr+of", "hroc", "hroc-sf", "hroc-sf+of"];

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

/// Runs every variant side by side over the session's path; every frame
/// must have 0 false negatives and 0 missing pixels. Returns drawn/visible.
fn assert_variants_conservative(s: &mut Session, label: &str) -> f64 {
    let mut cullers: Vec<hroc::View> = VARIANTS.iter().map(|v| s.create(v.parse().unwrap()).unwrap()).collect();
    let (mut drawn, mut visible) = (0usize, 0usize);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        visible += truth.visible.len();
        for c in cullers.iter_mut() {
            let r = s.run_frame(c, k).unwrap();
            let chk = s.check(&r, &truth).unwrap();
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "{label} {}: frame {k} missed objects/pixels, camera {:?}", c.method(), s.cameras[k]);
            drawn += chk.drawn;
        }
    }
    drawn as f64 / (visible.max(1) * VARIANTS.len()) as f64
}

#[test]
fn conservative_on_every_scene_path() {
    for key in hroc_bench::scene::generators::keys() {
        let scene = hroc_bench::scene::load(key, Some(1200), 3).unwrap();
        let mut s = Session::new(gpu(), scene, None, 12, RES, Split::Sah).unwrap();
        assert_variants_conservative(&mut s, key);
    }
}

#[test]
fn conservative_on_hard_paths() {
    // Cuts, eye inside object and group boxes, boxes across the near plane.
    for key in ["radial-city", "factory", "satellites", "library"] {
        let scene = hroc_bench::scene::load(key, Some(2000), 5).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 30, RES, Split::Sah).unwrap();
        assert_variants_conservative(&mut s, key);
    }
}

#[test]
fn conservative_with_every_split_and_fast_rotation() {
    for split in [Split::Mid, Split::Eq] {
        let scene = hroc_bench::scene::load("radial-city-fast", Some(2500), 1).unwrap();
        let mut s = Session::new(gpu(), scene, None, 20, RES, split).unwrap();
        assert_variants_conservative(&mut s, "radial-city-fast");
    }
}

#[test]
fn culls_close_to_ref_with_occluder_filtering() {
    let scene = hroc_bench::scene::load("radial-city", Some(4000), 0).unwrap();
    let mut s = Session::new(gpu(), scene, None, 20, (320, 180), Split::Sah).unwrap();
    let mut h = s.create("hroc-of".parse().unwrap()).unwrap();
    let n = s.renderer.object_count as usize;
    let (mut culled, mut ref_culled) = (0, 0);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut h, k).unwrap();
        let chk = s.check(&r, &truth).unwrap();
        culled += n - chk.drawn;
        ref_culled += n - truth.visible.len();
    }
    let c_over_r = culled as f64 / ref_culled as f64;
    assert!(c_over_r > 0.9, "C/R {c_over_r}: HROC hardly culls");
}

/// One frame of hroc-na at camera `k`, then the occlusion map rebuilt from
/// its occluder list, for the CPU references.
fn frame_with_occlusion_map(s: &mut Session, h: &mut hroc::View, k: usize) -> Vec<f32> {
    s.run_frame(h, k).unwrap();
    let gpu = s.gpu;
    let mut enc = gpu.encoder("occlusion map");
    s.renderer.clear(&mut enc);
    let st = h.method_state::<Hroc>().unwrap();
    s.renderer.draw(&mut enc, &host_list(st.occluder_list()), None);
    s.renderer.draw(&mut enc, &host_list(st.refill_list()), None);
    gpu.queue.submit([enc.finish()]);
    s.read_depth().unwrap()
}

/// The oriented box the culler holds for every object.
fn oriented_boxes(s: &Session) -> Vec<Option<hroc::geometry::OrientedBox>> {
    (0..s.renderer.object_count).map(|o| s.culler.oriented(o)).collect()
}

#[test]
fn gpu_group_extraction_and_ray_marking_match_cpu_references() {
    // Test scales: the paper's per-pixel test, the default blocks of 2 × 2,
    // and 4 × 4 (which 160 × 96 is divided by).
    for ((key, n), test_scale) in [("radial-city", 1500), ("satellites", 1200), ("factory", 1500)].into_iter().zip([1, 2, 4]) {
        let scene = hroc_bench::scene::load(key, Some(n), 11).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 16, RES, Split::Sah).unwrap();
        s.options = hroc::MethodOptions { hroc_test_scale: test_scale, ..Default::default() };
        let mut h = s.create("hroc-na".parse().unwrap()).unwrap();
        assert_eq!(h.method_state::<Hroc>().unwrap().test_scale(), test_scale);
        let aspect = s.renderer.aspect();
        for k in 0..s.cameras.len() {
            let depth = frame_with_occlusion_map(&mut s, &mut h, k);
            let dbg = h.method_state::<Hroc>().unwrap().debug_state(&core_gpu(s.gpu)).unwrap();
            let cam = s.cameras[k];
            // Group extraction: node states and groups exactly as Algorithm 1.
            let state = cpu::node_states(s.bvh(), &dbg.occluders);
            assert_eq!(state, dbg.state, "{key} frame {k}: node states differ");
            // The CPU references take the view as the culler derives it.
            let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(aspect), unclipped_depth: false }.geometry().unwrap();
            let (vp, rays) = (g.view_proj, g.ray_dirs);
            let pixel = cpu::pixel_angle_xy(&g, RES);
            let scale = h.method_state::<Hroc>().unwrap().test_scale();
            let (groups, forced) = cpu::groups(s.bvh(), &state, &g, pixel, scale);
            let obb = oriented_boxes(&s);
            assert_eq!(groups, dbg.groups, "{key} frame {k}: groups differ");
            // Ray marking: everything a slightly shrunk box test per pixel
            // finds must be marked, whatever the test's blocks; nothing
            // outside a generous test of the GPU's blocks may be.
            let strict = cpu::ray_marked(s.bvh(), &groups, &vp, &rays, &g.ray_origins, g.eye, RES, &depth, 1, None, -1e-3, -1e-6, &obb);
            let loose = cpu::ray_marked(s.bvh(), &groups, &vp, &rays, &g.ray_origins, g.eye, RES, &depth, scale, Some(pixel), 0.01, 1e-5, &obb);
            for o in 0..dbg.occludees.len() {
                let forced_o = forced.binary_search(&(o as u32)).is_ok();
                if strict[o] || forced_o {
                    assert!(dbg.occludees[o], "{key} frame {k}: object {o} should be an occludee");
                }
                if dbg.occludees[o] {
                    assert!(loose[o] || forced_o, "{key} frame {k}: object {o} marked without a ray reaching it");
                }
            }
        }
    }
}

#[test]
fn conservative_with_occludee_rounds() {
    // Every variant in front-to-back rounds, with the per-pixel test and on
    // blocks, along the hard paths; rounds draw fewer objects than one.
    for ((key, rounds), scale) in [("factory", 3), ("satellites", 2), ("radial-city", 4)].into_iter().zip([2, 1, 2]) {
        let scene = hroc_bench::scene::load(key, Some(2000), 5).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 30, RES, Split::Sah).unwrap();
        s.options = hroc::MethodOptions { hroc_test_scale: scale, ..Default::default() };
        let one = assert_variants_conservative(&mut s, key);
        s.options.hroc_rounds = rounds;
        let more = assert_variants_conservative(&mut s, key);
        assert!(more < one, "{key}: {rounds} rounds drew {more:.3} × the visible objects, one round {one:.3}");
    }
}

#[test]
fn conservative_with_occluder_rounds_and_oriented_boxes() {
    // V drawn front to back, with and without occludee rounds, per pixel
    // and on blocks, along the hard paths: every variant stays exact, and
    // on the scenes of rotated props the oriented boxes and the occluder
    // round each draw fewer objects.
    for (key, scale) in [("satellites", 1), ("factory", 2), ("radial-city", 2)] {
        let scene = hroc_bench::scene::load(key, Some(2000), 5).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 30, RES, Split::Sah).unwrap();
        let has_oriented = oriented_boxes(&s).iter().any(Option::is_some);
        assert!(has_oriented || key == "radial-city", "{key}: its rotated props get oriented boxes");
        s.options = hroc::MethodOptions { hroc_test_scale: scale, hroc_rounds: 2, ..Default::default() };
        let boxes = assert_variants_conservative(&mut s, key);
        s.options.hroc_occluder_rounds = true;
        let v_rounds = assert_variants_conservative(&mut s, key);
        s.options.hroc_rounds = 1;
        assert_variants_conservative(&mut s, key);
        s.options = hroc::MethodOptions { hroc_test_scale: scale, hroc_rounds: 2, ..Default::default() };
        s.set_oriented_boxes(false).unwrap();
        let world = assert_variants_conservative(&mut s, key);
        eprintln!("{key}: drawn/visible {world:.3} world boxes, {boxes:.3} oriented, {v_rounds:.3} with occluder rounds");
        if has_oriented {
            assert!(boxes < world, "{key}: oriented boxes drew {boxes:.3} × the visible objects, world boxes {world:.3}");
        }
        assert!(v_rounds < boxes, "{key}: the occluder round drew {v_rounds:.3} × the visible objects, without {boxes:.3}");
    }
}

#[test]
fn gpu_late_test_matches_cpu_reference() {
    // Round 0's late test re-tests U's objects not drawn in front, alone,
    // against the depth V and the front list left: everything a shrunk
    // per-pixel box test finds must go on, nothing a generous test of the
    // GPU's blocks rejects may.
    for ((key, n), scale) in [("factory", 1500), ("radial-city", 1500), ("satellites", 1200)].into_iter().zip([1, 2, 2]) {
        let scene = hroc_bench::scene::load(key, Some(n), 11).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 16, RES, Split::Sah).unwrap();
        s.options = hroc::MethodOptions { hroc_test_scale: scale, hroc_rounds: 2, ..Default::default() };
        let mut h = s.create("hroc-na".parse().unwrap()).unwrap();
        let aspect = s.renderer.aspect();
        let (mut fronts, mut retested) = (0, 0);
        for k in 0..s.cameras.len() {
            s.run_frame(&mut h, k).unwrap();
            let st = h.method_state::<Hroc>().unwrap();
            let u = st.debug_state(&core_gpu(s.gpu)).unwrap().occludees;
            let (front, next) = st.round_marks(&core_gpu(s.gpu), 0).unwrap().unwrap();
            let mut enc = s.gpu.encoder("late test depth");
            s.renderer.clear(&mut enc);
            s.renderer.draw(&mut enc, &host_list(st.occluder_list()), None);
            s.renderer.draw(&mut enc, &host_list(st.refill_list()), None);
            s.renderer.draw(&mut enc, &host_list(st.front_list(0).unwrap()), None);
            s.gpu.queue.submit([enc.finish()]);
            let depth = s.read_depth().unwrap();
            let cam = s.cameras[k];
            let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(aspect), unclipped_depth: false }.geometry().unwrap();
            let pixel = cpu::pixel_angle_xy(&g, RES);
            let obb = oriented_boxes(&s);
            let rest: Vec<u32> = (0..u.len()).filter(|&o| u[o] && front[o] == 0).map(|o| s.bvh().leaf_of_object[o]).collect();
            let strict = cpu::ray_marked(s.bvh(), &rest, &g.view_proj, &g.ray_dirs, &g.ray_origins, g.eye, RES, &depth, 1, None, -1e-3, -1e-6, &obb);
            let loose = cpu::ray_marked(s.bvh(), &rest, &g.view_proj, &g.ray_dirs, &g.ray_origins, g.eye, RES, &depth, scale, Some(pixel), 0.01, 1e-5, &obb);
            for o in 0..u.len() {
                assert!(front[o] <= 1 && (front[o] == 0 || u[o]), "{key} frame {k}: object {o} drawn in front but not in U");
                assert!(!strict[o] || next[o], "{key} frame {k}: object {o} is in front of the depth but left the rounds");
                assert!(!next[o] || loose[o], "{key} frame {k}: object {o} went on without a box in front of the depth");
            }
            fronts += front.iter().filter(|&&f| f != 0).count();
            retested += rest.len();
        }
        assert!(fronts > 0 && retested > 0, "{key}: the rounds drew {fronts} in front and re-tested {retested}");
    }
}

#[test]
fn box_winding_faces_outward() {
    // hroc_test.wgsl's CUBE table: counter-clockwise from outside, so the
    // rasterizer's back-face culling keeps exactly the near faces.
    let src = hroc::testing::shaders::source("hroc_test.wgsl");
    let table = &src[src.find("array<u32, 36>(").unwrap() + 15..];
    let idx: Vec<u32> = table[..table.find(");").unwrap()].split(|c: char| !c.is_ascii_digit()).filter(|t| !t.is_empty()).map(|t| t.parse().unwrap()).collect();
    assert_eq!(idx.len(), 36);
    let corner = |c: u32| glam::Vec3::new((c & 1) as f32, ((c >> 1) & 1) as f32, ((c >> 2) & 1) as f32);
    for t in idx.chunks(3) {
        let (a, b, c) = (corner(t[0]), corner(t[1]), corner(t[2]));
        let normal = (b - a).cross(c - a);
        let outward = (a + b + c) / 3.0 - glam::Vec3::splat(0.5);
        assert!(normal.dot(outward) > 0.0, "triangle {t:?} winds inward");
    }
}

/// The incoherent paths (`paths::cut_path`: a cut every second, 720°/s
/// turns, random eye heights) sampled at 2 frames per path second, where
/// every frame is detected as a cut: every variant stays conservative with
/// the ray-grid seed on cuts (the default), on every frame, and never.
#[test]
fn conservative_on_cut_paths_with_every_seed() {
    for key in ["radial-city", "factory", "satellites"] {
        let scene = hroc_bench::scene::load(key, Some(1500), 7).unwrap();
        let path = paths::cut_path(&scene, 3);
        let mut s = Session::new(gpu(), scene, Some(path), 21, RES, Split::Sah).unwrap();
        let mut drawn = Vec::new();
        for seed in [hroc::options::Seed::Cuts, hroc::options::Seed::Always, hroc::options::Seed::Never, hroc::options::Seed::CutsOnly] {
            // The seed alone: every frame culled by occlusion.
            s.options = hroc::MethodOptions { hroc_seed: seed, hroc_frustum_below: 0.0, ..Default::default() };
            let ratio = assert_variants_conservative(&mut s, &format!("{key} seed {seed:?}"));
            // Drawn over visible: every visible object is drawn.
            assert!(ratio >= 1.0, "{key} seed {seed:?}: {ratio}");
            drawn.push(ratio);
        }
        // Every frame is a cut: without the seed V is empty and the test
        // runs against an empty map, so the seeded runs draw fewer.
        assert!(drawn[0] < drawn[2] && drawn[1] < drawn[2], "{key}: drawn/visible with the seed on cuts, always, never: {drawn:?}");
    }
}

/// The seed pass against its CPU reference: after a signalled cut, V is
/// exactly the objects whose boxes the grid's rays enter first.
#[test]
fn gpu_seed_matches_cpu_reference() {
    for (key, n) in [("radial-city", 1500), ("factory", 1500), ("satellites", 1200)] {
        let scene = hroc_bench::scene::load(key, Some(n), 2).unwrap();
        let path = paths::cut_path(&scene, 5);
        let mut s = Session::new(gpu(), scene, Some(path), 12, RES, Split::Sah).unwrap();
        let mut h = s.create("hroc-na".parse().unwrap()).unwrap();
        let aspect = s.renderer.aspect();
        let mut seeded = 0;
        for k in 0..s.cameras.len() {
            s.run_frame_cut(&mut h, k, true).unwrap();
            let list = h.method_state::<Hroc>().unwrap().occluder_list().clone();
            let mut gpu_v: Vec<u32> = s.gpu.read_list(&list.commands, &list.count, list.max_count).unwrap().iter().map(|c| c.first_instance).collect();
            gpu_v.sort_unstable();
            let cam = s.cameras[k];
            let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(aspect), unclipped_depth: false }.geometry().unwrap();
            let cpu_v = cpu::seed(s.bvh(), &g.ray_dirs, &g.ray_origins, hroc::testing::cull::hroc::seed_grid(RES));
            // Ties between boxes entered at the same distance may round either way.
            let differ = gpu_v.iter().filter(|o| cpu_v.binary_search(o).is_err()).count() + cpu_v.iter().filter(|o| gpu_v.binary_search(o).is_err()).count();
            assert!(differ * 50 <= cpu_v.len().max(1), "{key} frame {k}: GPU seed {} objects, CPU {}, {differ} differ", gpu_v.len(), cpu_v.len());
            seeded += gpu_v.len();
        }
        assert!(seeded > 0, "{key}: the seed found nothing");
    }
}

/// The refill of V's holes against its CPU reference: on every frame not
/// seeded, the objects it drew are the first hits of the grid's cells that
/// V's depth left at the far plane and last frame's depth did not, less V.
#[test]
fn gpu_refill_matches_cpu_reference() {
    let mut refilled = 0;
    for (key, n) in [("radial-city", 1500), ("houses", 1500), ("satellites", 1200)] {
        let scene = hroc_bench::scene::load(key, Some(n), 2).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 16, RES, Split::Sah).unwrap();
        let mut h = s.create("hroc-na".parse().unwrap()).unwrap();
        let aspect = s.renderer.aspect();
        let mut last = vec![1.0f32; (RES.0 * RES.1) as usize];
        for k in 0..s.cameras.len() {
            s.run_frame(&mut h, k).unwrap();
            let seeded = h.stats(&s.culler).unwrap().iter().any(|x| x.0 == hroc::stats::Stat::Seeded && x.1 > 0.0);
            let final_depth = s.read_depth().unwrap();
            let st = h.method_state::<Hroc>().unwrap();
            let read = |l: &hroc::testing::cull::DrawList| -> Vec<u32> { s.gpu.read_list(&l.commands, &l.count, l.max_count).unwrap().iter().map(|c| c.first_instance).collect() };
            let (v, mut gpu_refill) = (read(st.occluder_list()), read(st.refill_list()));
            gpu_refill.sort_unstable();
            let mut enc = s.gpu.encoder("V's depth");
            s.renderer.clear(&mut enc);
            s.renderer.draw(&mut enc, &host_list(st.occluder_list()), None);
            s.gpu.queue.submit([enc.finish()]);
            let v_depth = s.read_depth().unwrap();
            if !seeded {
                let mut in_v = vec![false; s.renderer.object_count as usize];
                v.iter().for_each(|&o| in_v[o as usize] = true);
                let cam = s.cameras[k];
                let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(aspect), unclipped_depth: false }.geometry().unwrap();
                let cpu_refill = cpu::refill(s.bvh(), &g.ray_dirs, &g.ray_origins, hroc::testing::cull::hroc::seed_grid(RES), RES, &v_depth, &last, &in_v);
                // Ties between boxes entered at the same distance may round either way.
                let differ =
                    gpu_refill.iter().filter(|o| cpu_refill.binary_search(o).is_err()).count() + cpu_refill.iter().filter(|o| gpu_refill.binary_search(o).is_err()).count();
                assert!(differ * 20 <= cpu_refill.len().max(1), "{key} frame {k}: GPU refill {gpu_refill:?}, CPU {cpu_refill:?}");
                refilled += gpu_refill.len();
            } else {
                assert!(gpu_refill.is_empty(), "{key} frame {k}: a seeded frame refilled");
            }
            last = final_depth;
        }
    }
    assert!(refilled > 0, "no frame refilled V");
}

/// Cut detection: a frame that turns past `cut_turn_deg` or moves past
/// `cut_move` of the scene is culled as after a cut (the `cut` statistic),
/// one that does not is not, and infinite thresholds turn it off.
#[test]
fn cuts_are_detected_from_the_view() {
    let scene = hroc_bench::scene::load("radial-city", Some(1200), 1).unwrap();
    let path = paths::cut_path(&scene, 9);
    let mut s = Session::new(gpu(), scene, Some(path), 81, RES, Split::Sah).unwrap();
    let cut_of = |s: &mut Session, v: &mut hroc::View, k: usize| -> f64 {
        s.run_frame(v, k).unwrap();
        v.stats(&s.culler).unwrap().iter().find(|x| x.0 == hroc::stats::Stat::Cut).unwrap().1
    };
    let mut h = s.create("hroc".parse().unwrap()).unwrap();
    // 8 frames per path second: 90° turns within the even seconds, small
    // steps within the odd ones, a new eye at every second.
    let diagonal = s.bvh().aabb(0).extent().length();
    let (mut cuts, mut steps) = (0, 0);
    for k in 0..s.cameras.len() {
        let expect = k > 0 && {
            let (a, b) = (s.cameras[k - 1], s.cameras[k]);
            let turn = (a.target - a.eye).normalize().dot((b.target - b.eye).normalize()).clamp(-1.0, 1.0).acos().to_degrees();
            turn > 45.0 || a.eye.distance(b.eye) > 0.1 * diagonal
        };
        assert_eq!(cut_of(&mut s, &mut h, k), if expect { 1.0 } else { 0.0 }, "frame {k}");
        (cuts, steps) = (cuts + expect as usize, steps + !expect as usize);
    }
    assert!(cuts >= 40 && steps >= 30, "{cuts} cuts, {steps} steps");
    s.options = hroc::MethodOptions { cut_turn_deg: f32::INFINITY, cut_move: f32::INFINITY, ..Default::default() };
    let mut off = s.create("hroc".parse().unwrap()).unwrap();
    for k in 0..20 {
        assert_eq!(cut_of(&mut s, &mut off, k), 0.0, "frame {k} with detection off");
    }
}

/// Stall-free counters: on a cut path the counts outgrow the estimates
/// taken from earlier frames; the overflow draws take the rest, so hroc-sf
/// draws exactly what hroc-na draws, with 0 false negatives.
#[test]
fn stall_free_overflow_draws_what_the_estimate_misses() {
    // Every list above the 4,096 commands under which SF draws to the capacity.
    let scene = hroc_bench::scene::load("radial-city", Some(4500), 4).unwrap();
    let path = paths::cut_path(&scene, 2);
    let mut s = Session::new(gpu(), scene, Some(path), 31, RES, Split::Sah).unwrap();
    let mut sf = s.create("hroc-sf".parse().unwrap()).unwrap();
    let mut na = s.create("hroc-na".parse().unwrap()).unwrap();
    let mut overflowed = 0;
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut sf, k).unwrap();
        let c_sf = s.check(&r, &truth).unwrap();
        assert_eq!((c_sf.false_negatives, c_sf.missing_pixels), (0, 0), "frame {k}");
        let h = sf.method_state::<Hroc>().unwrap();
        let (est, c) = (h.estimates().unwrap(), h.set_sizes(&core_gpu(s.gpu)).unwrap());
        overflowed += (c.v > est[0]) as usize + (c.g > est[1]) as usize + (c.u > est[2]) as usize;
        let r = s.run_frame(&mut na, k).unwrap();
        let c_na = s.check(&r, &truth).unwrap();
        assert_eq!(c_sf.drawn, c_na.drawn, "frame {k}: hroc-sf and hroc-na differ");
    }
    assert!(overflowed > 0, "no count passed its estimate: the overflow draw was never exercised");
}

/// Work counters: hroc-cr+of (counter read-back) submits and waits three times a
/// frame, reading 4 bytes each time; hroc-na never waits and reads only
/// its gate's tallies; hroc (sf+of) never
/// waits either, yet its counts arrive (bytes read without a wait): |V|,
/// |G| and |U|, 12 bytes a frame's counts, and no more (no lists of rounds
/// it does not run), beside its gate's 28-byte tallies.
#[test]
fn work_counters_count_submits_waits_and_bytes() {
    // Every list above the 4,096 commands under which SF draws to the capacity.
    let scene = hroc_bench::scene::load("radial-city", Some(4500), 3).unwrap();
    let mut s = Session::new(gpu(), scene, None, 8, RES, Split::Sah).unwrap();
    for (m, waits) in [("hroc-cr+of", 3.0), ("hroc-na", 0.0), ("hroc", 0.0)] {
        let mut v = s.create(m.parse().unwrap()).unwrap();
        let mut bytes = 0.0;
        for k in 0..s.cameras.len() {
            s.run_frame(&mut v, k).unwrap();
            let st = v.stats(&s.culler).unwrap();
            let get = |w: hroc::stats::Stat| st.iter().find(|x| x.0 == w).unwrap().1;
            assert_eq!((get(hroc::stats::Stat::Waits), get(hroc::stats::Stat::Submits)), (waits, waits), "{m} frame {k}");
            // The gate's tallies (28 bytes each, one a probe) come back
            // without a wait too (`cull/hroc/gate.rs`).
            let read = get(hroc::stats::Stat::BytesRead) as u32;
            if waits > 0.0 {
                assert!(read >= 4 * waits as u32 && (read - 4 * waits as u32).is_multiple_of(28), "{m} frame {k}: {read} bytes");
            }
            if m == "hroc" {
                assert!((0..=read / 28).any(|t| (read - 28 * t).is_multiple_of(12)), "{m} frame {k}: {read} bytes, not whole frames of three counts and whole tallies");
            }
            bytes += get(hroc::stats::Stat::BytesRead);
        }
        // hroc-na reads only its gate's tallies.
        assert!(bytes > 0.0, "{m}: no bytes read");
        if m == "hroc-na" {
            assert_eq!(bytes % 28.0, 0.0, "{m}: {bytes} bytes read, not whole tallies");
        }
    }
}

/// Pipeline statistics: every stage's passes are counted under that stage.
/// vfc's frustum test runs one thread per object (rounded up to its 256-wide
/// workgroups), hroc-na's group extraction one to size its walk, one per
/// object of V (and of the refill), and one per candidate group and the
/// root: fewer than one per object and per node;
/// the host's draws, recorded with `Draw::record`, count vertices and
/// fragments; a view without statistics reports none.
#[test]
fn pipeline_statistics_count_every_stage() {
    use hroc::stats::Stage;
    use hroc::testing::gpu::Invocations;
    let gpu = gpu();
    // The tests' adapter (lavapipe) has pipeline-statistics queries.
    assert!(gpu.device.features().contains(hroc::device::PIPELINE_STATISTICS_FEATURES), "{} has no pipeline-statistics queries", gpu.adapter_name());
    let scene = hroc_bench::scene::load("radial-city", Some(1200), 3).unwrap();
    let mut s = Session::new(gpu, scene, None, 4, RES, Split::Sah).unwrap();
    let threads = |n: u32| n.div_ceil(256) as u64 * 256;
    let (n, nodes) = (s.renderer.object_count, s.bvh().nodes.len() as u32);
    let get = |r: &[(Stage, Invocations)], st: Stage| r.iter().find(|x| x.0 == st).map(|x| x.1).unwrap_or_else(|| panic!("no {st} in {r:?}"));
    for k in 0..s.cameras.len() {
        let mut vfc = s.create("vfc".parse().unwrap()).unwrap();
        let r = s.run_frame(&mut vfc, k).unwrap();
        assert_eq!(get(&r.invocations, Stage::FrustumCull).compute, threads(n), "frame {k}");
        let draw = get(&r.invocations, Stage::Draw);
        assert!(draw.vertex > 0 && draw.fragment > 0 && draw.compute == 0, "frame {k}: {draw:?}");
        // hroc-na: no stall-free overflow pass joins the extraction.
        let mut h = s.create("hroc-na".parse().unwrap()).unwrap();
        let r = s.run_frame(&mut h, k).unwrap();
        let ge = get(&r.invocations, Stage::GroupExtraction);
        let dbg = h.method_state::<Hroc>().unwrap().debug_state(&core_gpu(s.gpu)).unwrap();
        assert!(dbg.walked > 0 && dbg.candidates > 0, "frame {k}: {} walked, {} candidates", dbg.walked, dbg.candidates);
        // A view's first frame is seeded (no refill): a thread per object
        // for the walk and one per candidate (and the root's) for the
        // collection; wgpu checks the collection's indirect workgroups
        // with one thread of its own where the instance validates indirect
        // calls (its default).
        let own = threads(n) + threads(dbg.candidates + 1);
        assert!((ge.vertex, ge.fragment) == (0, 0) && [own, own + 1].contains(&ge.compute), "frame {k}: {ge:?}, {own} expected");
        assert!(ge.compute <= threads(n) + threads(nodes) + 3, "frame {k}: {ge:?}");
        // Stages are listed in stage order, each once.
        let stages: Vec<Stage> = r.invocations.iter().map(|x| x.0).collect();
        assert!(stages.windows(2).all(|w| w[0] < w[1]), "{stages:?}");
    }
    // Without timestamps the session counts nothing.
    let scene = hroc_bench::scene::load("radial-city", Some(300), 3).unwrap();
    let mut quiet = Session::with(gpu, scene, hroc_bench::bench::SessionDesc { timestamps: false, ..hroc_bench::bench::SessionDesc::new(2, RES) }).unwrap();
    let mut v = quiet.create("hroc".parse().unwrap()).unwrap();
    assert!(quiet.run_frame(&mut v, 0).unwrap().invocations.is_empty());
}

/// Clusters as objects: on scenes split into clusters of 64 triangles, on
/// their hard paths (cuts, the eye inside boxes, boxes across the near
/// plane), every variant stays conservative, and hroc culls inside meshes:
/// it draws fewer triangles than the unclustered scene's hroc.
#[test]
fn conservative_with_clusters() {
    for key in ["rooms", "factory"] {
        let whole = hroc_bench::scene::load(key, Some(300), 2).unwrap();
        let path = paths::hard_path(&whole);
        let clustered = whole.clone().clustered(hroc_bench::scene::ClusterOptions::new(64)).unwrap();
        assert!(clustered.objects.len() > whole.objects.len(), "{key}: nothing split");
        assert_eq!(clustered.stats().triangles, whole.stats().triangles, "{key}: triangles lost or doubled");
        let mut triangles = Vec::new();
        for scene in [whole, clustered] {
            let mut s = Session::new(gpu(), scene, Some(path.clone()), 24, RES, Split::Sah).unwrap();
            assert_variants_conservative(&mut s, key);
            let mut h = s.create("hroc".parse().unwrap()).unwrap();
            let mut t = 0u64;
            for k in 0..s.cameras.len() {
                let (_, truth) = s.truth(k).unwrap();
                let r = s.run_frame(&mut h, k).unwrap();
                t += s.check(&r, &truth).unwrap().triangles;
            }
            triangles.push(t);
        }
        assert!(triangles[1] < triangles[0], "{key}: clusters drew {} triangles, whole objects {}", triangles[1], triangles[0]);
    }
}

/// Occluder filtering (§4.2) with a stride: next frame's V is exactly the
/// objects of the ID target's sampled pixels (the centre of every S × S
/// square), and the variants stay conservative along the hard path.
#[test]
fn occluder_filtering_samples_every_stride() {
    let scene = hroc_bench::scene::load("radial-city", Some(1500), 4).unwrap();
    let path = paths::hard_path(&scene);
    for stride in [1u32, 3] {
        let mut s = Session::new(gpu(), scene.clone(), Some(path.clone()), 12, RES, Split::Sah).unwrap();
        s.options = hroc::MethodOptions { hroc_filter_stride: stride, ..Default::default() };
        let mut h = s.create("hroc-of".parse().unwrap()).unwrap();
        let (w, ht) = RES;
        let mut filtered_frames = 0;
        for k in 0..s.cameras.len() {
            s.run_frame(&mut h, k).unwrap();
            let ids = s.read_truth().unwrap().ids;
            let mut want = vec![false; s.renderer.object_count as usize];
            for y in (stride / 2..ht).step_by(stride as usize) {
                for x in (stride / 2..w).step_by(stride as usize) {
                    let id = ids[(y * w + x) as usize];
                    if id > 0 {
                        want[(id - 1) as usize] = true;
                    }
                }
            }
            let next = h.method_state::<Hroc>().unwrap().next_occluders(&core_gpu(s.gpu)).unwrap();
            // Where the view's filter gate merged instead (OF would have
            // kept most of O ∪ D), next V holds every object the filter keeps.
            let filtered = h.stats(&s.culler).unwrap().iter().any(|x| x.0 == hroc::stats::Stat::Filtered && x.1 > 0.0);
            if filtered {
                assert_eq!(next, want, "stride {stride} frame {k}");
                filtered_frames += 1;
            } else {
                assert!(want.iter().zip(&next).all(|(w, n)| !w || *n), "stride {stride} frame {k}: merged, yet an object the filter keeps is not in V");
            }
        }
        assert!(filtered_frames > 0, "stride {stride}: no frame filtered");
        if stride > 1 {
            assert_variants_conservative(&mut s, "radial-city, filter stride 3");
        }
    }
}

/// A list of the culler's internals as the renderer keeps lists.
fn host_list(l: &hroc::testing::cull::DrawList) -> hroc_bench::render::DrawList {
    hroc_bench::render::DrawList { commands: l.commands.clone(), count: l.count.clone(), max_count: l.max_count }
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
