//! HROC's frame sized to what it saves in each view (`cull/hroc/gate.rs`),
//! on lavapipe: a camera and a light's cascade over the same city, each
//! checked against its own unculled picture.

use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;

/// The gate (`cull/hroc/gate.rs`): in the far cascade of a light over the
/// city, where occlusion culls a few per cent of the frustum's objects and
/// nearly every object drawn owns a pixel, `hroc` culls by the frustum
/// alone between its probes (frame 0, then one in `PROBE_LEAST` once a
/// probe found occlusion not paying) and the frames before the first
/// probe's counts arrive; the camera culls
/// every frame by
/// occlusion and filters in more frames than the light. Every frame of
/// both draws every object the unculled view shows.
#[test]
fn hroc_sizes_its_frame_to_what_it_saves_in_each_view() {
    let scene = hroc_bench::scene::load("radial-city", Some(5000), 0).unwrap();
    let gpu = Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let mut s = Session::new(&gpu, scene, None, 40, (320, 180), Split::Sah).unwrap();
    s.set_shadow_cascades(3).unwrap();
    let far = 2;
    let (mut camera, mut light) = (s.create(hroc::Method::HROC).unwrap(), s.create_cascade(hroc::Method::HROC, far).unwrap());
    let stat = |v: &mut hroc::View, s: &Session, which| v.stats(&s.culler).unwrap().iter().any(|x| x.0 == which && x.1 > 0.0) as u32;
    use hroc::stats::Stat::{Filtered, Occlusion};
    let (mut camera_filtered, mut light_filtered, mut camera_occlusion, mut light_occlusion) = (0, 0, 0, 0);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k).unwrap();
        let r = s.run_frame(&mut camera, k).unwrap();
        let chk = s.check(&r, &truth).unwrap();
        assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "camera frame {k}");
        camera_filtered += stat(&mut camera, &s, Filtered);
        camera_occlusion += stat(&mut camera, &s, Occlusion);
        let cascade = s.cascades(k)[far as usize];
        let time = s.times[k];
        let (_, truth) = s.cascade_truth(far, &cascade, time).unwrap();
        let r = s.run_cascade(&mut light, far, &cascade, time).unwrap();
        let chk = s.check_cascade(far, &r, &truth).unwrap();
        assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "cascade frame {k}");
        light_filtered += stat(&mut light, &s, Filtered);
        light_occlusion += stat(&mut light, &s, Occlusion);
    }
    let frames = s.cameras.len() as u32;
    use hroc::testing::cull::hroc::gate::PROBE_LEAST;
    // At most a probe at frames 0, PROBE_LEAST, 2 × PROBE_LEAST, … (counts
    // arriving a frame or two late put each a little later).
    let probes = frames.div_ceil(PROBE_LEAST);
    assert_eq!(camera_occlusion, frames, "the camera culled {camera_occlusion} of {frames} frames by occlusion");
    assert!(light_occlusion <= probes + 4, "the light's view culled {light_occlusion} of {frames} frames by occlusion");
    assert!(camera_filtered > light_filtered, "camera filtered {camera_filtered}, light {light_filtered} of {frames}");
}

/// A light over `houses`, whose objects are all boxes: in its far
/// cascade occlusion culls most of the frustum's objects, but they hold
/// no more triangles than the boxes HROC's test draws for the objects it
/// tests. With the bar of views drawn depth only (the bench's cascades)
/// the view culls by the frustum alone and never probes; with one object
/// of the scene richer than its box, it probes and its measurements find
/// occlusion not paying, so it culls by the frustum between its probes;
/// without the bar (as a camera), by occlusion in most frames. Every
/// frame draws every object the unculled cascade shows.
#[test]
fn a_light_over_boxes_culls_by_the_frustum() {
    let boxes = hroc_bench::scene::load("houses", Some(3000), 0).unwrap();
    // (The same picture: the first object draws its block's triangles twice.)
    let mut richer = boxes.clone();
    let mut mesh = richer.meshes[richer.objects[0].mesh as usize].clone();
    assert_eq!(mesh.indices.len(), 36, "houses are built of boxes");
    mesh.indices = mesh.indices.repeat(2);
    richer.meshes.push(mesh);
    richer.objects[0].mesh = richer.meshes.len() as u32 - 1;
    let gpu = Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let far = 2;
    let mut occlusion = [0; 3];
    let mut frames = 0;
    let cases = [(&boxes, hroc::options::DEPTH_ONLY_TRIANGLES), (&richer, hroc::options::DEPTH_ONLY_TRIANGLES), (&boxes, 0.0)];
    for (i, (scene, bar)) in cases.into_iter().enumerate() {
        let mut s = Session::new(&gpu, scene.clone(), None, 40, (320, 180), Split::Sah).unwrap();
        s.set_shadow_cascades(3).unwrap();
        s.shadow_triangles = bar;
        let mut light = s.create_cascade(hroc::Method::HROC, far).unwrap();
        for k in 0..s.cameras.len() {
            let cascade = s.cascades(k)[far as usize];
            let time = s.times[k];
            let (_, truth) = s.cascade_truth(far, &cascade, time).unwrap();
            let r = s.run_cascade(&mut light, far, &cascade, time).unwrap();
            let chk = s.check_cascade(far, &r, &truth).unwrap();
            assert_eq!((chk.false_negatives, chk.missing_pixels), (0, 0), "case {i}, frame {k}");
            let stats = light.stats(&s.culler).unwrap();
            occlusion[i] += stats.iter().any(|x| x.0 == hroc::stats::Stat::Occlusion && x.1 > 0.0) as u32;
        }
        frames = s.cameras.len() as u32;
    }
    use hroc::testing::cull::hroc::gate::PROBE_LEAST;
    assert_eq!(occlusion[0], 0, "over boxes, with the depth-only bar, {} of {frames} frames by occlusion", occlusion[0]);
    assert!((1..=frames.div_ceil(PROBE_LEAST) + 4).contains(&occlusion[1]), "one object richer, {} of {frames} frames by occlusion", occlusion[1]);
    assert!(occlusion[2] >= frames * 3 / 4, "without the bar, {} of {frames} frames by occlusion", occlusion[2]);
}
