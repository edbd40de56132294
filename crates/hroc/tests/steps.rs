//! Engines that drive their own frame, on lavapipe: visibility as data
//! (`View::visibility`) and the stepwise frame (`View::steps`). An engine
//! of a few lines draws the street in its own two passes from the
//! visibility buffer, and each frame of each method that can run stepwise
//! draws every object `noc` shows, on the full and the portable tier, with
//! marks from boxes and from IDs, single-sample and at MSAA 4, along a
//! walk, a camera cut, the eye inside a box and an orthographic cascade;
//! the engine leaves out its late pass where the frame says it draws
//! nothing there (`Steps::late`).

use common::engine::Engine;
use common::street::{look, street, street_on, Depth};
use glam::{Mat4, Vec3};
use hroc::device::{Capabilities, Marks};
use hroc::options::Variant;
use hroc::{Culler, CullerDesc, Error, FrameInput, Method, MethodOptions, ViewDesc};

mod common;

fn path() -> Vec<(ViewDesc, bool)> {
    let mut path: Vec<(ViewDesc, bool)> = (0..4).map(|k| (look(Vec3::new(-3.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)), true));
    path.push((look(Vec3::new(0.0, 1.5, 2.5), Vec3::new(0.0, 1.0, -10.0)), true));
    path.push((look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    let light = Mat4::look_at_rh(Vec3::new(3.0, 12.0, 8.0), Vec3::new(0.0, 0.0, -8.0), Vec3::Z);
    for k in 0..2 {
        let proj = Mat4::orthographic_rh(-14.0, 14.0, -14.0, 14.0, -20.0 + k as f32, 60.0);
        path.push((ViewDesc { view: light, proj, unclipped_depth: false }, k == 0));
    }
    path
}

#[test]
fn stepwise_frames_draw_every_visible_object() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let path = path();
    let tiers = [Capabilities { marks: Marks::Boxes, ..Capabilities::FULL }, Capabilities { marks: Marks::Boxes, ..Capabilities::PORTABLE }, Capabilities::PORTABLE];
    for samples in [1, 4] {
        let (host, objects) = street_on(&device, Depth { samples, ..Depth::default() });
        let engine = Engine::new(&device, &host);
        let truth = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
        let visible = host.visible_along(&device, &queue, &truth, &path);
        for caps in tiers {
            let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), ..CullerDesc::new(&objects) }).unwrap();
            for method in [Method::Noc, Method::Vfc, Method::Hzb, Method::Roc, Method::Hroc(Variant::SF), Method::HROC, Method::Auto] {
                let label = format!("{method} stepwise ({caps:?}, {samples} samples)");
                let mut view = culler.view(method, &host.targets()).unwrap();
                let mut culled = 0;
                engine.late_left_out.set(0);
                for (k, &(desc, cut)) in path.iter().enumerate() {
                    let drawn = engine.frame(&device, &queue, &host, &culler, &mut view, desc, cut).unwrap_or_else(|e| panic!("{label}: {e}"));
                    let missed: Vec<u32> = visible[k].iter().copied().filter(|o| drawn.binary_search(o).is_err()).collect();
                    assert!(missed.is_empty(), "{label} frame {k}: visible objects {missed:?} not drawn");
                    // The engine's image: every object noc shows owns a pixel of it, and nothing else does.
                    assert_eq!(host.visible(&device, &queue), visible[k], "{label} frame {k}: the engine's ID image");
                    culled += objects.len() - drawn.len();
                }
                assert!(culled > 0 || method == Method::Noc, "{label} culled nothing");
                // Methods that decide everything before the early pass leave the late pass
                // nothing to draw, and say so (Steps::late); a test after the early pass draws late.
                let left_out = engine.late_left_out.get() as usize;
                match method {
                    Method::Noc | Method::Vfc => assert_eq!(left_out, path.len(), "{label}: late passes left out"),
                    Method::Hzb | Method::Roc => assert!(left_out < path.len(), "{label}: every late pass left out"),
                    _ => {}
                }
                // The same method through the host's draw lists culls as much (HROC's
                // refill, left out stepwise, culls a little more).
                let mut lists = culler.view(method, &host.targets()).unwrap();
                let listed: usize = path.iter().map(|&(desc, cut)| objects.len() - host.frame(&device, &queue, &culler, &mut lists, desc, cut).len()).sum();
                assert!(culled * 10 >= listed * 9, "{label}: culled {culled} stepwise, {listed} through the host's lists");
            }
        }
    }
}

/// A view drawn depth only where occlusion does not pay (the share bar
/// at 1): `View::plans_late` plans its frames of the frustum ahead,
/// without a late pass, and `View::wants_steps` asks to record only the
/// measurements and the frames before them; the engine leaves out the
/// rest. Every frame recorded draws every object `noc` shows and keeps to
/// its plan. Moved halfway to another texture of the same shape (an
/// engine's shadow map reallocated), the view keeps its measurements:
/// its next frame is still planned to the frustum.
#[test]
fn frames_of_the_frustum_are_planned_ahead_and_recorded_where_needed() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    let engine = Engine::new(&device, &host);
    let desc = look(Vec3::new(0.0, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0));
    let truth = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    let visible = host.visible_along(&device, &queue, &truth, &[(desc, false)]).remove(0);
    let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(Capabilities { marks: Marks::Boxes, ..Capabilities::FULL }), ..CullerDesc::new(&objects) }).unwrap();
    let options = MethodOptions { hroc_frustum_below: 1.0, hroc_frustum_triangles: hroc::options::DEPTH_ONLY_TRIANGLES, ..MethodOptions::default() };
    let mut view = culler.view_with(Method::Hroc(Variant::SF), &host.targets(), &options).unwrap();
    let input = FrameInput { view: desc, cut: false, time: 0.0 };
    let (other, _) = street(&device);
    let (frames, mut planned, mut recorded) = (80, 0, 0);
    for k in 0..frames {
        let host = if k < frames / 2 { &host } else { &other };
        if k == frames / 2 {
            view.resize(&culler, &other.targets()).unwrap();
        }
        let late = view.plans_late(&culler, &input);
        assert!(k != frames / 2 || !late, "the frame after the resize is planned to the frustum");
        planned += !late as u32;
        if !late && !view.wants_steps() {
            continue;
        }
        engine.late_left_out.set(0);
        let drawn = engine.frame(&device, &queue, host, &culler, &mut view, desc, false).unwrap();
        recorded += 1;
        assert!(late || engine.late_left_out.get() == 1, "frame {k}: planned without a late pass, and drew one");
        let missed: Vec<u32> = visible.iter().copied().filter(|o| drawn.binary_search(o).is_err()).collect();
        assert!(missed.is_empty(), "frame {k}: visible objects {missed:?} not drawn");
    }
    assert!(planned > frames * 3 / 4, "{planned} of {frames} frames planned to the frustum");
    assert!(recorded < frames / 4, "{recorded} of {frames} frames recorded");
}

/// Visibility as data in a frame culled through the host's draw lists:
/// the slots stamped with a phase are the objects of that phase's lists.
#[test]
fn visibility_stamps_the_lists_handed() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    for caps in [Capabilities::FULL, Capabilities::PORTABLE] {
        let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), ..CullerDesc::new(&objects) }).unwrap();
        for method in [Method::Vfc, Method::Hzb, Method::HROC] {
            let mut view = culler.view(method, &host.targets()).unwrap();
            let visibility = view.visibility(&culler).clone();
            for (k, &(desc, cut)) in path().iter().enumerate() {
                let drawn = host.frame(&device, &queue, &culler, &mut view, desc, cut);
                let slots: Vec<u32> = hroc_readback::read(&device, &queue, &visibility, 0, (hroc::device::VISIBILITY_HEADER + culler.object_count()) as u64).unwrap();
                let (header, slots) = slots.split_at(hroc::device::VISIBILITY_HEADER as usize);
                let stamped: Vec<u32> = (0..slots.len() as u32).filter(|&o| header[..6].contains(&slots[o as usize])).collect();
                assert_eq!(stamped, drawn, "{method} ({caps:?}) frame {k}: the stamped objects are the lists'");
                // Stamps of earlier frames no longer count.
                assert!(header.iter().take(6).all(|s| *s != 0) && header[..6].iter().collect::<std::collections::BTreeSet<_>>().len() == 6);
            }
        }
    }
}

/// What a stepwise frame cannot run is refused, naming the fix, and the
/// view runs its next frame.
#[test]
fn what_cannot_run_stepwise_is_refused() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    let engine = Engine::new(&device, &host);
    let desc = look(Vec3::new(0.0, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0));
    let boxes = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(Capabilities { marks: Marks::Boxes, ..Capabilities::FULL }), ..CullerDesc::new(&objects) }).unwrap();
    let early_z = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    let refused = |culler: &Culler, method: Method, options: &MethodOptions, needle: &str| {
        let mut view = culler.view_with(method, &host.targets(), options).unwrap();
        let e = engine.frame(&device, &queue, &host, culler, &mut view, desc, true).unwrap_err();
        assert!(matches!(e, Error::InvalidScene(_)) && e.to_string().contains(needle), "{method}: {e}");
    };
    refused(&boxes, Method::Hroc(Variant::CR), &MethodOptions::default(), "submits mid-frame");
    refused(&early_z, Method::HROC, &MethodOptions::default(), "Marks::Boxes");
    refused(&boxes, Method::Ioc, &MethodOptions::default(), "submits mid-frame");
    // A view refused once runs stepwise as soon as it can: hzb reads no marks.
    let mut view = early_z.view(Method::Hzb, &host.targets()).unwrap();
    assert!(engine.frame(&device, &queue, &host, &early_z, &mut view, desc, true).is_ok());
}

/// Stepwise frames validated (`View::validation`), on both tiers, in
/// views without IDs: the engine's passes raise nothing; an engine whose
/// vertex shader lifts a cube 0.6 above its box is reported within 3
/// frames, naming the cube.
#[test]
fn stepwise_frames_are_validated() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    // The cube at x = -4, z = 0, 3 high, before the wall.
    let cube = 21;
    for caps in [Capabilities { marks: Marks::Boxes, ..Capabilities::FULL }, Capabilities { marks: Marks::Boxes, ..Capabilities::PORTABLE }] {
        let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
        for method in [Method::Hzb, Method::Hroc(Variant::SF)] {
            for lifted in [None, Some((cube, 0.6))] {
                let engine = Engine::lifting(&device, &host, lifted);
                let mut view = culler.view(method, &host.targets()).unwrap();
                let results: Vec<hroc::Result<()>> = path()[..4]
                    .iter()
                    .map(|&(desc, cut)| {
                        engine.frame(&device, &queue, &host, &culler, &mut view, desc, cut).unwrap();
                        view.validation(&culler)
                    })
                    .collect();
                let label = format!("{method} ({caps:?}), lifted {lifted:?}");
                match lifted {
                    None => assert!(results.iter().all(|r| r.is_ok()), "{label}: {results:?}"),
                    Some(_) => {
                        let first = results.iter().position(|r| r.is_err()).filter(|&k| k < 3).unwrap_or_else(|| panic!("{label}: nothing within 3 frames: {results:?}"));
                        let Err(Error::Validation(finding)) = &results[first] else { panic!("{label}: {results:?}") };
                        assert!(finding.cause.contains("in front of every box") && finding.object == Some(cube), "{label}: {finding}");
                    }
                }
            }
        }
    }
}
