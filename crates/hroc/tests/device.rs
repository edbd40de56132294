//! What the culler asks of a device, and what it says when a device falls
//! short: missing features and limits are errors that name what is needed,
//! methods it cannot serve are refused by name with the reason, and
//! `hroc::features` / `hroc::limits` give a device that serves everything.

use hroc::{Aabb, Capabilities, Culler, CullerDesc, DepthRange, DrawCount, Error, Method, ObjectDesc, ObjectFlags, ViewTargets};

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
    let (device, queue) = common::device_with(hroc::FULL_FEATURES, |_| wgpu::Limits::default());
    let objects = objects();
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).expect("the culler fits wgpu's default limits");
    assert_eq!(culler.capabilities(), Capabilities::FULL);
    let served = culler.methods();
    assert!(served.contains(&Method::HROC) && served.contains(&Method::Hzb) && served.contains(&Method::Roc), "{served:?}");
    assert!(!served.contains(&Method::Ioc), "{served:?}");
    let depth = common::depth_texture(&device, 32);
    let refused = culler.view(Method::Ioc, &ViewTargets { depth: &depth, depth_range: DepthRange::Standard, ids: None }).err().expect("ioc refused");
    let text = refused.to_string();
    assert!(matches!(refused, Error::MethodUnavailable { .. }), "{text}");
    assert!(text.contains("ioc") && text.contains("max_storage_buffers_per_shader_stage") && text.contains("at least 10") && text.contains("it is 8"), "{text}");
}

/// Below what the culler's own passes need, `Culler::new` fails with the
/// limit, the value needed and the device's.
#[test]
fn a_limit_below_the_cullers_own_is_named() {
    let (device, queue) = common::device_with(hroc::FULL_FEATURES, |_| wgpu::Limits { max_storage_buffers_per_shader_stage: 4, ..wgpu::Limits::default() });
    let objects = objects();
    match Culler::new(&device, &queue, &CullerDesc::new(&objects)) {
        Err(Error::DeviceLimit { limit, needed, have, .. }) => assert_eq!((limit, needed, have), ("max_storage_buffers_per_shader_stage", 5, 4)),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("a culler on 4 storage buffers per stage"),
    }
}

/// `hroc::features` and `hroc::limits` give a device that serves every
/// method; asking for more than the device has is an error naming the
/// features; a device with only the required features runs portable and
/// refuses the methods that need early-Z, saying so.
#[test]
fn capabilities_follow_the_device() {
    let adapter = common::adapter();
    assert_eq!(hroc::features(&adapter) & hroc::FULL_FEATURES, hroc::FULL_FEATURES, "lavapipe has the full tier");
    let (device, queue) = common::device_with(hroc::features(&adapter), hroc::limits);
    let objects = objects();
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    assert_eq!(culler.methods(), Method::ALL.to_vec());

    let (device, queue) = common::device(hroc::REQUIRED_FEATURES);
    let culler = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
    assert_eq!(culler.capabilities(), Capabilities { draw_count: DrawCount::Emulated, early_z: false, read_only_depth: true });
    let text = culler.serves(Method::HROC).unwrap_err().to_string();
    assert!(text.contains("hroc") && text.contains("early-Z"), "{text}");
    assert!(culler.serves(Method::Hzb).is_ok() && culler.serves(Method::Chc).is_ok());
    match Culler::new(&device, &queue, &CullerDesc { capabilities: Some(Capabilities::FULL), ..CullerDesc::new(&objects) }) {
        Err(Error::MissingFeatures { missing, .. }) => assert_eq!(missing, wgpu::Features::MULTI_DRAW_INDIRECT_COUNT | wgpu::Features::SHADER_EARLY_DEPTH_TEST),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("the full tier without its features"),
    }
}
