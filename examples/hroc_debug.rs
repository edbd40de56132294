//! Finds frames where an HROC variant misses objects and explains why.
use hroc::bench::Session;
use hroc::bvh::Split;
use hroc::cull::hroc::{cpu, Hroc, Variant};
use hroc::gpu::Gpu;

fn main() -> hroc::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let key = args.get(1).map(String::as_str).unwrap_or("radial-city");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5000);
    let frames: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(30);
    let scene = hroc::scene::load(key, Some(n), 0)?;
    let gpu = Gpu::new()?;
    let mut s = Session::new(&gpu, scene, None, frames, (640, 360), Split::Sah)?;
    let mut h = Hroc::new("hroc-na", Variant::parse("hroc-na").unwrap(), &s.context())?;
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k)?;
        let r = s.run_frame(&mut h, k)?;
        let chk = s.check(&r, &truth)?;
        if chk.false_negatives == 0 && chk.missing_pixels == 0 {
            continue;
        }
        let drawn = s.drawn(&r.lists)?;
        let dbg = h.debug_state(&gpu)?;
        let cam = s.cameras[k];
        println!("frame {k}: fn {} missing {} eye {:?}", chk.false_negatives, chk.missing_pixels, cam.eye);
        let planes = hroc::scene::camera::frustum_planes(&cam.view_proj(s.renderer.aspect()));
        let (cg, forced) = cpu::groups(&s.bvh, &cpu::node_states(&s.bvh, &dbg.occluders), &planes, cam.near, cam.eye, cpu::pixel_angle(&cam.ray_dirs(s.renderer.aspect()), cam.near, s.renderer.targets.height));
        println!("  groups gpu {} cpu {} equal {}; forced {}", dbg.groups.len(), cg.len(), cg == dbg.groups, forced.len());
        for &o in truth.visible.iter().filter(|&&o| !drawn[o as usize]) {
            let leaf = s.bvh.leaf_of_object[o as usize];
            let mut chain = vec![];
            let mut m = leaf;
            loop {
                chain.push((m, dbg.state[m as usize], dbg.groups.binary_search(&m).is_ok()));
                match s.bvh.parent(m) { Some(p) => m = p, None => break }
            }
            println!("  missed object {o} box {:?} O {} U {} chain (node,state,group) {:?}", s.scene.objects[o as usize].bounds, dbg.occluders[o as usize], dbg.occludees[o as usize], &chain[..chain.len().min(8)]);
        }
    }
    Ok(())
}
