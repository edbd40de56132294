//! The host example on lavapipe (Vulkan) and llvmpipe (GL through EGL): a
//! renderer that is not hroc's, culling through the public API only,
//! checked against the same host drawing everything (`noc`): 0 false
//! negatives, 0 missing pixels, for standard finite and reversed infinite
//! depth, across a camera cut, on both backends and on both tiers. The blended
//! panel behind the wall is culled; the one in front is drawn and hides
//! nothing.

use hroc::device::Capabilities;
use hroc::{DepthRange, Method};
use hroc_forward_host::{open_device, open_device_on, Demo, ForwardHost, Views};

const SIZE: (u32, u32) = (192, 108);

/// One frame of `host`, and what it drew.
fn run(host: &mut ForwardHost, view: glam::Mat4, proj: glam::Mat4, cut: bool) -> hroc_forward_host::FrameOutput {
    host.frame(view, proj, cut).unwrap();
    host.output().unwrap()
}

#[test]
fn forward_host_culls_conservatively() {
    culls_conservatively(wgpu::Backends::VULKAN, None);
}

#[test]
fn forward_host_culls_conservatively_on_gl() {
    culls_conservatively(wgpu::Backends::GL, None);
}

/// The portable tier (an emulated count, ID marks: what DX12 and Metal
/// need), with the host's opaque shader free of hroc lines, on both
/// backends.
#[test]
fn forward_host_culls_conservatively_portable() {
    culls_conservatively(wgpu::Backends::VULKAN, Some(Capabilities::PORTABLE));
    culls_conservatively(wgpu::Backends::GL, Some(Capabilities::PORTABLE));
}

fn culls_conservatively(backends: wgpu::Backends, capabilities: Option<Capabilities>) {
    let (device, queue) = open_device_on(backends).expect("a Vulkan adapter (scripts/ensure-vulkan.sh) and GL through EGL (scripts/ensure-gl.sh)");
    let demo = Demo::new(1500, 16).unwrap();
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    for depth in [DepthRange::Standard, DepthRange::Reversed] {
        let mut truth = ForwardHost::new(&device, &queue, &demo.scene, SIZE, Method::Noc, depth, capabilities).unwrap();
        for method in [Method::HROC, Method::Hzb, Method::Roc, Method::Hroc(hroc::options::Variant::NA), Method::Hroc(hroc::options::Variant::OF)] {
            let mut host = ForwardHost::new(&device, &queue, &demo.scene, SIZE, method, depth, capabilities).unwrap();
            if let Some(caps) = capabilities {
                assert_eq!(host.capabilities(), caps);
            }
            let (mut culled_behind, mut drawn_total, mut all_total) = (0, 0, 0);
            for k in 0..demo.cameras.len() {
                let (view, proj) = demo.matrices(k, aspect, depth);
                let t = run(&mut truth, view, proj, k == demo.cut);
                let f = run(&mut host, view, proj, k == demo.cut);
                let label = format!("{method} {depth:?} frame {k}");
                let false_negatives: Vec<usize> = (0..t.visible.len()).filter(|&o| t.visible[o] && !f.drawn[o]).collect();
                assert!(false_negatives.is_empty(), "{label}: visible objects not drawn: {false_negatives:?}");
                let missing = t.depth.iter().zip(&f.depth).filter(|(a, b)| if depth == DepthRange::Standard { b > a } else { b < a }).count();
                assert_eq!(missing, 0, "{label}: missing pixels");
                assert!(!t.visible[demo.glass_behind], "{label}: the panel behind the wall is visible; the demo is broken");
                if k < demo.cut {
                    assert!(t.visible[demo.glass_front] && f.drawn[demo.glass_front], "{label}: the blended panel in front must be drawn");
                    // From the third frame on, last frame's occluders include the
                    // wall for every method (hzb's first pyramid after frame 0 may
                    // still be coarse around it).
                    if k >= 2 {
                        culled_behind += (!f.drawn[demo.glass_behind]) as usize;
                    }
                }
                drawn_total += f.drawn.iter().filter(|&&d| d).count();
                all_total += f.drawn.len();
            }
            assert_eq!(culled_behind, demo.cut - 2, "{method} {depth:?}: the panel behind the wall must be culled");
            assert!(drawn_total * 2 < all_total, "{method} {depth:?}: drew {drawn_total} of {all_total}: hardly culls");
        }
    }
}

/// A frame of an engine: a 4× MSAA main view and a directional light's
/// shadow map of three cascades, each cascade an orthographic,
/// depth-biased view of the same culler (culled by `hzb`, which needs no ID
/// target, or by `hroc-na`, whose depth-only pass then marks), at standard
/// and reversed-infinite depth, across a camera cut. Every view of every
/// frame is checked against the host drawing everything: the main view has
/// 0 false negatives and 0 missing samples, and each cascade's depth
/// equals the unculled cascade's, bit for bit.
#[test]
fn engine_frame_culls_every_view_conservatively() {
    let (device, queue) = open_device_on(wgpu::Backends::VULKAN).expect("a Vulkan adapter (scripts/ensure-vulkan.sh)");
    let demo = Demo::new(1500, 10).unwrap();
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    for depth in [DepthRange::Standard, DepthRange::Reversed] {
        let all = |m| (m, depth, None);
        let mut truth = ForwardHost::with_views(&device, &queue, &demo.scene, SIZE, all(Method::Noc), Views { shadow_method: Method::Noc, ..Views::ENGINE }).unwrap();
        let setups = [(Method::HROC, Method::Hzb), (Method::Hzb, Method::Hroc(hroc::options::Variant::NA)), (Method::Roc, Method::Hzb)];
        for (method, shadow_method) in setups {
            let mut host = ForwardHost::with_views(&device, &queue, &demo.scene, SIZE, all(method), Views { shadow_method, ..Views::ENGINE }).unwrap();
            let (mut cascade_drawn, mut cascade_all) = (0, 0);
            for k in 0..demo.cameras.len() {
                let (view, proj) = demo.matrices(k, aspect, depth);
                let t = run(&mut truth, view, proj, k == demo.cut);
                let f = run(&mut host, view, proj, k == demo.cut);
                let label = format!("{method} (cascades: {shadow_method}) {depth:?} frame {k}");
                let false_negatives: Vec<usize> = (0..t.visible.len()).filter(|&o| t.visible[o] && !f.drawn[o]).collect();
                assert!(false_negatives.is_empty(), "{label}: visible objects not drawn: {false_negatives:?}");
                assert_eq!(t.depth.len(), (SIZE.0 * SIZE.1 * 4) as usize, "every sample is read");
                let missing = t.depth.iter().zip(&f.depth).filter(|(a, b)| if depth == DepthRange::Standard { b > a } else { b < a }).count();
                assert_eq!(missing, 0, "{label}: missing samples");
                assert_eq!(t.cascade_depth.len(), 3);
                for (c, (a, b)) in t.cascade_depth.iter().zip(&f.cascade_depth).enumerate() {
                    let differing = a.iter().zip(b).filter(|(x, y)| x.to_bits() != y.to_bits()).count();
                    assert_eq!(differing, 0, "{label}, cascade {c}: depth differs from the unculled cascade's");
                    assert!(a.iter().any(|&d| d != if depth == DepthRange::Standard { 1.0 } else { 0.0 }), "{label}, cascade {c} holds casters");
                }
                cascade_drawn += f.cascade_drawn.iter().flatten().filter(|&&d| d).count();
                cascade_all += f.cascade_drawn.iter().map(Vec::len).sum::<usize>();
            }
            assert!(cascade_drawn < cascade_all, "{method} {depth:?}: the cascades culled nothing");
        }
    }
}

/// What a host can get wrong gets a clear error, never a panic.
#[test]
fn host_mistakes_are_clear_errors() {
    use hroc::{Culler, CullerDesc, ObjectDesc, ObjectFlags, ViewTargets};
    let (device, queue) = open_device().expect("a Vulkan adapter");
    let demo = Demo::new(200, 2).unwrap();
    // Timestamps on a device opened without them: the missing features are named.
    let mut desc = CullerDesc::new(&demo.scene.objects);
    desc.timestamps = true;
    let e = Culler::new(&device, &queue, &desc).err().expect("timestamps need features").to_string();
    assert!(e.contains("TIMESTAMP_QUERY"), "{e}");
    // A box that is not finite.
    let mut bad = demo.scene.objects.clone();
    bad[3] = ObjectDesc { bounds: hroc::Aabb::new(glam::Vec3::ZERO, glam::Vec3::splat(f32::NAN)), ..bad[3] };
    let e = Culler::new(&device, &queue, &CullerDesc::new(&bad)).err().expect("NaN box").to_string();
    assert!(e.contains("object 3"), "{e}");
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&demo.scene.objects)).unwrap();
    let tex = |format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d { width: 64, height: 32, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    use wgpu::TextureUsages as U;
    let depth = tex(wgpu::TextureFormat::Depth32Float, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING);
    // HROC's occluder filtering without an ID target.
    let no_ids = ViewTargets::new(&depth, DepthRange::Standard);
    let e = culler.view(Method::HROC, &no_ids).err().expect("OF needs IDs").to_string();
    assert!(e.contains("object-ID target"), "{e}");
    assert!(culler.view(Method::Hroc(hroc::options::Variant::CR), &no_ids).is_ok());
    // A depth target the culler cannot sample.
    let unsampled = tex(wgpu::TextureFormat::Depth32Float, U::RENDER_ATTACHMENT);
    let e = culler.view(Method::Hzb, &ViewTargets::new(&unsampled, DepthRange::Standard)).err().expect("unsampled depth").to_string();
    assert!(e.contains("TEXTURE_BINDING"), "{e}");
    // An ID target of another size.
    let ids = tex(wgpu::TextureFormat::R32Uint, U::RENDER_ATTACHMENT | U::TEXTURE_BINDING);
    let small = device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width: 32, height: 32, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Uint,
        usage: U::TEXTURE_BINDING,
        view_formats: &[],
    });
    assert!(culler.view(Method::HROC, &ViewTargets::new(&depth, DepthRange::Standard).with_ids(&small)).is_err());
    assert!(culler.view(Method::HROC, &ViewTargets::new(&depth, DepthRange::Standard).with_ids(&ids)).is_ok());
    // woc takes standard depth only.
    assert!(culler.view(Method::Woc, &ViewTargets::new(&depth, DepthRange::Reversed)).is_err());
    // Flags of an object out of range.
    let mut culler = culler;
    assert!(culler.set_flags(10_000, ObjectFlags::NEVER_CULL).is_err());
}

/// The host animates objects (a tenth of the city slides, the blended panel
/// in front drifts sideways) through `Culler::set_bounds`: still 0 false
/// negatives and 0 missing pixels on every frame, on both tiers.
#[test]
fn animated_objects_stay_conservative() {
    let (device, queue) = open_device().expect("a Vulkan adapter");
    let demo = Demo::new(1500, 16).unwrap();
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let base: Vec<glam::Mat4> = demo.scene.instances.iter().map(|i| glam::Mat4::from_cols_array_2d(&i.model)).collect();
    let moves = |k: usize| -> Vec<(u32, glam::Mat4)> {
        let t = k as f32 * 0.5;
        let mut m: Vec<(u32, glam::Mat4)> =
            (0..base.len()).step_by(10).map(|i| (i as u32, glam::Mat4::from_translation(glam::Vec3::new(6.0 * (t + i as f32).sin(), 0.0, 4.0 * t.cos())) * base[i])).collect();
        let g = demo.glass_front;
        m.push((g as u32, glam::Mat4::from_translation(glam::Vec3::new(1.5 * t.sin(), 0.0, 0.0)) * base[g]));
        m
    };
    let mut truth = ForwardHost::new(&device, &queue, &demo.scene, SIZE, Method::Noc, DepthRange::Standard, None).unwrap();
    let mut panel_seen = 0;
    for (method, caps) in [(Method::HROC, None), (Method::Hzb, None), (Method::HROC, Some(Capabilities::PORTABLE)), (Method::Roc, Some(Capabilities::PORTABLE))] {
        let mut host = ForwardHost::new(&device, &queue, &demo.scene, SIZE, method, DepthRange::Standard, caps).unwrap();
        for k in 0..demo.cameras.len() {
            let m = moves(k);
            truth.move_objects(&m).unwrap();
            host.move_objects(&m).unwrap();
            let (view, proj) = demo.matrices(k, aspect, DepthRange::Standard);
            let t = run(&mut truth, view, proj, k == demo.cut);
            let f = run(&mut host, view, proj, k == demo.cut);
            let false_negatives: Vec<usize> = (0..t.visible.len()).filter(|&o| t.visible[o] && !f.drawn[o]).collect();
            assert!(false_negatives.is_empty(), "{method} {caps:?} frame {k}: visible moving scene objects not drawn: {false_negatives:?}");
            assert_eq!(t.depth.iter().zip(&f.depth).filter(|(a, b)| b > a).count(), 0, "{method} {caps:?} frame {k}: missing pixels");
            panel_seen += t.visible[demo.glass_front] as usize;
        }
    }
    // The drifting blended panel was in the picture (and so drawn) in at
    // least a quarter of the frames of both runs.
    assert!(panel_seen >= demo.cut, "the blended panel was visible in only {panel_seen} frames");
}

/// The hard path (frame 0, cuts, the eye inside object and group boxes,
/// boxes across the near plane) through the forward host, in both depth
/// conventions, with no cut signal, on both tiers: 0 false negatives, 0
/// missing pixels.
#[test]
fn hard_path_in_both_depth_conventions() {
    let (device, queue) = open_device().expect("a Vulkan adapter");
    let demo = Demo::new(1500, 12).unwrap();
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    for depth in [DepthRange::Reversed, DepthRange::Standard] {
        let mut truth = ForwardHost::new(&device, &queue, &demo.scene, SIZE, Method::Noc, depth, None).unwrap();
        let methods = [Method::HROC, Method::Hzb, Method::Roc, Method::Hroc(hroc::options::Variant::NA)];
        let mut hosts: Vec<ForwardHost> = [None, Some(Capabilities::PORTABLE)]
            .into_iter()
            .flat_map(|caps| methods.map(|m| (m, caps)))
            .map(|(m, caps)| ForwardHost::new(&device, &queue, &demo.scene, SIZE, m, depth, caps).unwrap())
            .collect();
        for k in 0..demo.hard.len() {
            let (view, proj) = demo.hard_matrices(k, aspect, depth);
            let t = run(&mut truth, view, proj, false);
            for host in hosts.iter_mut() {
                let f = run(host, view, proj, false);
                let label = format!("{} {:?} {depth:?} hard frame {k}", host.view.method(), host.capabilities());
                let false_negatives: Vec<usize> = (0..t.visible.len()).filter(|&o| t.visible[o] && !f.drawn[o]).collect();
                assert!(false_negatives.is_empty(), "{label}: visible objects not drawn: {false_negatives:?}");
                let missing = t.depth.iter().zip(&f.depth).filter(|(a, b)| if depth == DepthRange::Standard { b > a } else { b < a }).count();
                assert_eq!(missing, 0, "{label}: missing pixels");
            }
        }
    }
}
