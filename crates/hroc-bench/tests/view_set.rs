//! A frame's views culled as a set (`Culler::cull_views`,
//! `set_frustum.wgsl`), on lavapipe: a light's cascades packed by one pass
//! against the same views culled one by one (the GPU's lists against the
//! CPU's frustum test, and every frame against `noc`'s picture).

use hroc::Method;
use hroc_bench::bench::{Session, SessionDesc};
use hroc_bench::gpu::Headless;

/// Radial-city with 4 cascades; `validate`: the culler checks the host's draws.
fn session(gpu: &Headless, frames: usize, options: hroc::MethodOptions, validate: bool) -> Session<'_> {
    let scene = hroc_bench::scene::load("radial-city", Some(3000), 0).unwrap();
    let mut s = Session::with(gpu, scene, SessionDesc { validate, ..SessionDesc::new(frames, (320, 180)) }).unwrap();
    s.options = options;
    s.set_shadow_cascades(4).unwrap();
    s
}

/// The objects a list draws, in its order.
fn drawn(s: &Session, l: &hroc_bench::render::DrawList) -> Vec<u32> {
    s.gpu.read_list(&l.commands, &l.count, l.max_count).unwrap().iter().filter(|c| c.instance_count > 0).map(|c| c.first_instance).collect()
}

/// `vfc`'s cascades packed by the set's pass hand the lists each culled
/// alone hands, in the same order, which are the objects whose boxes the
/// CPU finds in each cascade's frustum; each frame draws every object the
/// cascade's `noc` picture shows, its tally counts what its list draws,
/// and the set records one pass and one dispatch per cascade where the
/// cascades alone record a pass, a compaction and a tally each.
#[test]
fn a_set_packs_the_lists_views_culled_alone_hand() {
    let gpu = Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let mut s = session(&gpu, 40, hroc::MethodOptions::default(), true);
    let cascades = s.cascade_count();
    let mut set: Vec<hroc::View> = (0..cascades).map(|c| s.create_cascade(Method::Vfc, c).unwrap()).collect();
    let mut alone: Vec<hroc::View> = (0..cascades).map(|c| s.create_cascade(Method::Vfc, c).unwrap()).collect();
    let boxes: Vec<hroc::Aabb> = s.scene.objects.iter().map(|o| o.bounds).collect();
    for k in 0..s.cameras.len() {
        let (fitted, time) = (s.cascades(k), s.times[k]);
        let truths = s.cascade_truths(&fitted, time).unwrap();
        let results = s.run_cascades(&mut set, &fitted, time).unwrap();
        let set_shape: u32 = set.iter().map(shape).sum();
        let mut alone_shape = 0;
        for (c, ((r, (_, truth)), cascade)) in results.iter().zip(&truths).zip(&fitted).enumerate() {
            let chk = s.check_cascade(c as u32, r, truth).unwrap();
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "frame {k}, cascade {c} in the set");
            let one = s.run_cascade(&mut alone[c], c as u32, cascade, time).unwrap();
            alone_shape += shape(&alone[c]);
            let (packed, own) = (drawn(&s, &r.lists[0]), drawn(&s, &one.lists[0]));
            assert_eq!(packed, own, "frame {k}, cascade {c}: the set's list and the list culled alone");
            let planes = cascade.view_desc().geometry().unwrap().planes;
            let inside: Vec<u32> = (0..boxes.len() as u32).filter(|&i| hroc::geometry::aabb_in_frustum(&planes, boxes[i as usize].min, boxes[i as usize].max)).collect();
            assert_eq!(packed, inside, "frame {k}, cascade {c}: the GPU's list and the CPU's frustum test");
        }
        // (A cut, where the cascades jump, culls each alone.)
        let cut = set.iter_mut().any(|v| v.stats(&s.culler).unwrap().iter().any(|x| x.0 == hroc::stats::Stat::Cut && x.1 > 0.0));
        assert!(cut || set_shape + 4 * (cascades - 1) <= alone_shape, "frame {k}: the set recorded {set_shape} passes and dispatches, the cascades alone {alone_shape}");
    }
    s.gpu.wait().unwrap();
    for (c, (v, a)) in set.iter_mut().zip(alone.iter_mut()).enumerate() {
        let (packed, own) = (v.frame_stats(&s.culler).unwrap(), a.frame_stats(&s.culler).unwrap());
        assert_eq!((packed.frame, packed.objects, packed.triangles), (own.frame, own.objects, own.triangles), "cascade {c}: the set's tally");
        assert!(packed.objects > 0);
    }
}

/// Passes plus dispatches of a view's last frame.
fn shape(v: &hroc::View) -> u32 {
    use hroc::stats::Stat::{ComputePasses, Dispatches, RenderPasses};
    v.shape_stats().iter().filter(|(s, _)| matches!(s, ComputePasses | RenderPasses | Dispatches)).map(|(_, x)| *x as u32).sum()
}

/// Frame `k` of `views` (one per cascade, as a set): every cascade draws
/// every object its `noc` picture shows; returns the pictures' truths.
fn conservative_frame(s: &mut Session, views: &mut [hroc::View], k: usize) -> Vec<hroc_bench::bench::Truth> {
    let (fitted, time) = (s.cascades(k), s.times[k]);
    let truths = s.cascade_truths(&fitted, time).unwrap();
    let results = s.run_cascades(views, &fitted, time).unwrap();
    for (c, (r, (_, truth))) in results.iter().zip(&truths).enumerate() {
        let chk = s.check_cascade(c as u32, r, truth).unwrap();
        assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "frame {k}, cascade {c}");
    }
    truths.into_iter().map(|(_, t)| t).collect()
}

/// HROC's cascades in a set: where its probes find that occlusion does
/// not pay (every cascade, with the bar at 1), the set packs their
/// frames, which draw every object `noc` shows; frames of probes run
/// HROC's own.
#[test]
fn hroc_views_that_cull_by_the_frustum_are_packed_by_the_set() {
    let gpu = Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let options = hroc::MethodOptions { hroc_frustum_below: 1.0, ..hroc::MethodOptions::default() };
    let mut s = session(&gpu, 60, options, false);
    let cascades = s.cascade_count();
    let mut views: Vec<hroc::View> = (0..cascades).map(|c| s.create_cascade(Method::HROC, c).unwrap()).collect();
    let mut packed_frames = 0;
    for k in 0..s.cameras.len() {
        conservative_frame(&mut s, &mut views, k);
        // A frame where every cascade culls by its frustum is one pass and a
        // dispatch each (without validation's passes).
        let total: u32 = views.iter().map(shape).sum();
        if total == 1 + cascades {
            packed_frames += 1;
        }
    }
    assert!(packed_frames >= s.cameras.len() / 2, "{packed_frames} of {} frames packed every cascade", s.cameras.len());
}

/// HROC's cascades marking from boxes (a host whose shaders cannot mark,
/// as Bevy's), where occlusion never pays (the bar at 1): the frame of the
/// frustum before each probe makes V the objects its depth shows, so each
/// probe after the first starts from V holding every object the previous
/// frame's `noc` picture shows, not from the V of the last probe; every
/// frame draws every object `noc` shows.
#[test]
fn frames_of_the_frustum_refresh_v_before_a_probe() {
    use hroc::device::{Capabilities, Marks};
    use hroc::testing::cull::hroc::Hroc;
    let gpu = Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let scene = hroc_bench::scene::load("radial-city", Some(3000), 0).unwrap();
    let capabilities = Some(Capabilities { marks: Marks::Boxes, ..Capabilities::FULL });
    let mut s = Session::with(&gpu, scene, SessionDesc { validate: false, capabilities, ..SessionDesc::new(70, (320, 180)) }).unwrap();
    s.options = hroc::MethodOptions { hroc_frustum_below: 1.0, ..hroc::MethodOptions::default() };
    s.set_shadow_cascades(4).unwrap();
    // HROC as a host without IDs runs it: no occluder filtering, so its
    // box marks come at the end of the frame.
    let hroc::Method::Hroc(v) = Method::HROC else { unreachable!() };
    let method = Method::Hroc(hroc::options::Variant { of: false, ..v });
    let cascades = s.cascade_count();
    let mut views: Vec<hroc::View> = (0..cascades).map(|c| s.create_cascade(method, c).unwrap()).collect();
    let core = hroc::testing::gpu::Gpu::from_device(&gpu.device, &gpu.queue);
    let mut last: Vec<Option<(bool, Vec<u32>)>> = vec![None; cascades as usize];
    let mut refreshed = 0;
    for k in 0..s.cameras.len() {
        let truths = conservative_frame(&mut s, &mut views, k);
        for (c, truth) in truths.iter().enumerate() {
            let stats = views[c].stats(&s.culler).unwrap();
            let occlusion = stats.iter().any(|&(st, x)| st == hroc::stats::Stat::Occlusion && x > 0.0);
            // A probe after a frame of the frustum: V (O, marks at the end) as the frame before left it.
            if let (true, Some((false, visible))) = (occlusion, &last[c]) {
                let v = views[c].method_state::<Hroc>().unwrap().debug_state(&core).unwrap().occluders;
                let missing: Vec<u32> = visible.iter().copied().filter(|&o| !v[o as usize]).collect();
                assert!(missing.is_empty(), "frame {k}, cascade {c}: the probe's V lacks {} objects the frame before showed: {missing:?}", missing.len());
                refreshed += 1;
            }
            last[c] = Some((occlusion, truth.visible.clone()));
        }
    }
    assert!(refreshed >= cascades as usize, "{refreshed} probes after frames of the frustum");
}
