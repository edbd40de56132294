//! What marks from boxes (`hroc::device::Marks::Boxes`: the host's shaders
//! do not mark, as in an engine's depth prepass) cost `roc`, `hroc-sf`
//! and `hroc` against the host's early-Z marks: C/R and ms per frame,
//! side by side in one run ([`hroc_bench::bench::marks_cost`]).
//!
//! `cargo run --release -p hroc-bench --example marks_cost -- [scene] [objects] [frames]`
//! (defaults: radial-city, its own count, 60 frames at 640 × 360: the
//! default scene of `hroc bench`).

use hroc::options::Variant;
use hroc::Method;
use hroc_bench::bench::marks_cost;
use hroc_bench::gpu::Headless;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let key = args.get(1).map_or("radial-city", String::as_str);
    let objects = args.get(2).map(|n| n.parse().expect("a count of objects"));
    let frames = args.get(3).map_or(60, |n| n.parse().expect("a count of frames"));
    let gpu = Headless::new().expect("a Vulkan device (scripts/ensure-vulkan.sh)");
    let scene = hroc_bench::scene::load(key, objects, 0).expect("a scene");
    let costs = marks_cost(&gpu, &scene, frames, &[Method::Roc, Method::Hroc(Variant::SF), Method::HROC]).unwrap_or_else(|e| panic!("{e}"));
    println!("{key}, {} objects, {frames} frames at 640x360, {}", scene.objects.len(), gpu.adapter_name());
    println!("| method | C/R, host marks | boxes | ms/frame, host marks | boxes | boxes / host ms |");
    println!("|---|--:|--:|--:|--:|--:|");
    for c in costs {
        println!("| {} | {:.3} | {:.3} | {:.2} | {:.2} | {:.3} |", c.method, c.host_cr, c.boxes_cr, c.host_ms, c.boxes_ms, c.boxes_ms / c.host_ms);
    }
}
