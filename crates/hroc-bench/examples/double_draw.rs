//! Counts objects HROC draws in both of its lists in one frame.
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
fn main() -> hroc_bench::Result<()> {
    let gpu = Headless::new()?;
    let scene = hroc_bench::scene::load("radial-city", Some(2000), 3)?;
    let mut s = Session::new(&gpu, scene, None, 16, (160, 96), Split::Sah)?;
    for m in ["hroc", "hroc-na", "hzb", "roc"] {
        let mut v = s.create(m.parse()?)?;
        let (mut twice, mut drawn) = (0, 0);
        for k in 0..16 {
            let r = s.run_frame(&mut v, k)?;
            let mut n = vec![0u32; s.renderer.object_count as usize];
            for l in &r.lists {
                for cmd in s.gpu.read_list(&l.commands, &l.count, l.max_count)? {
                    if cmd.instance_count > 0 {
                        n[cmd.first_instance as usize] += 1;
                    }
                }
            }
            twice += n.iter().filter(|&&x| x > 1).count();
            drawn += n.iter().filter(|&&x| x > 0).count();
        }
        println!("{m}: {twice} double draws of {drawn} draws over 16 frames");
    }
    Ok(())
}
