//! What the culler asks of a device, and what it says when a device falls
//! short: missing features and limits are errors that name what is needed,
//! methods it cannot serve are refused by name with the reason, and
//! `hroc::device::features` / `hroc::device::limits` give a device that serves everything.

use glam::Vec3;
use hroc::device::{Capabilities, DrawCount, Marks};
use hroc::{Aabb, Culler, CullerDesc, DepthRange, Error, Method, ObjectDesc, ObjectFlags, ViewTargets};

mod common;

fn objects() -> Vec<ObjectDesc> {
    (0..64)
        .map(|i| {
            let c = glam::Vec3::new((i % 8) as f32, 0.0, -((i / 8) as f32) * 2.0);
            ObjectDesc { bounds: Aabb::new(c, c + glam::Vec3::ONE), index_count: 36, first_index: 0, base_vertex: 0, flags: ObjectFlags::NONE, oriented: None }
        })
        .collect()
}

/// wgpu's default limits allow 8 storage buffers per stage: the culler and
/// every method but IOC (10) fit; IOC is refused with the limit and the
/// value it needs, before any GPU work.
#[test]
fn default_limits_serve_every_method_but_ioc_and_name_what_ioc_needs() {
    let (device, queue) = common::device_with(hroc::device::FULL_FEATURES, |_| wgpu::Limits::default());
    let objects = objects();
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).expect("the culler fits wgpu's default limits");
    assert_eq!(culler.capabilities(), Capabilities::FULL);
    let served = culler.methods();
    assert!(served.contains(&Method::HROC) && served.contains(&Method::Hzb) && served.contains(&Method::Roc), "{served:?}");
    assert!(!served.contains(&Method::Ioc), "{served:?}");
    let depth = common::depth_texture(&device, 32);
    let refused = culler.view(Method::Ioc, &ViewTargets::new(&depth, DepthRange::Standard)).err().expect("ioc refused");
    let text = refused.to_string();
    assert!(matches!(refused, Error::MethodUnavailable { .. }), "{text}");
    assert!(text.contains("ioc") && text.contains("max_storage_buffers_per_shader_stage") && text.contains("at least 10") && text.contains("it is 8"), "{text}");
}

/// Below what the culler's own passes need, `Culler::new` fails with the
/// limit, the value needed and the device's.
#[test]
fn a_limit_below_the_cullers_own_is_named() {
    let (device, queue) = common::device_with(hroc::device::FULL_FEATURES, |_| wgpu::Limits { max_storage_buffers_per_shader_stage: 4, ..wgpu::Limits::default() });
    let objects = objects();
    match Culler::new(&device, &queue, &CullerDesc::new(&objects)) {
        Err(Error::DeviceLimit { limit, needed, have, .. }) => assert_eq!((limit, needed, have), ("max_storage_buffers_per_shader_stage", 7, 4)),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("a culler on 4 storage buffers per stage"),
    }
}

/// `hroc::device::features` and `hroc::device::limits` give a device that serves every
/// method; asking for more than the device has is an error naming the
/// features; a device with only the required features (what Metal offers)
/// runs with an emulated count and ID marks: its shaders compile without
/// early-Z, it serves every method but HROC's rounds (refused, saying
/// why), it asks for the ID target where marks are read, and its frames
/// draw every visible object.
#[test]
fn capabilities_follow_the_device() {
    let adapter = common::adapter();
    assert_eq!(hroc::device::features(&adapter) & hroc::device::FULL_FEATURES, hroc::device::FULL_FEATURES, "lavapipe has the full tier");
    let (device, queue) = common::device_with(hroc::device::features(&adapter), hroc::device::limits);
    let objects = objects();
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    assert_eq!(culler.methods(), Method::ALL.to_vec());

    let (device, queue) = common::device(hroc::device::REQUIRED_FEATURES);
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    assert_eq!(culler.capabilities(), Capabilities { draw_count: DrawCount::Emulated, marks: Marks::Ids, read_only_depth: true });
    let served = culler.methods();
    assert!(served.contains(&Method::HROC) && served.contains(&Method::Roc) && served.contains(&Method::Hzb) && served.contains(&Method::Chc), "{served:?}");
    let rounds = hroc::MethodOptions { hroc_rounds: 2, ..Default::default() };
    let text = culler.serves_with(Method::HROC, &rounds).unwrap_err().to_string();
    assert!(text.contains("hroc") && text.contains("rounds") && text.contains("SHADER_EARLY_DEPTH_TEST"), "{text}");
    let depth = common::depth_texture(&device, 32);
    let no_ids = ViewTargets::new(&depth, DepthRange::Standard);
    let text = culler.view(Method::Roc, &no_ids).err().expect("roc without an ID target").to_string();
    assert!(text.contains("roc") && text.contains("ViewTargets::ids"), "{text}");
    assert!(culler.view(Method::RocAll, &no_ids).is_ok(), "roc-all reads no marks");
    match Culler::new(&device, &queue, &CullerDesc { capabilities: Some(Capabilities::FULL), ..CullerDesc::new(&objects) }) {
        Err(Error::MissingFeatures { missing, .. }) => assert_eq!(missing, wgpu::Features::MULTI_DRAW_INDIRECT_COUNT | wgpu::Features::SHADER_EARLY_DEPTH_TEST),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("the full tier without its features"),
    }
}

/// On a device without forced early-Z, the culler's shaders compile and a
/// host whose fragment shader has no hroc line is culled conservatively:
/// every object that owns a pixel when everything is drawn is drawn.
#[test]
fn a_device_without_early_z_culls_conservatively() {
    use common::street::{look, street};
    let (device, queue) = common::device(hroc::device::REQUIRED_FEATURES);
    let (host, objects) = street(&device);
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    assert_eq!(culler.capabilities().marks, Marks::Ids);
    let mut path: Vec<(hroc::ViewDesc, bool)> = (0..4).map(|k| (look(Vec3::new(-2.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)), true));
    path.push((look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    let visible = host.visible_along(&device, &queue, &culler, &path);
    for method in [Method::Roc, Method::RocAll, Method::Ioc, Method::Chc, Method::Hroc(hroc::options::Variant::NA), Method::HROC] {
        let mut view = culler.view(method, &host.targets()).unwrap();
        let culled = host.draws_visible_along(&device, &queue, &culler, &mut view, &path, &visible, &method.to_string());
        assert!(culled > 0, "{method} culled nothing");
        let stats = view.frame_stats(&culler).expect("the last frame's statistics");
        assert_eq!(stats.id_passes > 0, method.reads_marks(), "{method}: {stats:?}");
    }
}
