//! Draws one object alone at one frame and prints its depth and ID around a
//! pixel: tells a rasterizer's stray fragment from a culling miss.
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;

fn main() -> hroc_bench::Result<()> {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize| a[i].parse::<usize>().unwrap();
    let (key, n, frames, k, obj, px, py) = (&a[1], arg(2), arg(3), arg(4), arg(5) as u32, arg(6) as i64, arg(7) as i64);
    let scene = hroc_bench::scene::load(key, Some(n), 0)?;
    let gpu = Headless::new()?;
    let mut s = Session::new(&gpu, scene, None, frames, (640, 360), Split::Sah)?;
    let mut r = s.create("ref".parse().unwrap())?;
    r.set_oracle(&s.culler, &[obj])?;
    s.run_frame(&mut r, k)?;
    let ids: Vec<u32> = gpu.read_texture(&s.renderer.targets.id, wgpu::TextureAspect::All)?;
    let depth = s.read_depth()?;
    for y in py - 2..=py + 2 {
        let row: Vec<String> = (px - 3..=px + 3)
            .map(|x| {
                let i = (y * 640 + x) as usize;
                if ids[i] == 0 {
                    "    -     ".into()
                } else {
                    format!("{:.7}", depth[i])
                }
            })
            .collect();
        println!("y {y}: {}", row.join(" "));
    }
    let all: Vec<usize> = (0..ids.len()).filter(|&i| ids[i] != 0).collect();
    let (lo, hi) = all.iter().fold((1f32, 0f32), |(l, h), &i| (l.min(depth[i]), h.max(depth[i])));
    println!("object {obj} alone: {} pixels, depth {lo:.7}..{hi:.7}", all.len());
    Ok(())
}
