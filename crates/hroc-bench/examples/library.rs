//! The library API in a dozen lines: load a scene, open the GPU, run two
//! methods over its camera path and check them against `noc`.
//! `cargo run --release --example library`

use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;

fn main() -> hroc_bench::Result<()> {
    let scene = hroc_bench::scene::load("radial-city", Some(5_000), 0)?;
    let gpu = Headless::new()?;
    let mut s = Session::new(&gpu, scene, None, 30, (640, 360), Split::Sah)?;
    let mut vfc = s.create("vfc".parse().unwrap())?;
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k)?; // noc's visible set and depth
        let frame = s.run_frame(&mut vfc, k)?;
        let check = s.check(&frame, &truth)?;
        println!("frame {k:2}: {:6.2} ms, drew {:5}, false negatives {}", frame.wall_ms, check.drawn, check.false_negatives);
    }
    Ok(())
}
