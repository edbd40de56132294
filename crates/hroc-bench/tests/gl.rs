//! The culler on a second driver: wgpu's GL backend on Mesa's llvmpipe,
//! through EGL without a display. It has no indirect draw count (the
//! culler emulates it), no read-only depth attachments (HROC's test
//! compares depth itself) and no depth copies (read-backs go through a
//! shader), and its own rasterizer. Every method it serves draws every
//! object `noc` shows, on the scene's own path, the hard path (cuts, the
//! eye inside boxes, boxes across the near plane) and the cuts path, and
//! with objects moving, and culls a directional light's shadow cascades.
//! (Both depth conventions on GL: the forward host's test.)

use hroc::device::DrawCount;
use hroc::Method;
use hroc_bench::bench::{self, BenchOptions};
use hroc_bench::gpu::{Backend, Headless};

#[test]
fn gl_serves_its_methods_with_no_false_negatives() {
    let gpu = Headless::open(Backend::Gl).expect("OpenGL through EGL (scripts/ensure-gl.sh)");
    assert_eq!(gpu.info.backend, wgpu::Backend::Gl);
    let methods = hroc_bench::bench::parse_methods("noc,vfc,hzb,roc,hroc,hroc-na,chc++,auto").unwrap();
    for path in [None, Some("hard"), Some("cuts")] {
        let o = BenchOptions { frames: 12, resolution: (160, 90), camera_path: path.map(Into::into), ..BenchOptions::new("radial-city", Some(1500), methods.clone()) };
        let r = bench::run(&gpu, &o).unwrap();
        assert_eq!(r.capabilities, "gl", "the GL backend runs with what wgpu gives GL");
        for row in &r.rows {
            assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} on GL, path {path:?}", row.method);
        }
        let hroc = r.rows.iter().find(|row| row.method == Method::HROC).unwrap();
        assert!(hroc.drawn_mean < r.objects as f64 / 2.0, "hroc culled little on GL: {}", hroc.drawn_mean);
    }
    // A tenth of the objects moving every frame (refit on the CPU and the
    // GPU's boxes), for the methods that follow motion.
    let moving = hroc_bench::bench::parse_methods("noc,vfc,hzb,roc,hroc").unwrap();
    let o = BenchOptions { frames: 12, resolution: (160, 90), moving: 0.1, ..BenchOptions::new("radial-city", Some(1500), moving) };
    let r = bench::run(&gpu, &o).unwrap();
    assert!(r.moved_objects > 0);
    for row in &r.rows {
        assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} on GL, moving", row.method);
    }
    // What it cannot serve, it refuses by name: HROC's rounds sample the
    // depth they test against while it is attached.
    let mut s = hroc_bench::bench::Session::load(&gpu, "radial-city", Some(200), None, 2, (64, 36), hroc::bvh::Split::Sah).unwrap();
    assert_eq!(s.culler.capabilities().draw_count, DrawCount::Emulated);
    assert!(s.culler.serves(Method::HROC).is_ok() && s.culler.serves(Method::Hzb).is_ok());
    s.options = hroc::MethodOptions { hroc_rounds: 3, ..Default::default() };
    let text = s.create(Method::HROC).err().expect("rounds refused on GL").to_string();
    assert!(text.contains("hroc") && text.contains("READ_ONLY_DEPTH_STENCIL"), "{text}");
    // Asking for the full tier on GL is an error that names what is missing.
    let objects = hroc_bench::render::object_descs(&s.scene);
    let full = hroc::CullerDesc { capabilities: Some(hroc::device::Capabilities::FULL), ..hroc::CullerDesc::new(&objects) };
    let text = hroc::Culler::new(&gpu.device, &gpu.queue, &full).err().expect("the full tier refused on GL").to_string();
    assert!(text.contains("MULTI_DRAW_INDIRECT_COUNT") || text.contains("READ_ONLY_DEPTH_STENCIL"), "{text}");
    // wgpu's GL backend samples neither multisampled textures nor a layer
    // other than 0 of an array: such views are refused by name, and the
    // light's cascades (a texture each on GL) cull with 0 false negatives.
    let o = BenchOptions { frames: 2, resolution: (64, 36), msaa: 4, ..BenchOptions::new("radial-city", Some(200), hroc_bench::bench::parse_methods("noc,hzb").unwrap()) };
    let Err(e) = bench::run(&gpu, &o) else { panic!("MSAA refused on GL") };
    let text = e.to_string();
    assert!(text.contains("4 samples") && text.contains("GL"), "{text}");
    let depth = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width: 64, height: 36, depth_or_array_layers: 2 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let text = s.culler.view(Method::Hzb, &hroc::ViewTargets::new(&depth, hroc::DepthRange::Standard).at(1, 0)).err().expect("layer 1 refused on GL").to_string();
    assert!(text.contains("layer 1") && text.contains("GL"), "{text}");
    assert!(s.culler.view(Method::Hzb, &hroc::ViewTargets::new(&depth, hroc::DepthRange::Standard)).is_ok());
    let methods = hroc_bench::bench::parse_methods("noc,vfc,hzb,roc,hroc").unwrap();
    let o = BenchOptions { frames: 8, resolution: (160, 90), shadow_cascades: 2, ..BenchOptions::new("radial-city", Some(1500), methods) };
    let r = bench::run(&gpu, &o).unwrap();
    for row in &r.rows {
        assert_eq!(row.drawn_per_view.len(), 3, "the camera and two cascades");
        assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} on GL with shadow cascades", row.method);
    }
}

/// Marks from boxes (`Marks::Boxes`, as the Bevy plugin culls) on GL,
/// where the box tests load depth themselves: the methods that read marks
/// draw every object `noc` shows on the hard path (cuts, the eye inside
/// boxes, boxes across the near plane) and the cuts path.
#[test]
fn gl_marks_from_boxes_with_no_false_negatives() {
    let mut gpu = Headless::open(Backend::Gl).expect("OpenGL through EGL (scripts/ensure-gl.sh)");
    let caps = hroc::device::Capabilities { marks: hroc::device::Marks::Boxes, ..hroc_bench::gpu::Tier::Gl.capabilities() };
    gpu.capabilities = Some(caps);
    let methods = hroc_bench::bench::parse_methods("noc,roc,hroc,hroc-na,hroc-sf").unwrap();
    for path in ["hard", "cuts"] {
        let o = BenchOptions { frames: 12, resolution: (160, 90), camera_path: Some(path.into()), ..BenchOptions::new("radial-city", Some(1500), methods.clone()) };
        let r = bench::run(&gpu, &o).unwrap();
        assert!(r.capabilities.contains("Boxes marks"), "{}", r.capabilities);
        for row in &r.rows {
            assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} on GL with marks from boxes, path {path}", row.method);
        }
        let sf = r.rows.iter().find(|row| row.method.to_string() == "hroc-sf").unwrap();
        assert!(sf.drawn_mean < r.objects as f64 / 2.0, "hroc-sf culled little on GL with marks from boxes: {}", sf.drawn_mean);
    }
}
