//! A view's frames need no submit of their own: every frame records what
//! it writes into the host's encoder and maps its read-backs when that
//! encoder is submitted. Two frames in one encoder, two encoders submitted
//! together, and an encoder dropped unsubmitted all leave every frame with
//! `noc`'s image (0 missing pixels), raise no validation error, and the
//! statistics of the frames submitted arrive.

use common::street::{look, read_ids, street, Host};
use glam::Vec3;
use hroc::{Culler, CullerDesc, Method, View, ViewDesc};

mod common;

/// Records one frame of `view` into `enc` and a copy of its ID image.
fn frame(device: &wgpu::Device, host: &Host, culler: &Culler, enc: &mut wgpu::CommandEncoder, view: &mut View, desc: ViewDesc) -> wgpu::Buffer {
    host.record(device, enc, culler, view, desc, false);
    host.copy_ids(device, enc)
}

#[test]
fn frames_may_share_an_encoder_be_submitted_late_or_be_dropped() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let (host, objects) = street(&device);
    let culler = Culler::new(&device, &queue, &CullerDesc { validation: true, ..CullerDesc::new(&objects) }).unwrap();
    // Along the street, where the wall hides most cubes; from above, where
    // the cubes behind it show; and turned away from all of them. Each
    // pair recorded before one submit differs, so a frame culled with the
    // other's view would miss pixels.
    let along = |k: f32| look(Vec3::new(-3.0 + k, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0));
    let above = look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0));
    let away = look(Vec3::new(0.0, 1.5, 8.0), Vec3::new(0.0, 1.5, 30.0));
    let mut truth_view = culler.view(Method::Noc, &host.targets()).unwrap();
    let mut truth = |desc: ViewDesc| {
        host.frame(&device, &queue, &culler, &mut truth_view, desc, false);
        host.ids(&device, &queue)
    };
    let lit = |ids: &[u32]| ids.iter().filter(|&&i| i > 0).count();
    assert!(lit(&truth(above)) > lit(&truth(along(0.0))) / 2, "the cubes show from above");
    assert!(truth(away) != truth(above) && truth(along(0.0)) != truth(above), "the views differ");

    for method in Method::ALL.into_iter().filter(|m| m.is_conservative() && !m.is_benchmark_only()) {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut view = culler.view(method, &host.targets()).unwrap();
        let new_encoder = || device.create_command_encoder(&Default::default());
        // (ID image copied after the frame, the frame's view)
        let mut images = Vec::new();
        // Frame 0 alone.
        let mut enc = new_encoder();
        images.push((frame(&device, &host, &culler, &mut enc, &mut view, along(0.0)), along(0.0)));
        queue.submit([enc.finish()]);
        // Frames 1 and 2 in one encoder.
        let mut enc = new_encoder();
        images.push((frame(&device, &host, &culler, &mut enc, &mut view, above), above));
        images.push((frame(&device, &host, &culler, &mut enc, &mut view, away), away));
        queue.submit([enc.finish()]);
        // Frames 3 to 5 recorded, their encoders dropped (as many as the
        // view keeps read-backs in flight).
        for k in 0..3 {
            let mut enc = new_encoder();
            frame(&device, &host, &culler, &mut enc, &mut view, along(1.0 + k as f32 / 3.0));
            drop(enc);
        }
        // Frames 6 and 7 in their own encoders, both recorded before either
        // is submitted. A view that never submits takes them submitted in
        // reverse. One that submits mid-frame refuses frame 7: its submit
        // would run ahead of frame 6's end.
        let (mut e6, mut e7) = (new_encoder(), new_encoder());
        images.push((frame(&device, &host, &culler, &mut e6, &mut view, along(2.0)), along(2.0)));
        if method.submits_mid_frame() {
            let mut lists = 0;
            let culled = view.cull(&culler, &mut e7, &hroc::FrameInput { view: along(3.0), cut: false, time: 0.0 }, &mut |_: &mut wgpu::CommandEncoder, _: &hroc::Draw| lists += 1);
            assert!(matches!(culled, Err(hroc::Error::SubmitOrder(_))), "{method}: frame 7 culled ahead of frame 6's end: {culled:?}");
            drop(e7);
            queue.submit([e6.finish()]);
        } else {
            images.push((frame(&device, &host, &culler, &mut e7, &mut view, along(3.0)), along(3.0)));
            queue.submit([e7.finish()]);
            queue.submit([e6.finish()]);
        }
        // Then one frame as usual.
        let mut enc = new_encoder();
        images.push((frame(&device, &host, &culler, &mut enc, &mut view, above), above));
        queue.submit([enc.finish()]);

        let got: Vec<Vec<u32>> = images.iter().map(|(image, _)| read_ids(&device, &queue, image)).collect();
        assert!(pollster::block_on(scope.pop()).is_none(), "{method}: a validation error");
        for (k, ((_, desc), got)) in images.iter().zip(&got).enumerate() {
            let want = truth(*desc);
            let missing = want.iter().zip(got).filter(|(w, g)| w != g).count();
            assert_eq!(missing, 0, "{method} image {k}: {missing} pixels differ from noc's");
        }
        // The dropped frames hold no read-back: the next frame's statistics
        // arrive.
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let drawn = host.frame(&device, &queue, &culler, &mut view, along(0.0), false);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let stats = view.frame_stats(&culler).expect("the statistics of submitted frames arrive");
        assert_eq!(stats.frame, if method.submits_mid_frame() { 8 } else { 9 }, "{method}: the newest statistics");
        assert_eq!(stats.objects as usize, drawn.len(), "{method}: the objects drawn");
    }
}
