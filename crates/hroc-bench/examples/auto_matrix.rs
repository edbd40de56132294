//! `auto` against the best fixed method: radial-city, factory and
//! satellites at 1k, 5k and 20k objects, on their own, hard and cut paths,
//! sampled at 5 and 60 frames per path second; `noc`, `vfc`, `hzb`,
//! `hroc` and `auto` side by side in each run (times are ratios within a
//! run). Prints a row per run (auto's mean and p95 over the best fixed
//! method's, and what auto ran), then the geometric mean and the worst.
//!
//! `cargo run --release -p hroc-bench --example auto_matrix -- [--quick]
//! [--seconds S] [--json FILE]`: `--quick` runs 1k and 5k only; at 60
//! frames per path second a run covers the path's first S seconds
//! (default 4: 241 frames).

use std::path::Path;

use hroc_bench::bench::{self, BenchOptions, BenchReport, MethodRow};
use hroc_bench::cull::Method;
use hroc_bench::gpu::Headless;
use hroc_bench::scene::CameraPath;

const FIXED: [Method; 4] = [Method::Noc, Method::Vfc, Method::Hzb, Method::HROC];

fn row(r: &BenchReport, method: Method) -> &MethodRow {
    r.rows.iter().find(|row| row.method == method).unwrap_or_else(|| panic!("no {method} row"))
}

/// The path's first `seconds`.
fn first_seconds(path: &CameraPath, seconds: f32) -> CameraPath {
    let t0 = path.keys.first().map_or(0.0, |k| k.t);
    CameraPath::new(path.keys.iter().filter(|k| k.t <= t0 + seconds + 1e-4).cloned().collect())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let seconds: f32 = value("--seconds").map_or(Ok(4.0), |s| s.parse())?;
    let gpu = Headless::new()?;
    let sizes: &[usize] = if quick { &[1000, 5000] } else { &[1000, 5000, 20000] };
    let methods = bench::parse_methods("noc,vfc,hzb,hroc,auto")?;
    println!("# {} | {}", gpu.adapter_name(), if quick { "quick" } else { "full" });
    println!("| scene | objects | path | fps | frames | best fixed | its ms | auto ms | auto/best | its p95 | auto p95 | p95 ratio | auto ran |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let (mut logs, mut worst, mut p95_worst) = (Vec::new(), (0.0f64, String::new()), (0.0f64, String::new()));
    let mut reports = Vec::new();
    for scene_key in ["radial-city", "factory", "satellites"] {
        for &n in sizes {
            for path_name in ["own", "hard", "cuts"] {
                for fps in [5.0f32, 60.0] {
                    let o = BenchOptions { fps: Some(fps), ..BenchOptions::new(scene_key, Some(n), methods.clone()) };
                    let (scene, _) = bench::load_inputs(&o)?;
                    let path = match path_name {
                        "own" => scene.path.clone(),
                        spec => bench::load_path(&scene, Path::new(spec))?,
                    };
                    let path = if fps > 30.0 { first_seconds(&path, seconds) } else { path };
                    let r = bench::run_scene(&gpu, &o, scene, Some(path))?;
                    for x in &r.rows {
                        assert_eq!((x.false_negatives, x.missing_pixels), (0, 0), "{} {scene_key} {n} {path_name} {fps}", x.method);
                    }
                    let best = FIXED.iter().map(|&m| row(&r, m)).min_by(|a, b| a.ms_mean.total_cmp(&b.ms_mean)).expect("fixed methods");
                    let auto = row(&r, Method::Auto);
                    let (ratio, p95) = (auto.ms_mean / best.ms_mean, auto.ms_p95 / best.ms_p95);
                    let ran: Vec<String> = auto.choices().iter().map(|(m, s)| format!("{m} {:.0}%", 100.0 * s)).collect();
                    let label = format!("{scene_key} {n} {path_name} {fps}");
                    println!(
                        "| {scene_key} | {n} | {path_name} | {fps} | {} | {} | {:.2} | {:.2} | {ratio:.3} | {:.2} | {:.2} | {p95:.3} | {} |",
                        r.frames,
                        best.method,
                        best.ms_mean,
                        auto.ms_mean,
                        best.ms_p95,
                        auto.ms_p95,
                        ran.join(", ")
                    );
                    logs.push(ratio.ln());
                    if ratio > worst.0 {
                        worst = (ratio, label.clone());
                    }
                    if p95 > p95_worst.0 {
                        p95_worst = (p95, label);
                    }
                    reports.push(r);
                }
            }
        }
    }
    let geo = (logs.iter().sum::<f64>() / logs.len() as f64).exp();
    println!(
        "\nauto over the best fixed method: geometric mean {geo:.3} over {} runs; worst {:.3} ({}); worst p95 ratio {:.3} ({})",
        logs.len(),
        worst.0,
        worst.1,
        p95_worst.0,
        p95_worst.1
    );
    if let Some(file) = value("--json") {
        std::fs::write(file, serde_json::to_string_pretty(&reports)?)?;
    }
    Ok(())
}
