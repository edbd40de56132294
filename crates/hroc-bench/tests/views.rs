//! The views engines cull, through the benchmark: a 4× MSAA camera and a
//! directional light's shadow cascades (orthographic, depth-biased views
//! on layers of one depth array, each checked against its own unculled
//! picture), on the full and the portable tier, and an orthographic
//! camera. Every conservative method that serves them has 0 false
//! negatives and 0 missing pixels (samples, with MSAA) on the scene's own
//! path and the hard path (cuts, the eye inside boxes, boxes across the
//! near plane).

use hroc::Method;
use hroc_bench::bench::{self, BenchOptions, Projection};
use hroc_bench::gpu::{Headless, Tier};

fn methods() -> Vec<Method> {
    hroc_bench::bench::parse_methods("noc,vfc,chc++,roc,ioc,hzb,hroc-na,hroc,auto").unwrap()
}

fn check(gpu: &Headless, o: &BenchOptions, views: usize, label: &str) {
    let r = bench::run(gpu, o).unwrap();
    assert_eq!((r.msaa, r.shadow_cascades, r.projection), (o.msaa, o.shadow_cascades, o.projection));
    for row in &r.rows {
        assert_eq!(row.drawn_per_view.len(), views, "{label}: drawn per view");
        assert_eq!((row.false_negatives, row.missing_pixels), (0, 0), "{} {label}", row.method);
    }
    let (noc, hroc) = (&r.rows[0], r.rows.iter().find(|row| row.method == Method::HROC).unwrap());
    assert!(hroc.drawn_mean < noc.drawn_mean, "{label}: hroc culled nothing");
}

#[test]
fn msaa_cascades_and_orthographic_cameras_have_no_false_negatives() {
    for tier in [None, Some(Tier::Portable)] {
        let mut gpu = Headless::new().expect("a Vulkan adapter (scripts/ensure-vulkan.sh)");
        gpu.capabilities = tier.map(Tier::capabilities);
        for path in [None, Some("hard")] {
            let base = BenchOptions { frames: 10, resolution: (160, 90), camera_path: path.map(Into::into), ..BenchOptions::new("radial-city", Some(1500), methods()) };
            let label = format!("{tier:?}, path {path:?}");
            check(&gpu, &BenchOptions { msaa: 4, ..base.clone() }, 1, &format!("4x MSAA, {label}"));
            check(&gpu, &BenchOptions { shadow_cascades: 3, ..base.clone() }, 4, &format!("3 cascades, {label}"));
            check(&gpu, &BenchOptions { projection: Projection::Orthographic, ..base }, 1, &format!("orthographic, {label}"));
        }
    }
}
