//! Every depth format a host may draw into, multisampled targets, and a
//! view on another layer or mip of its depth texture, on the full and the portable tier: each
//! frame of each method family draws exactly `noc`'s picture (the same
//! object-ID image, so no object that owns a pixel is missed and no pixel
//! is missing), across a walk, a camera cut and the eye inside an object's
//! box. So does a host that biases its depth away from the viewer, or
//! clamps it at the near plane (shadow passes).
//!
//! Why the box tests' margins need not grow with the format's step: an
//! object that owns a pixel in `noc` won the depth test there, so its
//! depth, stored, is a step or more in front of every occluder's stored
//! depth; a box fragment lies in front of (or on) the object's surface, so
//! it is in front of the stored occluder depth by at least the rounding of
//! one store, whatever the step. The margins cover the rasterizer's
//! interpolation, which the format does not change.

use common::street::{look, street_on, Depth};
use glam::Vec3;
use hroc::device::Capabilities;
use hroc::options::Variant;
use hroc::{Culler, CullerDesc, Method, ViewDesc};

mod common;

/// The walk, a cut, the eye in a box and a look over the wall, for a host on `at`: with unclipped
/// depth, the near plane 6 units ahead, so the nearest cubes lie before it.
fn path(at: Depth) -> Vec<(ViewDesc, bool)> {
    let near = if at.unclipped { 6.0 } else { 0.1 };
    let view = |eye: Vec3, target: Vec3| {
        let v = ViewDesc { unclipped_depth: at.unclipped, ..look(eye, target) };
        match at.range {
            hroc::DepthRange::Standard => ViewDesc { proj: glam::Mat4::perspective_rh(1.1, 1.0, near, 200.0), ..v },
            hroc::DepthRange::Reversed => ViewDesc { proj: glam::Mat4::perspective_infinite_reverse_rh(1.1, 1.0, near), ..v },
        }
    };
    let mut path: Vec<(ViewDesc, bool)> = (0..4).map(|k| (view(Vec3::new(-2.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((view(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)), true));
    path.push((view(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    // Above the wall: far cubes peek over its top edge, some by less than
    // a pixel (what one sample of a pixel sees and another does not).
    path.extend([6.5f32, 7.0].map(|y| (view(Vec3::new(0.3, y, 8.0), Vec3::new(0.0, 1.0, -14.0)), false)));
    path
}

/// Every frame of every method family on `at` gives `noc`'s ID image, with
/// the full tier's capabilities and the portable tier's (ID marks, box
/// tests that load depth and compare it themselves).
fn same_picture_as_noc(device: &wgpu::Device, queue: &wgpu::Queue, at: Depth) {
    for caps in [Capabilities::FULL, Capabilities::PORTABLE] {
        same_picture_with(device, queue, at, caps);
    }
}

fn same_picture_with(device: &wgpu::Device, queue: &wgpu::Queue, at: Depth, caps: Capabilities) {
    let (host, objects) = street_on(device, at);
    let culler = Culler::new(device, queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
    let path = path(at);
    let mut truth = culler.view(Method::Noc, &host.targets()).unwrap();
    let pictures: Vec<Vec<u32>> = path
        .iter()
        .map(|&(desc, cut)| {
            host.frame(device, queue, &culler, &mut truth, desc, cut);
            host.ids(device, queue)
        })
        .collect();
    assert!(pictures.iter().all(|p| p.iter().any(|&id| id > 0)), "{at:?}: the street is drawn");
    for method in [Method::Vfc, Method::Hzb, Method::Roc, Method::Ioc, Method::Chc, Method::Hroc(Variant::NA), Method::HROC] {
        let mut view = culler.view(method, &host.targets()).unwrap();
        let mut culled = 0;
        for (k, &(desc, cut)) in path.iter().enumerate() {
            let drawn = host.frame(device, queue, &culler, &mut view, desc, cut);
            let differing = host.ids(device, queue).iter().zip(&pictures[k]).filter(|(a, b)| a != b).count();
            assert_eq!(differing, 0, "{method} on {at:?} ({caps:?}), frame {k}: pixels differ from noc's");
            culled += objects.len() - drawn.len();
        }
        assert!(culled > 0, "{method} on {at:?} ({caps:?}) culled nothing");
    }
}

#[test]
fn every_depth_format_gives_noc_s_picture() {
    let adapter = common::adapter();
    let extra = adapter.features() & wgpu::Features::DEPTH32FLOAT_STENCIL8;
    let (device, queue) = common::device(hroc::device::FULL_FEATURES | extra);
    use wgpu::TextureFormat as F;
    let mut formats = vec![F::Depth16Unorm, F::Depth24Plus, F::Depth24PlusStencil8, F::Depth32Float];
    if !extra.is_empty() {
        formats.push(F::Depth32FloatStencil8);
    }
    for format in formats {
        same_picture_as_noc(&device, &queue, Depth { format, ..Depth::default() });
    }
}

#[test]
fn a_view_on_layer_1_or_mip_1_gives_noc_s_picture() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    same_picture_as_noc(&device, &queue, Depth { layers: 3, layer: 1, ..Depth::default() });
    same_picture_as_noc(&device, &queue, Depth { mips: 2, mip: 1, ..Depth::default() });
    same_picture_as_noc(&device, &queue, Depth { layers: 2, mips: 3, layer: 1, mip: 2, ..Depth::default() });
}

/// Multisampled targets (4× MSAA depth, `Rg16Uint` IDs), standard and
/// reversed, and a layer of an MSAA array where the device has
/// `MULTISAMPLE_ARRAY`: box tests raster at the target's sample count, and
/// every load of depth or IDs reads every sample, so each method gives
/// `noc`'s picture sample for sample.
#[test]
fn msaa_targets_give_noc_s_picture() {
    let adapter = common::adapter();
    assert!(adapter.features().contains(wgpu::Features::MULTISAMPLE_ARRAY), "lavapipe has multisampled arrays");
    let (device, queue) = common::device(hroc::device::FULL_FEATURES | wgpu::Features::MULTISAMPLE_ARRAY);
    for range in [hroc::DepthRange::Standard, hroc::DepthRange::Reversed] {
        same_picture_as_noc(&device, &queue, Depth { range, samples: 4, ..Depth::default() });
    }
    same_picture_as_noc(&device, &queue, Depth { samples: 4, layers: 2, layer: 1, ..Depth::default() });
}

/// The ID target must match the depth target: `R32Uint` or `Rg16Uint`,
/// its size and its sample count; anything else is an error that names
/// what it got.
#[test]
fn an_id_target_unlike_the_depth_target_is_an_error() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street_on(&device, Depth { samples: 4, ..Depth::default() });
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    let size = (common::street::SIZE, common::street::SIZE, 1);
    let ids = |format, samples| common::texture(&device, format, size, 1, samples, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT);
    use wgpu::TextureFormat as F;
    let targets = host.targets();
    assert!(culler.view(Method::HROC, &targets.with_ids(&ids(F::Rg16Uint, 4))).is_ok());
    for (format, samples, named) in [(F::Rg16Uint, 1, "1 sample(s)"), (F::R32Float, 4, "R32Float"), (F::Rgba8Uint, 4, "Rgba8Uint")] {
        let e = culler.view(Method::HROC, &targets.with_ids(&ids(format, samples))).err().expect("an ID target unlike the depth").to_string();
        assert!(e.contains(named) && e.contains("4 sample(s)"), "{e}");
    }
}

/// A layer or mip the depth texture does not have is an error that says so.
#[test]
fn a_layer_or_mip_outside_the_texture_is_an_error() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street_on(&device, Depth { layers: 2, mips: 2, ..Depth::default() });
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    for (layer, mip) in [(2, 0), (0, 2)] {
        let e = culler.view(Method::Hzb, &host.targets().at(layer, mip)).err().expect("outside the texture").to_string();
        assert!(e.contains(&format!("layer {layer} mip {mip}")) && e.contains("2 layers, 2 mips"), "{e}");
    }
    assert!(culler.view(Method::Hzb, &host.targets().at(1, 0)).is_ok());
    // Mip 1 is 32 × 32: the 64 × 64 ID target no longer fits it.
    let e = culler.view(Method::Hzb, &host.targets().at(1, 1)).err().expect("an ID target of another size").to_string();
    assert!(e.contains("32x32"), "{e}");
}

/// A host that biases its depth away from the viewer, as shadow passes do
/// (constant and slope-scaled, positive for standard depth, negative for
/// reversed), gets `noc`'s picture from every method family.
#[test]
fn depth_bias_away_from_the_viewer_gives_noc_s_picture() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    for (range, sign) in [(hroc::DepthRange::Standard, 1), (hroc::DepthRange::Reversed, -1)] {
        let bias = wgpu::DepthBiasState { constant: sign * 200, slope_scale: sign as f32 * 2.0, clamp: 0.0 };
        same_picture_as_noc(&device, &queue, Depth { range, bias, ..Depth::default() });
    }
}

/// A host that clamps depth instead of clipping at the near plane (a
/// shadow pass "pancaking" casters, `unclipped_depth`), with the near plane
/// cutting the street: every method family draws what lies before it.
#[test]
fn unclipped_depth_draws_what_lies_before_the_near_plane() {
    let adapter = common::adapter();
    assert!(adapter.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL), "lavapipe clamps depth");
    let (device, queue) = common::device(hroc::device::FULL_FEATURES | wgpu::Features::DEPTH_CLIP_CONTROL);
    for range in [hroc::DepthRange::Standard, hroc::DepthRange::Reversed] {
        same_picture_as_noc(&device, &queue, Depth { range, unclipped: true, ..Depth::default() });
    }
}

/// Targets are given once, when the view is created; [`hroc::View::resize`]
/// changes them. Another texture of the same shape (a host that alternates
/// two depth textures) keeps the view's visible set: the next frame is no
/// cut, and draws everything `noc` shows there. Another shape starts over
/// as after a cut. A projection whose depth range is not the targets' is
/// refused, naming where the range is given. Views share the culler's
/// pipelines: a second view of a method, and a view moved to another
/// texture of the same shape, make no new module or pipeline (a point
/// light's six faces, made again whenever the engine reallocates its
/// shadow maps).
#[test]
fn a_view_keeps_its_state_across_targets_of_the_same_shape() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (a, objects) = street_on(&device, Depth::default());
    let (b, _) = street_on(&device, Depth::default());
    let (msaa, _) = street_on(&device, Depth { samples: 4, ..Depth::default() });
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    let desc = look(Vec3::new(0.0, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0));
    let cut = |view: &mut hroc::View| view.stats(&culler).unwrap().iter().any(|&(s, v)| s == hroc::stats::Stat::Cut && v > 0.0);
    let mut truth = culler.view(Method::Noc, &b.targets()).unwrap();
    b.frame(&device, &queue, &culler, &mut truth, desc, true);
    let visible = b.visible(&device, &queue);
    assert!(!visible.is_empty());
    for method in [Method::Hzb, Method::HROC] {
        let mut view = culler.view(method, &a.targets()).unwrap();
        let steady = (0..3).map(|k| a.frame(&device, &queue, &culler, &mut view, desc, k == 0)).last().unwrap();
        assert!(!cut(&mut view), "{method}: a steady frame");
        let made = culler.gpu().cache.counts();
        let mut second = culler.view(method, &b.targets()).unwrap();
        b.frame(&device, &queue, &culler, &mut second, desc, true);
        view.resize(&culler, &b.targets()).unwrap();
        assert_eq!(culler.gpu().cache.counts(), made, "{method}: modules and pipelines made by a second view and a resize");
        let drawn = b.frame(&device, &queue, &culler, &mut view, desc, false);
        assert!(!cut(&mut view), "{method}: another texture of the same shape is no cut");
        assert_eq!(drawn, steady, "{method}: the frame after the resize culls as the one before");
        assert!(visible.iter().all(|o| drawn.contains(o)), "{method}: drawn {drawn:?}, noc shows {visible:?}");
        view.resize(&culler, &msaa.targets()).unwrap();
        msaa.frame(&device, &queue, &culler, &mut view, desc, false);
        assert!(cut(&mut view), "{method}: targets of another shape start over");
    }
    let mut view = culler.view(Method::Hzb, &a.targets()).unwrap();
    let reversed = ViewDesc { proj: glam::Mat4::perspective_infinite_reverse_rh(1.1, 1.0, 0.1), ..desc };
    let mut enc = device.create_command_encoder(&Default::default());
    let input = hroc::FrameInput { view: reversed, cut: false, time: 0.0 };
    let e = view.cull(&culler, &mut enc, &input, &mut |_: &mut wgpu::CommandEncoder, _: &hroc::Draw| {}).unwrap_err().to_string();
    assert!(e.contains("Reversed") && e.contains("ViewTargets::depth_range"), "{e}");
}
