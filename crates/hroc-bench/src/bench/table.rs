//! Plain-text and Markdown tables of a bench report.

use super::{BenchReport, InvocationsMean, MethodRow};
use hroc::stats::{Stage, Stat};
use hroc::Method;
use std::collections::BTreeSet;
use std::fmt::Write;

/// Aligned rows, as Markdown or plain text; the first column left-aligned.
fn grid(head: &[String], rows: &[Vec<String>], markdown: bool) -> String {
    // A `|` inside a Markdown cell (|V|) would split it.
    let escaped = |s: &String| if markdown { s.replace('|', "\\|") } else { s.clone() };
    let head: Vec<String> = head.iter().map(escaped).collect();
    let rows: Vec<Vec<String>> = rows.iter().map(|r| r.iter().map(escaped).collect()).collect();
    let (head, rows) = (&head[..], &rows[..]);
    let widths: Vec<usize> = (0..head.len()).map(|i| rows.iter().map(|r| r[i].len()).chain([head[i].len()]).max().unwrap_or(0)).collect();
    let line = |cells: &[String]| {
        let c: Vec<String> = cells.iter().zip(&widths).enumerate().map(|(i, (s, w))| if i == 0 { format!("{s:<w$}") } else { format!("{s:>w$}") }).collect();
        if markdown {
            format!("| {} |", c.join(" | "))
        } else {
            c.join("  ")
        }
    };
    let mut out = String::new();
    let _ = writeln!(out, "{}", line(head));
    if markdown {
        let _ = writeln!(
            out,
            "|{}|",
            widths.iter().enumerate().map(|(i, w)| if i == 0 { format!(":{}", "-".repeat(w + 1)) } else { format!("{}:", "-".repeat(w + 1)) }).collect::<Vec<_>>().join("|")
        );
    }
    for row in rows {
        let _ = writeln!(out, "{}", line(row));
    }
    out
}

/// GPU ms per stage (the paper's Figure 6) and method statistics, per method.
pub fn breakdown(r: &BenchReport, markdown: bool) -> String {
    // In stage order, which is the order a frame runs them.
    let stages: BTreeSet<Stage> = r.rows.iter().flat_map(|row| row.stages_ms.keys().copied()).collect();
    let stats: BTreeSet<Stat> = r.rows.iter().flat_map(|row| row.stats.keys().copied()).collect();
    let mut head = vec!["method".to_string()];
    head.extend(stages.iter().map(|s| format!("{s} ms")));
    head.extend(stats.iter().map(|s| match s {
        Stat::V | Stat::O | Stat::G | Stat::U | Stat::D => format!("|{s}|"),
        Stat::NodesPerRay => "nodes/ray".to_string(),
        _ => s.to_string(),
    }));
    let rows: Vec<Vec<String>> = r
        .rows
        .iter()
        .map(|row| {
            let mut cells = vec![row.method.to_string()];
            cells.extend(stages.iter().map(|s| row.stages_ms.get(s).map_or("-".into(), |v| format!("{v:.2}"))));
            cells.extend(stats.iter().map(|s| row.stats.get(s).map_or("-".into(), |v| if *v >= 100.0 { format!("{v:.0}") } else { format!("{v:.1}") })));
            cells
        })
        .collect();
    grid(&head, &rows, markdown)
}

/// Shader invocations per frame and stage (pipeline statistics), one row
/// per method and stage, then the method's culling stages summed; `None`
/// when no row has them.
pub fn invocations(r: &BenchReport, markdown: bool) -> Option<String> {
    if r.rows.iter().all(|row| row.invocations.is_empty()) {
        return None;
    }
    let head: Vec<String> = ["method", "stage", "vertex", "fragment", "compute"].map(String::from).to_vec();
    let cells = |method: &str, stage: &str, i: &InvocationsMean| vec![method.to_string(), stage.to_string(), count(i.vertex), count(i.fragment), count(i.compute)];
    let mut rows = Vec::new();
    for row in r.rows.iter().filter(|row| !row.invocations.is_empty()) {
        rows.extend(row.invocations.iter().map(|(stage, i)| cells(row.method.name(), stage.name(), i)));
        rows.push(cells(row.method.name(), "(culling stages)", &row.culling_invocations()));
    }
    Some(grid(&head, &rows, markdown))
}

/// A per-frame count, rounded.
fn count(v: f64) -> String {
    format!("{v:.0}")
}

/// The table `hroc bench` prints: one row per method.
pub fn render(r: &BenchReport, markdown: bool) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}scene {} | {} objects | {} triangles | {} | path {}: {} frames, {:.1} per path second ({} warm-up untimed) | BVH {} ({} nodes, {:.1} ms) | {} | {} | {}",
        if markdown { "" } else { "# " },
        r.scene,
        r.objects,
        r.triangles,
        r.resolution,
        r.path,
        r.frames,
        r.frames_per_second,
        r.warmup_frames,
        r.split,
        r.bvh_nodes,
        r.bvh_build_ms,
        r.adapter,
        r.capabilities,
        if r.validated { "validated: no finding" } else { "not validated" }
    );
    if r.projection != super::Projection::Perspective {
        let _ = writeln!(out, "{}an orthographic camera (parallel rays through the perspective frustum's box at the scene centre's distance)", if markdown { "" } else { "# " });
    }
    if r.msaa > 1 || r.shadow_cascades > 0 {
        let per_view = |x: &MethodRow| x.drawn_per_view.iter().map(|d| format!("{d:.0}")).collect::<Vec<_>>().join(" + ");
        let _ = writeln!(
            out,
            "{}views: the camera{}{} | drawn/frame per view: {}",
            if markdown { "" } else { "# " },
            if r.msaa > 1 { format!(" ({}× MSAA)", r.msaa) } else { String::new() },
            if r.shadow_cascades > 0 {
                format!(
                    " and {} shadow cascades (orthographic, depth-biased; every view checked against its own noc picture; the frame's shape summed over the views)",
                    r.shadow_cascades
                )
            } else {
                String::new()
            },
            r.rows.iter().map(|x| format!("{} {}", x.method, per_view(x))).collect::<Vec<_>>().join(", ")
        );
    }
    if r.moved_objects > 0 {
        let _ = writeln!(
            out,
            "{}moving {:.0}% ({} objects, {}) | object update {:.2} ms/frame, of which CPU {:.2} (BVH refit on the {}, {} rebuilds) | SAH cost {} | the bench host's boxes and transforms {:.2} ms/frame",
            if markdown { "" } else { "# " },
            r.moving * 100.0,
            r.moved_objects,
            if r.dynamic { "DYNAMIC: tested alone" } else { "static: refit" },
            r.update_ms_mean,
            r.refit_ms_mean,
            r.refit.to_uppercase(),
            r.rebuilds,
            r.sah_growth.map_or("not tracked by the GPU refit".into(), |g| format!("{g:.2}x as last built")),
            r.host_update_ms_mean
        );
    }
    let head = ["method", "ms/frame", "p95 ms", "GPU ms", "C/N", "C/R", "false neg", "missing px", "drawn/frame", "most drawn", "triangles/frame"];
    let noc = r.rows.iter().find(|x| x.method == Method::Noc).map(|x| x.ms_mean);
    let mut rows: Vec<Vec<String>> = r
        .rows
        .iter()
        .map(|x| {
            vec![
                x.method.to_string(),
                format!("{:.2}", x.ms_mean),
                format!("{:.2}", x.ms_p95),
                x.gpu_ms_mean.map_or("-".into(), |g| format!("{g:.2}")),
                format!("{:.3}", x.c_over_n),
                format!("{:.3}", x.c_over_r),
                x.false_negatives.to_string(),
                x.missing_pixels.to_string(),
                format!("{:.0}", x.drawn_mean),
                x.drawn_max.to_string(),
                format!("{:.0} ({:.1} %)", x.triangles_mean, 100.0 * x.triangles_fraction),
            ]
        })
        .collect();
    let mut head: Vec<String> = head.iter().map(|s| s.to_string()).collect();
    if let Some(noc) = noc {
        head.push("× noc".into());
        for (row, x) in rows.iter_mut().zip(&r.rows) {
            row.push(format!("{:.2}", x.ms_mean / noc));
        }
    }
    out.push_str(&grid(&head, &rows, markdown));
    for x in r.rows.iter().filter(|x| !x.frame_methods.is_empty()) {
        let shares: Vec<String> = x.choices().iter().map(|(m, s)| format!("{m} {:.0} %", 100.0 * s)).collect();
        let probes = x.stats.get(&hroc::stats::Stat::Probe).copied().unwrap_or(0.0) * r.frames as f64;
        let _ = writeln!(out, "\n{} ran: {} of {} frames ({probes:.0} probe frames)", x.method, shares.join(", "), x.frame_methods.len());
    }
    let stray: Vec<String> = r.rows.iter().filter(|x| x.stray_pixels > 0).map(|x| format!("{} {}", x.method, x.stray_pixels)).collect();
    if !stray.is_empty() {
        let _ = writeln!(out, "\nnoc fragments in front of their own object's box (rasterizer strays, not culling misses), not reproduced: {}", stray.join(", "));
    }
    out
}

/// The motion table: each method's ms/frame (and × noc) at every moving
/// fraction of one `hroc bench --moving a,b,c` run, then the shared object
/// update per frame, and each method's frame plus update over its static
/// frame when the first fraction is 0.
pub fn motion(reports: &[BenchReport], markdown: bool) -> String {
    let Some(first) = reports.first() else { return String::new() };
    let (head, rows) = motion_grid(reports);
    let mut out = String::new();
    let _ = writeln!(out, "{}motion: {}", if markdown { "" } else { "# " }, motion_caption(first));
    out.push_str(&grid(&head, &rows, markdown));
    out
}

/// What a motion run held fixed: scene, size, adapter, and how the moving
/// objects were handled.
pub fn motion_caption(first: &BenchReport) -> String {
    format!(
        "scene {} | {} objects | {} | moving objects {} | refit on the {}",
        first.scene,
        first.objects,
        first.adapter,
        if first.dynamic { "DYNAMIC (tested alone)" } else { "static (refit)" },
        first.refit.to_uppercase()
    )
}

/// The motion table's header and rows, shared by `hroc bench --moving` and
/// the report. The last column sums each method's false negatives and
/// missing pixels over every fraction.
pub fn motion_grid(reports: &[BenchReport]) -> (Vec<String>, Vec<Vec<String>>) {
    let mut head = vec!["method".to_string()];
    for r in reports {
        head.push(format!("{:.0}% ms", r.moving * 100.0));
        head.push(format!("{:.0}% × noc", r.moving * 100.0));
    }
    let static_first = reports.first().is_some_and(|r| r.moving == 0.0);
    if static_first {
        for r in &reports[1..] {
            head.push(format!("{:.0}% (+update) / 0%", r.moving * 100.0));
        }
    }
    head.push("false neg / missing px".to_string());
    let Some(first) = reports.first() else { return (head, Vec::new()) };
    let mut rows = Vec::new();
    for m in first.rows.iter().map(|x| x.method) {
        let mut row = vec![m.to_string()];
        let found: Vec<Option<&MethodRow>> = reports.iter().map(|r| r.rows.iter().find(|x| x.method == m)).collect();
        let ms: Vec<Option<f64>> = found.iter().map(|x| x.map(|x| x.ms_mean)).collect();
        for (r, v) in reports.iter().zip(&ms) {
            let noc = r.rows.iter().find(|x| x.method == Method::Noc).map(|x| x.ms_mean);
            row.push(v.map_or("-".into(), |v| format!("{v:.2}")));
            row.push(match (v, noc) {
                (Some(v), Some(n)) if n > 0.0 => format!("{:.3}", v / n),
                _ => "-".into(),
            });
        }
        if static_first {
            for (r, v) in reports.iter().zip(&ms).skip(1) {
                row.push(match (v, ms[0]) {
                    (Some(v), Some(s)) if s > 0.0 => format!("{:.3}", (v + r.update_ms_mean) / s),
                    _ => "-".into(),
                });
            }
        }
        let (fneg, miss) = found.iter().flatten().fold((0, 0), |(f, p), x| (f + x.false_negatives, p + x.missing_pixels));
        row.push(format!("{fneg} / {miss}"));
        rows.push(row);
    }
    let mut upd = vec!["object update".to_string()];
    for r in reports {
        upd.push(format!("{:.2}", r.update_ms_mean));
        upd.push(format!("{} rebuilds", r.rebuilds));
    }
    upd.resize(head.len(), String::new());
    rows.push(upd);
    (head, rows)
}
