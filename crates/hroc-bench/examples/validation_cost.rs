//! What validation (`hroc::CullerDesc::validation`) costs `hzb` and
//! `hroc`: each frame culled in a session that validates and in one that
//! does not, side by side in one run ([`hroc_bench::bench::validation_cost`]).
//!
//! `cargo run --release -p hroc-bench --example validation_cost -- [scene] [objects] [frames] [cascades]`
//! (defaults: radial-city, its own count, 60 frames at 640 × 360, no
//! shadow cascades: the default scene of `hroc bench`).

use hroc::Method;
use hroc_bench::bench::validation_cost;
use hroc_bench::gpu::Headless;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let key = args.get(1).map_or("radial-city", String::as_str);
    let objects = args.get(2).map(|n| n.parse().expect("a count of objects"));
    let frames = args.get(3).map_or(60, |n| n.parse().expect("a count of frames"));
    let cascades = args.get(4).map_or(0, |n| n.parse().expect("a count of cascades"));
    let gpu = Headless::new().expect("a Vulkan device (scripts/ensure-vulkan.sh)");
    let scene = hroc_bench::scene::load(key, objects, 0).expect("a scene");
    let costs = validation_cost(&gpu, &scene, frames, &[Method::Hzb, Method::HROC], cascades).unwrap_or_else(|e| panic!("{e}"));
    println!("{key}, {} objects, {frames} frames at 640x360, {cascades} shadow cascades, {}", scene.objects.len(), gpu.adapter_name());
    println!("| method | ms/frame, validation off | on | on / off |");
    println!("|---|--:|--:|--:|");
    for c in costs {
        println!("| {} | {:.2} | {:.2} | {:.3} |", c.method, c.off_ms, c.on_ms, c.on_ms / c.off_ms);
    }
}
