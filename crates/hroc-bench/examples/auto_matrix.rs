//! `auto` against the best fixed method: radial-city, factory and
//! satellites at 1k, 5k and 20k objects, on their own, hard and cut paths,
//! sampled at 5 and 60 frames per path second; `noc`, `vfc`, `hzb`,
//! `hroc` and `auto` side by side in each run (times are ratios within a
//! run). Prints a row per run (auto's mean and p95 over the best fixed
//! method's, and what auto ran), then the geometric mean and the worst.
//!
//! `--repeat` runs each run a second time and prints the spread of
//! repeated runs: the best fixed method's mean and p95 in the second run
//! over the first, and auto's (the margins auto is held to cannot be
//! finer than these); then the second runs' own figures, and how far one
//! run's `auto` / best ratio varies from run to run.
//!
//! `--record FILE` writes every fixed method's ms and triangles in every
//! frame, for replaying the chooser against them on the CPU
//! (`hroc::cull::auto::chooser::replay`, a test): `run LABEL WARMUP`, then
//! per frame `CUT MS_NOC MS_VFC MS_HZB MS_HROC TRI_NOC TRI_VFC TRI_HZB
//! TRI_HROC`.
//!
//! `cargo run --release -p hroc-bench --example auto_matrix -- [--quick]
//! [--repeat] [--seconds S] [--only TEXT] [--fps 5|60] [--json FILE]
//! [--record FILE]`:
//! `--quick` runs 1k and 5k only, `--only` the runs whose label ("factory
//! 5000 hard 5") holds TEXT, `--fps` one sampling;
//! at 60 frames per path second a run covers the path's first S seconds
//! (default 4: 241 frames).

use hroc::Method;
use hroc_bench::bench::{self, BenchOptions, BenchReport, MethodRow};
use hroc_bench::gpu::Headless;
use hroc_bench::scene::CameraPath;

const FIXED: [Method; 4] = [Method::Noc, Method::Vfc, Method::Hzb, Method::HROC];

fn row(r: &BenchReport, method: Method) -> &MethodRow {
    r.rows.iter().find(|row| row.method == method).unwrap_or_else(|| panic!("no {method} row"))
}

/// Appends run `label` of `r` in `--record`'s format.
fn record(out: &mut String, label: &str, r: &BenchReport) {
    use std::fmt::Write;
    let rows: Vec<&MethodRow> = FIXED.iter().map(|&m| row(r, m)).collect();
    let cuts = &row(r, Method::Auto).cut_frames;
    let _ = writeln!(out, "run {label} {}", r.warmup_frames);
    for k in 0..r.frames {
        let ms: Vec<String> = rows.iter().map(|x| format!("{:.4}", x.frame_ms[k])).collect();
        let tri: Vec<String> = rows.iter().map(|x| x.frame_triangles[k].to_string()).collect();
        let _ = writeln!(out, "{} {} {}", cuts.contains(&k) as u8, ms.join(" "), tri.join(" "));
    }
}

/// The geometric mean of `v` (not empty).
fn geometric_mean(v: impl ExactSizeIterator<Item = f64>) -> f64 {
    let n = v.len() as f64;
    (v.map(f64::ln).sum::<f64>() / n).exp()
}

/// The path's first `seconds`.
fn first_seconds(path: &CameraPath, seconds: f32) -> CameraPath {
    let t0 = path.keys.first().map_or(0.0, |k| k.t);
    CameraPath::new(path.keys.iter().filter(|k| k.t <= t0 + seconds + 1e-4).cloned().collect())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let repeat = args.iter().any(|a| a == "--repeat");
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let only = value("--only");
    let only_fps: Option<f32> = value("--fps").map(|s| s.parse()).transpose()?;
    let seconds: f32 = value("--seconds").map_or(Ok(4.0), |s| s.parse())?;
    let gpu = Headless::new()?;
    let sizes: &[usize] = if quick { &[1000, 5000] } else { &[1000, 5000, 20000] };
    let methods = bench::parse_methods("noc,vfc,hzb,hroc,auto")?;
    println!("# {} | {}", gpu.adapter_name(), if quick { "quick" } else { "full" });
    let again = if repeat { " best again / first | p95 again / first | auto again / first |" } else { "" };
    println!("| scene | objects | path | fps | frames | best fixed | its ms | auto ms | auto/best | its p95 | auto p95 | p95 ratio | auto ran |{again}");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|{}", if repeat { "---|---|---|" } else { "" });
    let mut spreads: Vec<(f64, f64, String)> = Vec::new();
    let mut auto_spreads: Vec<f64> = Vec::new();
    // The second runs' `auto` over their own best fixed method: mean and p95.
    let mut second_runs: Vec<(f64, f64, String)> = Vec::new();
    let (mut logs, mut worst, mut p95_worst) = (Vec::new(), (0.0f64, String::new()), (0.0f64, String::new()));
    let mut reports = Vec::new();
    let mut recorded = String::new();
    for scene_key in ["radial-city", "factory", "satellites"] {
        for &n in sizes {
            for path_name in ["own", "hard", "cuts"] {
                for fps in [5.0f32, 60.0].into_iter().filter(|&f| only_fps.is_none_or(|o| o == f)) {
                    let label = format!("{scene_key} {n} {path_name} {fps}");
                    if only.as_ref().is_some_and(|o| !label.contains(o.as_str())) {
                        continue;
                    }
                    let camera_path = (path_name != "own").then(|| path_name.into());
                    let o = BenchOptions { fps: Some(fps), camera_path, validate: false, ..BenchOptions::new(scene_key, Some(n), methods.clone()) };
                    let (scene, path) = bench::load_inputs(&o)?;
                    let path = path.unwrap_or_else(|| scene.path.clone());
                    let path = if fps > 30.0 { first_seconds(&path, seconds) } else { path };
                    let r = bench::run_scene(&gpu, &o, scene.clone(), Some(path.clone()))?;
                    for x in &r.rows {
                        assert_eq!((x.false_negatives, x.missing_pixels), (0, 0), "{} {scene_key} {n} {path_name} {fps}", x.method);
                    }
                    let best = FIXED.iter().map(|&m| row(&r, m)).min_by(|a, b| a.ms_mean.total_cmp(&b.ms_mean)).expect("fixed methods");
                    let auto = row(&r, Method::Auto);
                    let (ratio, p95) = (auto.ms_mean / best.ms_mean, auto.ms_p95 / best.ms_p95);
                    let ran: Vec<String> = auto.choices().iter().map(|(m, s)| format!("{m} {:.0}%", 100.0 * s)).collect();
                    // The same run again.
                    let again = if repeat {
                        let r2 = bench::run_scene(&gpu, &o, scene, Some(path))?;
                        let (b2, a2) = (row(&r2, best.method), row(&r2, Method::Auto));
                        spreads.push((b2.ms_mean / best.ms_mean, b2.ms_p95 / best.ms_p95, label.clone()));
                        auto_spreads.push(a2.ms_mean / auto.ms_mean);
                        let best2 = FIXED.iter().map(|&m| row(&r2, m)).min_by(|a, b| a.ms_mean.total_cmp(&b.ms_mean)).expect("fixed methods");
                        second_runs.push((a2.ms_mean / best2.ms_mean, a2.ms_p95 / best2.ms_p95, label.clone()));
                        format!(" {:.3} | {:.3} | {:.3} |", b2.ms_mean / best.ms_mean, b2.ms_p95 / best.ms_p95, a2.ms_mean / auto.ms_mean)
                    } else {
                        String::new()
                    };
                    println!(
                        "| {scene_key} | {n} | {path_name} | {fps} | {} | {} | {:.2} | {:.2} | {ratio:.3} | {:.2} | {:.2} | {p95:.3} | {} |{again}",
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
                        p95_worst = (p95, label.clone());
                    }
                    record(&mut recorded, &label, &r);
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
    if !spreads.is_empty() {
        let geo = geometric_mean(spreads.iter().map(|s| s.0));
        let far = |f: fn(&(f64, f64, String)) -> f64| {
            spreads.iter().map(|s| (f(s).max(1.0 / f(s)), &s.2)).max_by(|a, b| a.0.total_cmp(&b.0)).map(|(x, l)| (x, l.clone())).unwrap_or_default()
        };
        let ((mean_far, mean_at), (p95_far, p95_at)) = (far(|s| s.0), far(|s| s.1));
        let auto_far = auto_spreads.iter().map(|&x| x.max(1.0 / x)).fold(1.0, f64::max);
        println!("spread of repeated runs (the best fixed method again / first): geometric mean {geo:.3}; farthest {mean_far:.3} ({mean_at}); farthest p95 {p95_far:.3} ({p95_at}); auto again / first: farthest {auto_far:.3}");
        // The same figures over the second runs, and the noise of one
        // run's ratio: the standard deviation of ln(second / first) over √2.
        let geo2 = geometric_mean(second_runs.iter().map(|s| s.0));
        let worst2 = second_runs.iter().max_by(|a, b| a.0.total_cmp(&b.0)).map(|s| (s.0, s.2.clone())).unwrap_or_default();
        let p95_2 = second_runs.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map(|s| (s.1, s.2.clone())).unwrap_or_default();
        let d: Vec<f64> = second_runs.iter().zip(&logs).map(|(s, f)| s.0.ln() - f).collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sd = (d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (d.len().max(2) - 1) as f64).sqrt();
        println!(
            "second runs: geometric mean {geo2:.3}; worst {:.3} ({}); worst p95 ratio {:.3} ({}); a run's auto / best varies by {:.3} (standard deviation of its logarithm)",
            worst2.0,
            worst2.1,
            p95_2.0,
            p95_2.1,
            sd / std::f64::consts::SQRT_2
        );
    }
    if let Some(file) = value("--record") {
        std::fs::write(file, recorded)?;
    }
    if let Some(file) = value("--json") {
        std::fs::write(file, serde_json::to_string_pretty(&reports)?)?;
    }
    Ok(())
}
