//! Finds frames where an HROC variant misses objects and explains why.
use hroc::testing::cull::hroc::{cpu, Hroc};
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;

fn main() -> hroc_bench::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let key = args.get(1).map(String::as_str).unwrap_or("radial-city");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5000);
    let frames: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(30);
    let variant = args.get(4).map(String::as_str).unwrap_or("hroc-na");
    let mut scene = hroc_bench::scene::load(key, Some(n), 0)?;
    // LOOSE=1: the transformed mesh boxes instead of the tight ones, to compare.
    if std::env::var_os("LOOSE").is_some() {
        for o in scene.objects.iter_mut() {
            o.bounds = scene.meshes[o.mesh as usize].bounds.transformed(&o.transform);
        }
    }
    let gpu = Headless::new()?;
    let mut s = Session::new(&gpu, scene, None, frames, (640, 360), Split::Sah)?;
    let mut h = s.create(variant.parse()?)?;
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k)?;
        let noc_ids: Vec<u32> = gpu.read_texture(&s.renderer.targets.id, wgpu::TextureAspect::All)?;
        let r = s.run_frame(&mut h, k)?;
        let chk = s.check(&r, &truth)?;
        if chk.false_negatives == 0 && chk.missing_pixels == 0 {
            continue;
        }
        let drawn = s.drawn(&r.lists)?;
        let dbg = h.method_state::<Hroc>().unwrap().debug_state(&core_gpu(&gpu))?;
        let cam = s.cameras[k];
        println!("frame {k}: fn {} missing {} eye {:?}", chk.false_negatives, chk.missing_pixels, cam.eye);
        let size = (s.renderer.targets.width, s.renderer.targets.height);
        let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(s.renderer.aspect()), unclipped_depth: false }.geometry()?;
        let (cg, forced) = cpu::groups(s.bvh(), &cpu::node_states(s.bvh(), &dbg.occluders), &g, cpu::pixel_angle_xy(&g, size), h.method_state::<Hroc>().unwrap().test_scale());
        println!("  groups gpu {} cpu {} equal {}; forced {}", dbg.groups.len(), cg.len(), cg == dbg.groups, forced.len());
        for &o in truth.visible.iter().filter(|&&o| !drawn[o as usize]) {
            let leaf = s.bvh().leaf_of_object[o as usize];
            let mut chain = vec![];
            let mut m = leaf;
            loop {
                chain.push((m, dbg.state[m as usize], dbg.groups.binary_search(&m).is_ok()));
                match s.bvh().parent(m) {
                    Some(p) => m = p,
                    None => break,
                }
            }
            let b = s.scene.objects[o as usize].bounds;
            let mesh = &s.scene.meshes[s.scene.objects[o as usize].mesh as usize].name;
            println!(
                "  mesh {mesh}: eye-box distance {:.4} (eye inside {}), box extent {:?}",
                (cam.eye.clamp(b.min, b.max) - cam.eye).length(),
                b.contains_point(cam.eye),
                b.extent()
            );
            let depth = s.read_depth()?;
            let (w, hh) = (s.renderer.targets.width, s.renderer.targets.height);
            let vp = cam.view_proj(s.renderer.aspect());
            let rd = cam.ray_dirs(s.renderer.aspect());
            let pa = cpu::pixel_angle(&g, size);
            for (i, _) in noc_ids.iter().enumerate().filter(|(_, &id)| id == o + 1) {
                let (x, y) = (i as u32 % w, i as u32 / w);
                let ndc = glam::Vec2::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / hh as f32 * 2.0);
                let dir = (rd * glam::Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
                let c0 = vp * cam.eye.extend(1.0);
                let c1 = vp * dir.extend(0.0);
                let hit = |bx: hroc_bench::scene::Aabb| {
                    let (t0, t1) = ((bx.min - cam.eye) / dir, (bx.max - cam.eye) / dir);
                    let (en, ex) = (t0.min(t1).max_element(), t0.max(t1).min_element());
                    let t = en.max(1.0);
                    (en, ex, (c0.z + t * c1.z) / (c0.w + t * c1.w))
                };
                println!("  pixel ({x},{y}) noc depth {:.9} method depth {:.9}", truth.depth[i], depth[i]);
                println!("    rock box {:?} padded {:?}", hit(b), hit(cpu::padded(b, cam.eye, pa)));
                for &(node, _, g) in &chain {
                    if g {
                        println!("    group {node} padded {:?}", hit(cpu::padded(s.bvh().aabb(node), cam.eye, pa)));
                    }
                }
            }
            println!(
                "  missed object {o} box {:?} O {} U {} chain (node,state,group) {:?}",
                s.scene.objects[o as usize].bounds,
                dbg.occluders[o as usize],
                dbg.occludees[o as usize],
                &chain[..chain.len().min(8)]
            );
        }
    }
    Ok(())
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
