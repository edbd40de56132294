//! What validation (`hroc::CullerDesc::validation`) costs: two sessions of
//! one scene on one device, one culler validating and one not, each
//! frame of the path culled by `hzb` and `hroc` in both, in turn, and
//! checked against `noc`. Prints each method's mean ms/frame without and
//! with validation and their ratio, measured side by side in one run.
//!
//! `cargo run --release -p hroc-bench --example validation_cost -- [scene] [objects] [frames]`
//! (defaults: radial-city, its own count, 60 frames at 640 × 360).

use hroc::Method;
use hroc_bench::bench::{warmup_frames, Session, SessionDesc};
use hroc_bench::gpu::Headless;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene_key = args.get(1).map_or("radial-city", String::as_str);
    let objects = args.get(2).map(|n| n.parse().expect("a count of objects"));
    let frames: usize = args.get(3).map_or(60, |n| n.parse().expect("a count of frames"));
    let gpu = Headless::new().expect("a Vulkan device (scripts/ensure-vulkan.sh)");
    let scene = hroc_bench::scene::load(scene_key, objects, 0).expect("a scene");
    let n = scene.objects.len();
    let session = |validate: bool| {
        let desc = SessionDesc { validate, timestamps: false, ..SessionDesc::new(frames, (640, 360)) };
        Session::with(&gpu, scene.clone(), desc).expect("a session")
    };
    let (mut off, mut on) = (session(false), session(true));
    let methods = [Method::Hzb, Method::HROC];
    let mut views: Vec<_> = methods.iter().map(|&m| (off.create(m).expect("a view"), on.create(m).expect("a view"))).collect();
    let warm = warmup_frames(frames);
    let mut ms = vec![(0.0, 0.0); methods.len()];
    for k in 0..frames {
        let (_, truth) = on.truth(k).expect("noc's frame");
        for ((plain, checked), sum) in views.iter_mut().zip(ms.iter_mut()) {
            let a = off.run_frame(plain, k).expect("a frame without validation");
            let b = on.run_frame(checked, k).expect("a frame with validation, and no finding");
            let c = on.check(&b, &truth).expect("a check");
            assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{} frame {k}", checked.method());
            if k >= warm {
                sum.0 += a.wall_ms;
                sum.1 += b.wall_ms;
            }
        }
    }
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    for (_, checked) in views.iter_mut() {
        checked.validation(&on.culler).expect("no finding in the last frames");
    }
    let timed = (frames - warm) as f64;
    println!("{scene_key}, {n} objects, {frames} frames at 640x360 ({warm} warm-up untimed), {}", gpu.adapter_name());
    println!("| method | ms/frame, validation off | on | on / off |");
    println!("|---|--:|--:|--:|");
    for (m, (a, b)) in methods.iter().zip(ms) {
        println!("| {m} | {:.2} | {:.2} | {:.3} |", a / timed, b / timed, b / a);
    }
}
