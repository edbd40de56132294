//! The portable tier (`--tier portable`: an emulated draw count, ID marks,
//! box tests that load depth and compare in the fragment stage), what
//! DX12 and Metal need, forced on lavapipe's Vulkan and on llvmpipe's GL.
//! Every method it serves draws every object `noc` shows on the hard and
//! cuts paths of radial-city, factory and satellites, and with objects
//! moving; the methods that read marks read them from the ID target.

use hroc::stats::Stat;
use hroc::Method;
use hroc_bench::bench::{self, BenchOptions};
use hroc_bench::gpu::{Backend, Headless, Tier};

fn portable(backend: Backend) -> Headless {
    let mut gpu = Headless::open(backend).expect("Vulkan (scripts/ensure-vulkan.sh) and OpenGL through EGL (scripts/ensure-gl.sh)");
    gpu.capabilities = Some(Tier::Portable.capabilities());
    gpu
}

fn check(r: &bench::BenchReport, what: &str) {
    assert_eq!(r.capabilities, "portable", "{what}");
    for row in &r.rows {
        assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} {what}", row.method);
        let id_passes = row.stats.get(&Stat::IdPasses).copied().unwrap_or(0.0);
        // auto reads marks in the frames it runs HROC.
        if row.method != Method::Auto {
            assert_eq!(id_passes > 0.0, row.method.reads_marks(), "{} {what}: {id_passes} ID passes per frame", row.method);
        }
    }
}

#[test]
fn portable_tier_on_vulkan_has_no_false_negatives() {
    let gpu = portable(Backend::Vulkan);
    let methods = hroc_bench::bench::parse_methods("noc,vfc,hzb,roc,roc-all,ioc,hroc,hroc-na,hroc-cr,hroc-sf,chc++,auto").unwrap();
    for scene in ["radial-city", "factory", "satellites"] {
        for path in ["hard", "cuts"] {
            let o = BenchOptions { frames: 10, resolution: (160, 90), camera_path: Some(path.into()), ..BenchOptions::new(scene, Some(1000), methods.clone()) };
            check(&bench::run(&gpu, &o).unwrap(), &format!("{scene} {path}"));
        }
    }
    let moving = hroc_bench::bench::parse_methods("noc,hzb,roc,ioc,hroc,hroc-na").unwrap();
    let o = BenchOptions { frames: 10, resolution: (160, 90), moving: 0.1, ..BenchOptions::new("radial-city", Some(1000), moving) };
    let r = bench::run(&gpu, &o).unwrap();
    assert!(r.moved_objects > 0);
    check(&r, "moving");
}

#[test]
fn portable_tier_on_gl_has_no_false_negatives() {
    let gpu = portable(Backend::Gl);
    let methods = hroc_bench::bench::parse_methods("noc,hzb,roc,ioc,hroc,hroc-na,auto").unwrap();
    for path in ["hard", "cuts"] {
        let o = BenchOptions { frames: 10, resolution: (160, 90), camera_path: Some(path.into()), ..BenchOptions::new("radial-city", Some(1000), methods.clone()) };
        check(&bench::run(&gpu, &o).unwrap(), &format!("GL {path}"));
    }
}
