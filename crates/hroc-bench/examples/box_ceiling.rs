//! The most any box-based occlusion test can cull: every object whose box
//! a pixel's ray enters no deeper than the final depth (`noc`'s, which no
//! culler's occlusion map can beat) must be drawn by a conservative test
//! of that box. Prints, averaged over the scene's own path, the visible
//! objects (`ref`), and the objects and C/R of that per-pixel test against
//! the final depth with world-axis boxes (the BVH's, HROC's) and with each
//! object's box in its own frame (its mesh or cluster box under its
//! transform, an oriented box). Beside them, `hroc-of`'s own frames: last
//! frame's visible set V, drawn untested, and how much of it is hidden.
//!
//! `cargo run --release --example box_ceiling -- --scene satellites --objects 20000 [--clusters 256] [--frames 60]`

use clap::Parser;
use glam::{Mat4, Vec2, Vec4};
use hroc_bench::bench::{parse_resolution, Session};
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use hroc_bench::scene::{Aabb, ClusterOptions};
use rayon::prelude::*;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "satellites")]
    scene: String,
    #[arg(long)]
    objects: Option<usize>,
    /// Triangles per cluster (none: whole meshes).
    #[arg(long)]
    clusters: Option<u32>,
    #[arg(long, default_value_t = 60)]
    frames: usize,
    #[arg(long, default_value = "640x360", value_parser = parse_resolution)]
    resolution: (u32, u32),
}

fn main() -> hroc_bench::Result<()> {
    let a = Args::parse();
    let gpu = Headless::new()?;
    let mut scene = hroc_bench::scene::load(&a.scene, a.objects, 0)?;
    if let Some(t) = a.clusters {
        scene = scene.clustered(ClusterOptions::new(t))?;
    }
    // Each object's box in its own frame, and the inverse of that frame.
    let local: Vec<(Aabb, Mat4)> = scene
        .objects
        .iter()
        .map(|o| {
            let m = &scene.meshes[o.mesh as usize];
            (o.cluster.map_or(m.bounds, |c| m.clusters[c as usize].bounds), o.transform.inverse())
        })
        .collect();
    let n = scene.objects.len();
    let (w, h) = a.resolution;
    let mut s = Session::new(&gpu, scene, None, a.frames, a.resolution, Split::Sah)?;
    let aspect = s.renderer.aspect();
    let (mut visible, mut world, mut oriented) = (0usize, 0usize, 0usize);
    let mut hroc = s.create("hroc-of".parse().unwrap())?;
    let (mut v, mut v_hidden, mut drawn) = (0usize, 0usize, 0usize);
    for k in 0..s.cameras.len() {
        let (_, truth) = s.truth(k)?;
        let r = s.run_frame(&mut hroc, k)?;
        drawn += s.check(&r, &truth)?.drawn;
        let occluders = hroc.method_state::<hroc::testing::cull::hroc::Hroc>().expect("hroc-of").debug_state(&core_gpu(s.gpu))?.occluders;
        let mut own_pixel = vec![false; n];
        truth.visible.iter().for_each(|&o| own_pixel[o as usize] = true);
        v += occluders.iter().filter(|&&x| x).count();
        v_hidden += (0..n).filter(|&o| occluders[o] && !own_pixel[o]).count();
        let cam = s.cameras[k];
        let g = hroc::ViewDesc { view: cam.view(), proj: cam.proj(aspect), unclipped_depth: false }.geometry()?;
        let bvh = s.bvh();
        let c0 = g.view_proj * g.eye.extend(1.0);
        // Per pixel centre: the leaves whose world box the ray enters in
        // front of the final depth, and which of those have their own box
        // entered there too.
        let rows: Vec<(Vec<u32>, Vec<u32>)> = (0..h)
            .into_par_iter()
            .map(|y| {
                let (mut wb, mut ob) = (Vec::new(), Vec::new());
                for x in 0..w {
                    let ndc = Vec2::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / h as f32 * 2.0);
                    let dir = (g.ray_dirs * Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
                    let c1 = g.view_proj * dir.extend(0.0);
                    let limit = truth.depth[(y * w + x) as usize];
                    let in_front = |b: Aabb, eye: glam::Vec3, dir: glam::Vec3| {
                        let (t0, t1) = ((b.min - eye) / dir, (b.max - eye) / dir);
                        let t = t0.min(t1).max_element().max(1.0);
                        let exit = t0.max(t1).min_element();
                        !(exit < t || exit.is_nan()) && (c0.z + t * c1.z) / (c0.w + t * c1.w) <= limit
                    };
                    let mut stack = vec![0u32];
                    while let Some(node) = stack.pop() {
                        if !in_front(bvh.aabb(node), g.eye, dir) {
                            continue;
                        }
                        match (bvh.object(node), bvh.children(node)) {
                            (Some(o), _) => {
                                wb.push(o);
                                let (b, inv) = local[o as usize];
                                // An affine map keeps the ray parameter t.
                                if in_front(b, inv.transform_point3(g.eye), inv.transform_vector3(dir)) {
                                    ob.push(o);
                                }
                            }
                            (_, Some([l, r])) => stack.extend([l, r]),
                            _ => {}
                        }
                    }
                }
                (wb, ob)
            })
            .collect();
        let (mut wm, mut om) = (vec![false; n], vec![false; n]);
        for (wb, ob) in rows {
            wb.into_iter().for_each(|o| wm[o as usize] = true);
            ob.into_iter().for_each(|o| om[o as usize] = true);
        }
        visible += truth.visible.len();
        world += wm.iter().filter(|&&x| x).count();
        oriented += om.iter().filter(|&&x| x).count();
    }
    let f = s.cameras.len() as f64;
    let culled_by_ref = n as f64 - visible as f64 / f;
    let c_over_r = |drawn: usize| (n as f64 - drawn as f64 / f) / culled_by_ref;
    println!("# {} | {n} objects | {} frames | {w}x{h}", a.scene, s.cameras.len());
    println!("| test against the final depth, per pixel | objects drawn/frame | C/R |");
    println!("|:--|--:|--:|");
    println!("| ref (objects that own a pixel) | {:.0} | 1.000 |", visible as f64 / f);
    println!("| world-axis boxes | {:.0} | {:.3} |", world as f64 / f, c_over_r(world));
    println!("| each object's own box (oriented) | {:.0} | {:.3} |", oriented as f64 / f, c_over_r(oriented));
    println!("| hroc-of (its own occlusion maps) | {:.0} | {:.3} |", drawn as f64 / f, c_over_r(drawn));
    println!("hroc-of: |V| {:.0} per frame, of which {:.0} own no pixel this frame", v as f64 / f, v_hidden as f64 / f);
    Ok(())
}

/// The culler's own GPU helper on the bench's device (for its debug read-backs).
fn core_gpu(g: &hroc_bench::gpu::Headless) -> hroc::testing::gpu::Gpu {
    hroc::testing::gpu::Gpu::from_device(&g.device, &g.queue)
}
