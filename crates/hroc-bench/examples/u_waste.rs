//! Which meshes HROC tests positive (U) without being visible: where C/R is lost.
use hroc::testing::cull::hroc::Hroc;
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use std::collections::BTreeMap;

fn main() -> hroc_bench::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let key = args.get(1).map(String::as_str).unwrap_or("factory");
    let scene = hroc_bench::scene::load(key, Some(10000), 0)?;
    let gpu = Headless::new()?;
    let mut s = Session::new(&gpu, scene, None, 150, (640, 360), Split::Sah)?;
    let mut h = s.create("hroc-of".parse().unwrap())?;
    let mut waste: BTreeMap<String, (u32, u32)> = BTreeMap::new();
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k)?;
        s.run_frame(&mut h, k)?;
        let dbg = h.method_state::<Hroc>().unwrap().debug_state(&core_gpu(&gpu))?;
        for (o, &u) in dbg.occludees.iter().enumerate() {
            if u {
                let name = s.scene.meshes[s.scene.objects[o].mesh as usize].name.clone();
                let e = waste.entry(name).or_default();
                if truth.visible.binary_search(&(o as u32)).is_ok() {
                    e.0 += 1
                } else {
                    e.1 += 1
                }
            }
        }
    }
    let mut v: Vec<_> = waste.into_iter().collect();
    v.sort_by_key(|(_, (_, w))| std::cmp::Reverse(*w));
    for (name, (vis, w)) in v.iter().take(12) {
        println!("{name:<24} U visible {vis:6}  U hidden {w:6}");
    }
    Ok(())
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
