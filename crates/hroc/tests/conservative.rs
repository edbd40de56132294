//! The culler on its own (no scene crate, no benchmark), on lavapipe: a
//! host of a few lines draws a street of cubes behind a wall through every
//! method family, and each frame of each method draws every object that
//! owns a pixel when everything is drawn (`noc`'s object-ID image), across
//! a walk, a camera cut and an eye inside an object's box.

use common::street::{look, street, street_on, Depth};
use glam::Vec3;
use hroc::device::{Capabilities, DrawCount, Marks};
use hroc::options::Variant;
use hroc::{Culler, CullerDesc, Method, ViewDesc};

mod common;

#[test]
fn every_method_family_draws_every_visible_object() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    assert_eq!(culler.capabilities(), Capabilities::FULL);
    // A walk along the street, a cut to above the wall, and the eye inside
    // the last box (which crosses the near plane).
    let mut path: Vec<(ViewDesc, bool)> = (0..6).map(|k| (look(Vec3::new(-3.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)), true));
    path.push((look(Vec3::new(0.0, 1.5, 2.5), Vec3::new(0.0, 1.0, -10.0)), true));
    path.push((look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    let visible = host.visible_along(&device, &queue, &culler, &path);
    assert!(visible.iter().all(|v| !v.is_empty()) && visible[0].len() < objects.len() / 2, "the wall hides most of the street: {visible:?}");
    // The full tier; what GL has (an emulated count, early-Z marks, no
    // read-only depth attachments, so the box tests compare depth
    // themselves); what DX12 has (the indirect count, ID marks); and the
    // portable tier (an emulated count, ID marks, no read-only depth).
    let gl = Capabilities { draw_count: DrawCount::Emulated, marks: Marks::EarlyZ, read_only_depth: false };
    let dx12 = Capabilities { draw_count: DrawCount::Indirect, marks: Marks::Ids, read_only_depth: true };
    for caps in [Capabilities::FULL, gl, dx12, Capabilities::PORTABLE] {
        let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
        assert_eq!(culler.capabilities(), caps);
        for method in [Method::Vfc, Method::Hzb, Method::Roc, Method::RocAll, Method::Ioc, Method::Chc, Method::Hroc(Variant::NA), Method::HROC] {
            let mut view = culler.view(method, &host.targets()).unwrap();
            let culled = host.draws_visible_along(&device, &queue, &culler, &mut view, &path, &visible, &format!("{method} ({caps:?})"));
            assert!(culled > 0, "{method} ({caps:?}) culled nothing");
        }
    }
}

/// Orthographic views (a directional light's shadow cascade looks at the
/// scene this way): every method family draws every object `noc` shows,
/// in both depth conventions, from the side and from above, with near
/// planes in front of the scene and cutting through it, across cuts, on
/// the full and the portable tier.
#[test]
fn orthographic_views_draw_every_visible_object() {
    use glam::Mat4;
    use hroc::DepthRange;
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let ortho = |eye: Vec3, target: Vec3, half: f32, near: f32, far: f32, depth: DepthRange| {
        let up = if (target - eye).normalize().y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
        let proj = match depth {
            DepthRange::Standard => Mat4::orthographic_rh(-half, half, -half, half, near, far),
            DepthRange::Reversed => Mat4::orthographic_rh(-half, half, -half, half, far, near),
        };
        ViewDesc { view: Mat4::look_at_rh(eye, target, up), proj, unclipped_depth: false }
    };
    for (depth, caps) in [DepthRange::Standard, DepthRange::Reversed].into_iter().flat_map(|d| [(d, Capabilities::FULL), (d, Capabilities::PORTABLE)]) {
        let (host, objects) = street_on(&device, Depth { range: depth, ..Depth::default() });
        let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
        let path: Vec<(ViewDesc, bool)> = vec![
            (ortho(Vec3::new(0.0, 2.0, 12.0), Vec3::new(0.0, 1.0, -10.0), 6.0, 0.1, 40.0, depth), true),
            (ortho(Vec3::new(1.0, 2.0, 12.0), Vec3::new(0.5, 1.0, -10.0), 6.0, 0.1, 40.0, depth), false),
            // The near plane cuts the street (behind it the wall hides most).
            (ortho(Vec3::new(1.0, 2.0, 12.0), Vec3::new(0.5, 1.0, -10.0), 6.0, 10.0, 40.0, depth), false),
            // A light from above and in front, its near plane behind the camera position.
            (ortho(Vec3::new(3.0, 12.0, 8.0), Vec3::new(0.0, 0.0, -8.0), 14.0, -20.0, 60.0, depth), true),
            (ortho(Vec3::new(3.5, 12.0, 8.0), Vec3::new(0.0, 0.0, -8.0), 14.0, -20.0, 60.0, depth), false),
        ];
        let visible = host.visible_along(&device, &queue, &culler, &path);
        assert!(visible.iter().all(|v| !v.is_empty()), "{depth:?}: the street is in view");
        for method in [Method::Vfc, Method::Hzb, Method::Roc, Method::RocAll, Method::Ioc, Method::Chc, Method::Hroc(Variant::NA), Method::HROC] {
            let mut view = culler.view(method, &host.targets()).unwrap();
            let culled = host.draws_visible_along(&device, &queue, &culler, &mut view, &path, &visible, &format!("{method} {depth:?} {caps:?} orthographic"));
            assert!(culled > 0, "{method} {depth:?} culled nothing in orthographic views");
        }
    }
}

/// A shadow cascade keeps the light's view matrix while its box follows
/// the camera in the projection: a view treats a jump of its box as a cut
/// (as a camera's jump), and a box that slides a little as coherent.
#[test]
fn a_cascade_whose_box_jumps_is_a_cut() {
    use glam::Mat4;
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    let light = Mat4::look_at_rh(Vec3::ZERO, Vec3::new(-0.3, -1.0, -0.4), Vec3::Z);
    let cascade = |x: f32| ViewDesc { view: light, proj: Mat4::orthographic_rh(x - 8.0, x + 8.0, -8.0, 8.0, -40.0, 40.0), unclipped_depth: false };
    let mut view = culler.view(Method::HROC, &host.targets()).unwrap();
    let mut cuts = Vec::new();
    for x in [0.0, 0.3, 0.6, 14.0, 14.3] {
        host.frame(&device, &queue, &culler, &mut view, cascade(x), false);
        let stats = view.stats(&culler).unwrap();
        cuts.push(stats.iter().find(|(s, _)| *s == hroc::stats::Stat::Cut).map(|s| s.1).unwrap());
    }
    assert_eq!(cuts, [0.0, 0.0, 0.0, 1.0, 0.0], "a jump of 14 units (past a tenth of the street's diagonal) is a cut; slides of 0.3 are not");
}

/// Marks from boxes (`Marks::Boxes`: the host's shaders do not mark, and
/// no ID target is read for marks): every method that reads marks draws
/// every object `noc` shows, on the full and the portable tier, in
/// perspective along the walk (a cut, the eye inside a box) and in an
/// orthographic cascade, single-sample and at MSAA 4.
#[test]
fn marks_from_boxes_draw_every_visible_object() {
    use glam::Mat4;
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let mut path: Vec<(ViewDesc, bool)> = (0..4).map(|k| (look(Vec3::new(-3.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((look(Vec3::new(0.0, 1.5, 2.5), Vec3::new(0.0, 1.0, -10.0)), true));
    path.push((look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    let light = Mat4::look_at_rh(Vec3::new(3.0, 12.0, 8.0), Vec3::new(0.0, 0.0, -8.0), Vec3::Z);
    for k in 0..2 {
        let proj = Mat4::orthographic_rh(-14.0, 14.0, -14.0, 14.0, -20.0 + k as f32, 60.0);
        path.push((ViewDesc { view: light, proj, unclipped_depth: false }, k == 0));
    }
    let boxes_full = Capabilities { marks: Marks::Boxes, ..Capabilities::FULL };
    let boxes_portable = Capabilities { marks: Marks::Boxes, ..Capabilities::PORTABLE };
    // A device without forced early-Z (DX12, Metal): the box tests load depth.
    let (plain_device, plain_queue) = common::device(hroc::device::REQUIRED_FEATURES | wgpu::Features::MULTI_DRAW_INDIRECT_COUNT);
    for (samples, plain) in [(1, false), (4, false), (1, true), (4, true)] {
        let (device, queue) = if plain { (&plain_device, &plain_queue) } else { (&device, &queue) };
        let (host, objects) = street_on(device, Depth { samples, ..Depth::default() });
        let culler = Culler::new(device, queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
        let visible = host.visible_along(device, queue, &culler, &path);
        for caps in [boxes_full, boxes_portable] {
            let culler = Culler::new(device, queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
            assert_eq!(culler.capabilities(), caps);
            for method in [Method::Roc, Method::Ioc, Method::Hroc(Variant::NA), Method::Hroc(Variant::SF), Method::HROC] {
                let mut view = culler.view(method, &host.targets()).unwrap();
                let label = format!("{method} ({caps:?}, {samples} samples, early-Z device: {})", !plain);
                let culled = host.draws_visible_along(device, queue, &culler, &mut view, &path, &visible, &label);
                assert!(culled > 0, "{label} culled nothing");
                if let Method::Hroc(_) = method {
                    // Effective occluders in the last frame: those the boxes
                    // marked, or all of V where the boxes mark once a frame
                    // (hroc-sf, hroc-na: then the boxes' marks are next V).
                    let stats = view.stats(&culler).unwrap();
                    let o = stats.iter().find(|(s, _)| *s == hroc::stats::Stat::O).map_or(0.0, |s| s.1);
                    assert!(o > 0.0, "{label}: no object marked by its box");
                }
            }
        }
    }
}
