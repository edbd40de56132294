//! The occlusion-query baselines (oq, soq, chc++) on lavapipe: conservative
//! against noc on every built-in path, RC' and the hard paths; CPU tests of
//! the traversal order, soq's statistics and CHC++'s multiqueries and
//! tighter bounds.

use glam::{Vec3, Vec4};
use hroc::testing::cull::queries::{box_distance, chc, front_to_back, oq, soq, Class, NodeView};
use hroc::testing::cull::MethodOptions;
use hroc_bench::bench::Session;
use hroc_bench::bvh::{Bvh, Split};
use hroc_bench::gpu::Headless;
use hroc_bench::scene::{paths, Aabb};
use std::collections::BTreeMap;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const METHODS: [&str; 3] = ["oq", "soq", "chc++"];

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

/// Runs the three methods side by side over the session's path: every frame
/// must have 0 false negatives and 0 missing pixels. Returns per method the
/// objects drawn and the sums of its statistics over the path.
fn assert_conservative(s: &mut Session, label: &str) -> Vec<(usize, BTreeMap<&'static str, f64>)> {
    let mut cullers: Vec<hroc::View> = METHODS.iter().map(|m| s.create(m.parse().unwrap()).unwrap()).collect();
    let mut out = vec![(0usize, BTreeMap::new()); METHODS.len()];
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        for (c, o) in cullers.iter_mut().zip(out.iter_mut()) {
            let r = s.run_frame(c, k).unwrap();
            let chk = s.check(&r, &truth).unwrap();
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "{label} {}: frame {k} missed objects/pixels, camera {:?}", c.method(), s.cameras[k]);
            let stats: BTreeMap<_, _> = c.stats(&s.culler).unwrap().into_iter().map(|(k, v)| (k.name(), v)).collect();
            for k in ["queries", "query_batches", "wait_ms"] {
                assert!(stats.contains_key(k), "{} reports no {k}", c.method());
            }
            assert!(stats["query_batches"] <= stats["queries"], "{label} {}: more read-backs than queries", c.method());
            o.0 += chk.drawn;
            for (k, v) in stats {
                *o.1.entry(k).or_default() += v;
            }
        }
    }
    out
}

#[test]
fn conservative_on_every_scene_path() {
    for key in hroc_bench::scene::generators::keys() {
        let scene = hroc_bench::scene::load(key, Some(800), 3).unwrap();
        let mut s = Session::new(gpu(), scene, None, 10, RES, Split::Sah).unwrap();
        let n = s.renderer.object_count as usize * s.cameras.len();
        let r = assert_conservative(&mut s, key);
        if key.starts_with("radial-city") {
            // A city street is occluded: every method culls something.
            for (m, (drawn, stats)) in METHODS.iter().zip(&r) {
                assert!(*drawn < n, "{key} {m}: drew everything");
                assert!(stats["queries"] > 0.0, "{key} {m}: no queries");
            }
        }
    }
}

#[test]
fn conservative_on_hard_paths() {
    // Cuts, eye inside object and group boxes, boxes across the near plane.
    for key in ["radial-city", "factory", "library"] {
        let scene = hroc_bench::scene::load(key, Some(800), 5).unwrap();
        let path = paths::hard_path(&scene);
        let mut s = Session::new(gpu(), scene, Some(path), 16, RES, Split::Sah).unwrap();
        assert_conservative(&mut s, key);
    }
}

#[test]
#[allow(clippy::needless_update)] // MethodOptions may grow
fn conservative_with_options_far_from_the_defaults() {
    // Long soq statistics, tiny CHC++ batches, re-queries every frame, no
    // tighter bounds / deep ones: still conservative.
    let scene = hroc_bench::scene::load("radial-city-fast", Some(800), 1).unwrap();
    let mut s = Session::new(gpu(), scene, None, 10, RES, Split::Sah).unwrap();
    s.options = MethodOptions { soq_base_time: 5.0, chc_batch: 3, chc_nav: 1, chc_dmax: 6, chc_smax: 3.0, ..MethodOptions::default() };
    let r = assert_conservative(&mut s, "radial-city-fast (options)");
    assert!(r[1].1["rendered_unqueried"] > 0.0, "soq never skipped a query: {:?}", r[1].1);
    assert!(r[2].1["multiqueries"] > 0.0, "chc++ never grouped queries: {:?}", r[2].1);
    s.options = MethodOptions { chc_dmax: 0, ..MethodOptions::default() };
    let mut c = s.create("chc++".parse().unwrap()).unwrap();
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut c, k).unwrap();
        assert_eq!(s.check(&r, &truth).unwrap().false_negatives, 0);
    }
}

#[test]
fn soq_not_query_time_and_actions() {
    let base = 2.0 / 3.0;
    assert_eq!(soq::not_query_time(base, 0), base);
    assert!((soq::not_query_time(base, 1) - base * 1.5).abs() < 1e-6);
    assert!((soq::not_query_time(base, 2) - base * 1.75).abs() < 1e-6);
    assert!((soq::not_query_time(base, 30) - 2.0 * base).abs() < 1e-6);
    for n in 0..8 {
        assert!(soq::not_query_time(base, n + 1) > soq::not_query_time(base, n));
    }

    use soq::{action, Action, History};
    let fresh = History::default();
    assert_eq!(action(Class::Outside, &fresh, 1, 0.0, base), Action::Skip);
    assert_eq!(action(Class::Near, &fresh, 1, 0.0, base), Action::Render);
    assert_eq!(action(Class::Testable, &fresh, 1, 0.0, base), Action::Query, "no statistics: query");
    // Visible once at t = 1, seen in frame 9; now frame 10.
    let mut h = History { last_seen: 9, ..History::default() };
    h.record(true, 1.0);
    assert_eq!(h.unoccluded(), 1);
    let limit = soq::not_query_time(base, 1); // 1.0
    assert_eq!(action(Class::Testable, &h, 10, 1.0 + 0.9 * limit, base), Action::Render);
    assert_eq!(action(Class::Testable, &h, 10, 1.0 + 1.1 * limit, base), Action::Query, "statistics expired");
    assert_eq!(action(Class::Testable, &h, 12, 1.1, base), Action::Query, "not seen in the previous frame: too old");
    assert_eq!(action(Class::Testable, &h, 10, 0.5, base), Action::Query, "time went backwards");
    assert_eq!(action(Class::Outside, &h, 10, 1.1, base), Action::Skip);
    // Three unoccluded results stretch the interval; an occluded last one forces a query.
    h.record(true, 1.2);
    h.record(true, 1.4);
    assert_eq!(h.unoccluded(), 3);
    let stretched = soq::not_query_time(base, 3);
    assert_eq!(action(Class::Testable, &h, 10, 1.4 + 0.99 * stretched, base), Action::Render);
    assert!(1.4 + 0.99 * stretched > 1.4 + limit);
    h.record(false, 1.5);
    assert_eq!(h.unoccluded(), 3);
    assert_eq!(action(Class::Testable, &h, 10, 1.51, base), Action::Query, "last result occluded");
    // The history keeps the last 8 results.
    for i in 0..10 {
        h.record(true, 2.0 + i as f32);
    }
    assert_eq!(h.unoccluded(), soq::HISTORY);
}

/// A row of unit boxes along x, 2 apart.
fn row(n: usize) -> Vec<Aabb> {
    (0..n).map(|i| Aabb::new(Vec3::new(2.0 * i as f32, 0.0, 0.0), Vec3::new(2.0 * i as f32 + 1.0, 1.0, 1.0))).collect()
}

/// A view looking down +x from `eye` with a wide frustum (nothing culled).
fn open_view(eye: Vec3) -> NodeView {
    let far = Vec4::new(0.0, 0.0, 0.0, 1e6);
    let mut planes = [far; 6];
    planes[4] = Vec4::new(1.0, 0.0, 0.0, -eye.x - 0.01); // near plane at x = eye.x + 0.01
    NodeView { planes, near_plane: planes[4], near: 0.01, eye, pixel: glam::Vec2::new(0.0, 1e-3) }
}

#[test]
fn traversal_is_front_to_back() {
    let boxes = row(37);
    let bvh = Bvh::build(&boxes, Split::Sah);
    for (eye, expect_rev) in [(Vec3::new(-10.0, 0.5, 0.5), false), (Vec3::new(100.0, 0.5, 0.5), true)] {
        // Children in front-to-back order, at every node.
        for n in 0..bvh.nodes.len() as u32 {
            if let Some(c) = bvh.children(n) {
                let [a, b] = front_to_back(&bvh, eye, c);
                assert!(box_distance(&bvh.aabb(a), eye) <= box_distance(&bvh.aabb(b), eye));
            }
        }
        // Everything visible: objects come out sorted by distance.
        let mut view = open_view(eye);
        if expect_rev {
            view.planes[4] = Vec4::new(-1.0, 0.0, 0.0, eye.x - 0.01);
            view.near_plane = view.planes[4];
        }
        let mut order = Vec::new();
        let tested = oq::traverse(&bvh, &view, |v| {
            if let oq::Visit::Draw(o) = v {
                order.push(o);
            }
            Ok(true)
        })
        .unwrap();
        assert_eq!(tested as usize, bvh.nodes.len(), "every node queried");
        let mut expect: Vec<u32> = (0..37).collect();
        if expect_rev {
            expect.reverse();
        }
        assert_eq!(order, expect);
    }
    // Occluded subtrees are skipped whole; a box holding the eye is never queried.
    let eye = Vec3::new(4.5, 0.5, 0.5); // inside box 2
    let view = open_view(eye);
    let mut queried = Vec::new();
    let mut drawn = Vec::new();
    oq::traverse(&bvh, &view, |v| match v {
        oq::Visit::Test(n) => {
            queried.push(n);
            Ok(n == 0 || bvh.aabb(n).contains(&boxes[3]))
        }
        oq::Visit::Draw(o) => {
            drawn.push(o);
            Ok(true)
        }
    })
    .unwrap();
    assert_eq!(view.classify(boxes[2]), Class::Near);
    assert!(!queried.contains(&bvh.leaf_of_object[2]));
    drawn.sort_unstable();
    assert_eq!(drawn, vec![2, 3]);
}

#[test]
fn chc_multiqueries_and_tighter_bounds() {
    // Fresh nodes (p = 0.29) are queried alone; long-invisible ones share queries.
    let fresh: Vec<(u32, u32)> = (0..5).map(|n| (n, 0)).collect();
    assert!(chc::multiqueries(fresh).iter().all(|m| m.len() == 1));
    let old: Vec<(u32, u32)> = (0..40).map(|n| (n, 20)).collect();
    let m = chc::multiqueries(old);
    assert!(m.len() < 40 && m.iter().any(|q| q.len() > 1), "{m:?}");
    let mut all: Vec<u32> = m.concat();
    all.sort_unstable();
    assert_eq!(all, (0..40).collect::<Vec<_>>(), "every node in exactly one query");
    assert!(chc::p_stay_invisible(0) < chc::p_stay_invisible(1) && chc::p_stay_invisible(30) < 0.99 + 1e-12);
    assert_eq!(chc::multiquery_value(1, 0.0), 1.0);

    // Tighter bounds cover every leaf below, stay within s_max and d_max.
    let boxes = row(50);
    let bvh = Bvh::build(&boxes, Split::Sah);
    for n in 0..bvh.nodes.len() as u32 {
        let t = chc::tight_boxes(&bvh, n, 4, 1.4);
        let own = bvh.aabb(n).area();
        let sum: f32 = t.iter().map(|&m| bvh.aabb(m).area()).sum();
        assert!(t == vec![n] || sum <= 1.4 * own * (1.0 + 1e-6), "node {n}: {sum} vs {own}");
        assert!(t.len() <= 16);
        let mut covered: Vec<u32> = t.iter().flat_map(|&m| leaves_under(&bvh, m)).collect();
        covered.sort_unstable();
        assert_eq!(covered, leaves_under(&bvh, n), "node {n}: tighter bounds lose leaves");
        assert!(t.iter().all(|&m| ancestors(&bvh, m).contains(&n) && ancestors(&bvh, m).len() <= ancestors(&bvh, n).len() + 4));
    }
    // Boxes spread along a row: splitting shrinks the area, so the root takes
    // the deepest allowed cut; with s_max below 1 nothing splits.
    assert_eq!(chc::tight_boxes(&bvh, 0, 4, 1.4).len(), 16);
    assert_eq!(chc::tight_boxes(&bvh, 0, 4, 0.5), vec![0]);
    assert_eq!(chc::tight_boxes(&bvh, 0, 0, 1.4), vec![0]);
}

fn ancestors(bvh: &Bvh, mut n: u32) -> Vec<u32> {
    let mut out = vec![n];
    while let Some(p) = bvh.parent(n) {
        out.push(p);
        n = p;
    }
    out
}

fn leaves_under(bvh: &Bvh, n: u32) -> Vec<u32> {
    let mut out = Vec::new();
    let mut stack = vec![n];
    while let Some(m) = stack.pop() {
        match bvh.children(m) {
            Some(c) => stack.extend(c),
            None => out.push(bvh.object(m).unwrap()),
        }
    }
    out.sort_unstable();
    out
}

#[test]
fn query_batches_chain_query_sets() {
    // More queries in one read-back than a query set holds: the results of
    // one big batch equal those of small batches over the same depth.
    use hroc::testing::cull::queries::{QueryRenderer, SET_SIZE};
    use hroc::Phase;
    let scene = hroc_bench::scene::load("radial-city", Some(1200), 2).unwrap();
    let mut s = Session::new(gpu(), scene, None, 4, RES, Split::Sah).unwrap();
    let nodes = s.bvh().nodes.len() as u32;
    let bvh = s.bvh().clone();
    let mut v = s.create("noc".parse().unwrap()).unwrap();
    let mut q = QueryRenderer::new(&v.method_context(&s.culler)).unwrap();
    let (mut big, mut small, mut testable) = (Vec::new(), Vec::new(), Vec::new());
    let mut body = |f: &mut hroc::testing::cull::Frame| -> hroc::Result<()> {
        q.begin_frame();
        let all = f.all();
        f.draw(Phase::Visible, &all, None);
        let view = NodeView::from_frame(f);
        let t: Vec<u32> = (0..nodes).filter(|&n| view.classify(bvh.aabb(n)) == Class::Testable).collect();
        // Every testable box, over and over: two sets and a part of a third.
        testable = t.iter().cycle().take(2 * SET_SIZE as usize + 123).copied().collect();
        for &n in &testable {
            q.query(f, &[n]);
        }
        big = q.collect(f)?;
        for chunk in testable.chunks(700) {
            for &n in chunk {
                q.query(f, &[n]);
            }
            small.extend(q.collect(f)?);
        }
        q.finish_frame(f);
        Ok(())
    };
    let cam = s.cameras[1];
    s.run_camera_with(&mut v, cam, 0.0, false, &mut |view, culler, enc, input, host| view.cull_with(culler, enc, input, host, &mut body)).unwrap();
    assert_eq!(big.len(), testable.len());
    assert_eq!(big, small);
    let visible = big.iter().filter(|&&x| x > 0).count();
    assert!(visible > 0 && visible < big.len(), "{visible} of {} boxes visible", big.len());
    assert_eq!(q.stats.batches as usize, 1 + testable.len().div_ceil(700));
}
