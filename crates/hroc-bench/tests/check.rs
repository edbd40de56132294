//! The checker every conservativeness test relies on: a dropped visible
//! object is a false negative with missing pixels; a `noc` fragment that
//! lies in front of its own object's box (a rasterizer stray) is neither.

use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;

/// Satellites, 10,000 objects, frame 325 of 600: lavapipe (Mesa 22.3)
/// draws object 9646, a rock 81 m away, with one fragment at pixel
/// (276, 236) whose depth puts it 16 m from the eye. A CPU projection of
/// the rock's triangles covers no such pixel (examples/stray_fragment.rs).
const FRAME: usize = 325;
const ROCK: u32 = 9646;
const PIXEL: usize = 236 * 640 + 276;

#[test]
fn real_misses_count_and_strays_do_not() {
    let gpu = Headless::new().unwrap();
    let scene = hroc_bench::scene::load("satellites", Some(10_000), 0).unwrap();
    let mut s = Session::new(&gpu, scene, None, 600, (640, 360), Split::Sah).unwrap();
    let (_, truth) = s.truth(FRAME).unwrap();
    let mut r = s.create("ref".parse().unwrap()).unwrap();

    // Drop one ordinary visible object (the one owning the most pixels): a real miss.
    let mut owned = vec![0usize; s.scene.objects.len()];
    for &id in truth.ids.iter().filter(|&&id| id > 0) {
        owned[(id - 1) as usize] += 1;
    }
    let big = (0..owned.len()).max_by_key(|&o| owned[o]).unwrap() as u32;
    r.set_oracle(&s.culler, &truth.visible.iter().copied().filter(|&o| o != big).collect::<Vec<_>>()).unwrap();
    let f = s.run_frame(&mut r, FRAME).unwrap();
    let c = s.check(&f, &truth).unwrap();
    assert_eq!(c.false_negatives, 1, "{c:?}");
    assert!(c.missing_pixels > 0 && c.stray_pixels == 0, "{c:?}");

    // Drop the rock whose only noc pixel is the stray.
    // The scene and frame were chosen for lavapipe's rasterizer, which
    // draws the rock's one stray fragment there.
    assert_eq!((truth.ids[PIXEL], owned[ROCK as usize]), (ROCK + 1, 1), "noc draws the rock's stray fragment at pixel {PIXEL} of frame {FRAME}");
    r.set_oracle(&s.culler, &truth.visible.iter().copied().filter(|&o| o != ROCK).collect::<Vec<_>>()).unwrap();
    let f = s.run_frame(&mut r, FRAME).unwrap();
    let c = s.check(&f, &truth).unwrap();
    assert_eq!((c.false_negatives, c.missing_pixels, c.stray_pixels), (0, 0, 1), "{c:?}");
}
