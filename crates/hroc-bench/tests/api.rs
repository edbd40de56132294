//! The host API beyond the paper, on lavapipe: several views of one
//! culler keep their own state, a camera cut makes a view start over,
//! never-culled objects are drawn once every frame, and every one of
//! them stays conservative against `noc`.

use hroc::{ObjectFlags, View};
use hroc_bench::bench::{FrameResult, Session};
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const FRAMES: usize = 16;

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

fn session() -> Session<'static> {
    let scene = hroc_bench::scene::load("radial-city", Some(2000), 3).unwrap();
    Session::new(gpu(), scene, None, FRAMES, RES, Split::Sah).unwrap()
}

/// Objects drawn per command list of a frame (instance_count > 0), counted
/// with repeats.
fn draws_of(s: &Session, r: &FrameResult) -> Vec<u32> {
    let mut n = vec![0u32; s.renderer.object_count as usize];
    for l in &r.lists {
        for c in s.gpu.read_list(&l.commands, &l.count, l.max_count).unwrap() {
            if c.instance_count > 0 && c.index_count > 0 {
                n[c.first_instance as usize] += 1;
            }
        }
    }
    n
}

/// Runs `view` at camera `k` (with `cut`) and checks it against noc there.
fn checked(s: &mut Session, view: &mut View, k: usize, cut: bool) -> Vec<u32> {
    let (_, truth) = s.truth(k).unwrap();
    let r = s.run_frame_cut(view, k, cut).unwrap();
    let c = s.check(&r, &truth).unwrap();
    assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{} frame {k}", view.method());
    draws_of(s, &r)
}

#[test]
fn views_of_one_culler_keep_their_own_state() {
    let mut s = session();
    for method in ["hroc", "hzb", "roc"] {
        // One view alone along the path...
        let mut solo = s.create(method.parse().unwrap()).unwrap();
        let alone: Vec<Vec<u32>> = (0..FRAMES).map(|k| checked(&mut s, &mut solo, k, false)).collect();
        // ...and the same method again, interleaved with a second view that
        // flies the path backwards: its frames must not change.
        let (mut a, mut b) = (s.create(method.parse().unwrap()).unwrap(), s.create(method.parse().unwrap()).unwrap());
        for (k, alone) in alone.iter().enumerate() {
            let drawn = checked(&mut s, &mut a, k, false);
            assert_eq!(&drawn, alone, "{method} frame {k}: a second view changed the first one's result");
            checked(&mut s, &mut b, FRAMES - 1 - k, false);
        }
    }
}

#[test]
fn a_camera_cut_starts_the_view_over() {
    let mut s = session();
    for method in ["hroc", "hzb", "roc", "chc++"] {
        let mut warm = s.create(method.parse().unwrap()).unwrap();
        for k in 0..FRAMES / 2 {
            checked(&mut s, &mut warm, k, false);
        }
        // After a cut to the last camera, the warm view culls exactly as a
        // fresh view's first frame there.
        let cut = checked(&mut s, &mut warm, FRAMES - 1, true);
        let mut fresh = s.create(method.parse().unwrap()).unwrap();
        let first = checked(&mut s, &mut fresh, FRAMES - 1, false);
        assert_eq!(cut, first, "{method}: a cut did not reset the view");
    }
}

#[test]
fn never_culled_objects_are_drawn_once_every_frame() {
    let mut s = session();
    let n = s.renderer.object_count;
    let never: Vec<u32> = (0..n).step_by(97).collect();
    for &o in &never {
        s.culler.set_flags(o, ObjectFlags::NEVER_CULL).unwrap();
    }
    assert!(s.culler.set_flags(n, ObjectFlags::NEVER_CULL).is_err(), "an object out of range is an error");
    for method in ["hroc", "hzb", "chc++", "vfc", "noc"] {
        let mut v = s.create(method.parse().unwrap()).unwrap();
        for k in 0..FRAMES {
            let drawn = checked(&mut s, &mut v, k, false);
            for &o in &never {
                assert_eq!(drawn[o as usize], 1, "{method} frame {k}: never-culled object {o} drawn {} times", drawn[o as usize]);
            }
        }
    }
}

/// Objects drawn (with repeats) and their triangles, from the lists of a
/// frame read back after it.
fn drawn_of(s: &Session, r: &FrameResult) -> (u32, u32) {
    let (mut objects, mut triangles) = (0, 0);
    for l in &r.lists {
        for c in s.gpu.read_list(&l.commands, &l.count, l.max_count).unwrap() {
            if c.instance_count > 0 && c.index_count > 0 {
                objects += 1;
                triangles += c.index_count / 3;
            }
        }
    }
    (objects, triangles)
}

/// `View::frame_stats` comes back without a wait, once the frame's work is
/// done, and counts
/// what the lists of that frame drew: for every method family, with
/// stall-free overflow lists, mid-frame submits (read-backs, queries) and
/// flagged objects.
#[test]
fn frame_stats_count_what_every_method_drew() {
    let mut s = session();
    let n = s.renderer.object_count;
    for o in (0..n).step_by(89) {
        s.culler.set_flags(o, ObjectFlags::NEVER_CULL).unwrap();
    }
    for o in (5..n).step_by(101) {
        s.culler.set_flags(o, ObjectFlags::NOT_OCCLUDER).unwrap();
    }
    for method in ["noc", "vfc", "hzb", "roc", "hroc", "hroc-cr", "ioc", "oq", "chc++"] {
        let mut v = s.create(method.parse().unwrap()).unwrap();
        assert_eq!(v.frame_stats(&s.culler), None, "{method}: no frame yet");
        let mut drawn = Vec::new();
        for k in 0..FRAMES {
            let r = s.run_frame(&mut v, k).unwrap();
            drawn.push(drawn_of(&s, &r));
            // run_frame waited for the frame: its statistics have come back.
            let st = v.frame_stats(&s.culler).unwrap_or_else(|| panic!("{method} frame {k}: no statistics"));
            assert_eq!(st.frame, k as u64, "{method}");
            assert_eq!((st.objects, st.triangles), drawn[k], "{method} frame {k}");
        }
    }
}
