//! The report's tables and figures, in the papers' order, from the
//! measurements of one run.

use std::path::Path;

use super::doc::{Doc, Table};
use super::{hroc_variants, ReportData, SceneResult};
use crate::bench::plot::{self, LinePlot, Series, StackedBars};
use crate::bench::{BenchReport, MethodRow};
use crate::error::Result;
use hroc::stats::{Stage, Stat};
use hroc::Method;

const PLOT: (u32, u32) = (900, 500);

/// GPU ms of the stages that do not draw scene geometry. `None` for the
/// query methods, whose queries and draws share one stage.
pub fn culling_ms(row: &MethodRow) -> Option<f64> {
    if row.stages_ms.contains_key(&Stage::QueriesAndDraws) {
        return None;
    }
    // fold, not sum: an empty f64 sum is -0.0, which prints as "-0.00".
    Some(row.stages_ms.iter().filter(|(k, _)| !k.draws_scene()).fold(0.0, |a, (_, v)| a + v))
}

fn row(r: &BenchReport, method: Method) -> Option<&MethodRow> {
    r.rows.iter().find(|x| x.method == method)
}

fn ms(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.2}")
    }
}

pub fn build(d: &ReportData, plots: &Path) -> Result<Doc> {
    let mut doc = Doc { title: "hroc report".into(), ..Default::default() };
    header(&mut doc, d);
    scenes_table(&mut doc, d);
    frame_times(&mut doc, d);
    accelerations(&mut doc, d);
    splits(&mut doc, d);
    efficiency(&mut doc, d);
    per_frame_plots(&mut doc, d, plots)?;
    breakdown(&mut doc, d, plots)?;
    overdraw(&mut doc, d);
    sweep(&mut doc, d, plots)?;
    hires(&mut doc, d);
    motion(&mut doc, d);
    clusters(&mut doc, d);
    Ok(doc)
}

fn header(doc: &mut Doc, d: &ReportData) {
    let m = &d.meta;
    doc.para(format!(
        "**{}** ({}, {}, driver {}) · {} · hroc {} · {} frames over each 10 s camera path at {} · measured in {:.1} min · {}.",
        m.adapter,
        m.device_type,
        m.backend,
        m.driver,
        m.date,
        m.version,
        m.frames,
        m.resolution,
        m.minutes,
        if m.validated { "every view's draws validated, no finding (`--validate`)" } else { "not validated (`--validate` checks every view's draws)" }
    ));
    doc.code(m.command.clone());
    let warm = d.scenes.first().map_or(0, |s| s.main.warmup_frames);
    doc.para(format!(
        "ms/frame: wall time from the camera upload to the GPU's completion, averaged over the path after {warm} untimed warm-up frames (the paper's §5.1 leaves out 4). \
         C/N: culled objects over all objects; C/R: culled objects over the objects `ref` culls (hidden or outside the view). \
         Every frame of every method is checked against `noc`: false negatives (objects `noc` shows that the method did not draw) and missing pixels (pixels whose depth is farther than `noc`'s) must be 0 for a conservative method."
    ));
}

fn scenes_table(doc: &mut Doc, d: &ReportData) {
    doc.heading("Scenes (Lee's thesis, Table 1)");
    let mut t = Table::new(&["scene", "objects", "meshes", "triangles", "vertices", "extent (m)", "BVH nodes", "depth sah/mid/eq", "build ms sah/mid/eq"]);
    for s in &d.scenes {
        let by = |f: &dyn Fn(&super::BvhInfo) -> String| s.bvh.iter().map(f).collect::<Vec<_>>().join(" / ");
        t.row(vec![
            s.spec.clone(),
            s.stats.objects.to_string(),
            s.stats.meshes.to_string(),
            s.stats.triangles.to_string(),
            s.stats.vertices.to_string(),
            format!("{:.0} × {:.0} × {:.0}", s.extent[0], s.extent[1], s.extent[2]),
            s.bvh.first().map_or("-".into(), |b| b.nodes.to_string()),
            by(&|b| b.depth.to_string()),
            by(&|b| format!("{:.1}", b.build_ms)),
        ]);
    }
    doc.table(t);
}

/// Methods in the order of the first scene's run.
fn methods(d: &ReportData) -> Vec<Method> {
    d.scenes.first().map(|s| s.main.rows.iter().map(|r| r.method).collect()).unwrap_or_default()
}

fn scene_head(first: &str, d: &ReportData) -> Vec<String> {
    std::iter::once(first.to_string()).chain(d.scenes.iter().map(|s| s.spec.clone())).collect()
}

fn frame_times(doc: &mut Doc, d: &ReportData) {
    doc.heading("Frame time (HROC paper Table 1)");
    doc.para("Mean ms per frame, and in brackets the ratio to `noc` measured in the same run (frames of all methods interleaved).");
    let mut t = Table { head: scene_head("method", d), rows: Vec::new() };
    for m in methods(d) {
        let mut cells = vec![m.to_string()];
        for s in &d.scenes {
            let noc = row(&s.main, Method::Noc).map(|r| r.ms_mean);
            cells.push(match (row(&s.main, m), noc) {
                (Some(r), Some(n)) if n > 0.0 => format!("{} ({:.2}×)", ms(r.ms_mean), r.ms_mean / n),
                (Some(r), _) => ms(r.ms_mean),
                _ => "-".into(),
            });
        }
        t.row(cells);
    }
    doc.table(t);
}

fn accelerations(doc: &mut Doc, d: &ReportData) {
    let present: Vec<Method> = hroc_variants().into_iter().filter(|&v| d.scenes.iter().all(|s| row(&s.main, v).is_some())).collect();
    if present.is_empty() {
        return;
    }
    doc.heading("HROC accelerations (HROC paper Table 3)");
    doc.para("NA: no acceleration; CR: counter read-back (draw counts read back and used as `max_count`); OF: occluder filtering (next V = objects owning a pixel). Speed-up = NA ms / variant ms.");
    let mut head = vec!["scene".to_string()];
    head.extend(present.iter().map(|v| format!("{v} ms")));
    head.extend(present.iter().skip(1).map(|v| format!("{v} speed-up")));
    let mut t = Table { head, rows: Vec::new() };
    for s in &d.scenes {
        let v: Vec<f64> = present.iter().filter_map(|&m| row(&s.main, m)).map(|r| r.ms_mean).collect();
        let mut cells = vec![s.spec.clone()];
        cells.extend(v.iter().map(|&x| ms(x)));
        cells.extend(v.iter().skip(1).map(|&x| format!("{:.2}×", v[0] / x)));
        t.row(cells);
    }
    doc.table(t);
}

fn splits(doc: &mut Doc, d: &ReportData) {
    if d.scenes.iter().all(|s| s.splits.is_empty()) {
        return;
    }
    doc.heading("BVH splits (Lee's thesis, Table 4)");
    doc.para("HROC variants' ms/frame with BVHs built by the surface area heuristic (SAH), the middle of the longest axis (MID) and equal counts (EQ); C/R of `hroc-cr+of`. Each split is its own run: compare rows through their `noc` ms, measured in the same run.");
    let mut head = vec!["scene".to_string(), "split".to_string(), "noc ms".to_string()];
    head.extend(hroc_variants().iter().map(|v| format!("{v} ms")));
    head.push("C/R cr+of".into());
    let mut t = Table { head, rows: Vec::new() };
    for s in &d.scenes {
        for r in std::iter::once(&s.main).chain(&s.splits) {
            let mut cells = vec![s.spec.clone(), r.split.clone(), row(r, Method::Noc).map_or("-".into(), |x| ms(x.ms_mean))];
            cells.extend(hroc_variants().iter().map(|&v| row(r, v).map_or("-".into(), |x| ms(x.ms_mean))));
            cells.push(row(r, Method::Hroc(hroc::options::Variant::CR_OF)).map_or("-".into(), |x| format!("{:.3}", x.c_over_r)));
            t.row(cells);
        }
    }
    doc.table(t);
}

fn efficiency(doc: &mut Doc, d: &ReportData) {
    doc.heading("Culling efficiency (Lee et al. 2021 Table 4; Lee's thesis, Table 5)");
    doc.para("C/N / C/R per scene (`ref` has C/R = 1 by definition). Then false negatives / missing pixels summed over all frames.");
    let mut t = Table { head: scene_head("method", d), rows: Vec::new() };
    let mut f = Table { head: scene_head("method", d), rows: Vec::new() };
    for m in methods(d) {
        let cells = |g: &dyn Fn(&MethodRow) -> String| std::iter::once(m.to_string()).chain(d.scenes.iter().map(|s| row(&s.main, m).map_or("-".into(), g))).collect::<Vec<_>>();
        t.row(cells(&|r| format!("{:.3} / {:.3}", r.c_over_n, r.c_over_r)));
        f.row(cells(&|r| format!("{} / {}", r.false_negatives, r.missing_pixels)));
    }
    doc.table(t);
    doc.table(f);
}

fn per_frame_plots(doc: &mut Doc, d: &ReportData, plots: &Path) -> Result<()> {
    doc.heading("Frame time along the path (Lee et al. 2021 Figure 5; Lee's thesis, Figure 15)");
    let mut imgs = Vec::new();
    for s in &d.scenes {
        let series: Vec<Series> = s
            .main
            .rows
            .iter()
            .map(|r| Series { name: r.method.to_string(), points: r.frame_ms.iter().enumerate().skip(s.main.warmup_frames).map(|(k, &v)| (k as f64, v)).collect() })
            .collect();
        let title = format!("{}: ms per frame", s.spec);
        let fig = plot::line_plot(&LinePlot { title: &title, x_label: "frame", y_label: "ms", series: &series, log_x: false, log_y: false }, PLOT)?;
        let frames_stem = format!("frames-{}", stem(&s.spec));
        fig.save(plots, &frames_stem)?;
        imgs.push((format!("plots/{frames_stem}.svg"), format!("{} ({} objects)", s.spec, s.stats.objects)));
        // What auto ran each frame: the methods as levels, cheapest draw at the top.
        for r in s.main.rows.iter().filter(|r| !r.frame_methods.is_empty()) {
            let levels = [Method::Noc, Method::Vfc, Method::Hzb];
            let level = |m: &Method| levels.iter().position(|l| l == m).unwrap_or(levels.len()) as f64;
            let points: Vec<(f64, f64)> = r.frame_methods.iter().enumerate().map(|(k, m)| (k as f64, level(m))).collect();
            let series = [Series { name: format!("{} (0 noc, 1 vfc, 2 hzb, 3 hroc)", r.method), points }];
            let title = format!("{}: the method {} ran", s.spec, r.method);
            let fig = plot::line_plot(&LinePlot { title: &title, x_label: "frame", y_label: "method", series: &series, log_x: false, log_y: false }, PLOT)?;
            let choice_stem = format!("choice-{}", stem(&s.spec));
            fig.save(plots, &choice_stem)?;
            imgs.push((format!("plots/{choice_stem}.svg"), format!("{}: what {} ran", s.spec, r.method)));
        }
    }
    doc.images(imgs);
    Ok(())
}

fn breakdown(doc: &mut Doc, d: &ReportData, plots: &Path) -> Result<()> {
    let hroc_rows = |s: &SceneResult| -> Vec<MethodRow> { s.main.rows.iter().filter(|r| matches!(r.method, Method::Hroc(_))).cloned().collect() };
    if d.scenes.iter().all(|s| hroc_rows(s).is_empty()) {
        return Ok(());
    }
    doc.heading("HROC per-stage GPU time (HROC paper Figure 6)");
    doc.para("GPU ms per stage from timestamp queries, mean over the timed frames; below, HROC's mean per-frame counts: |V| objects drawn into the occlusion map, |O| effective occluders, |G| tested groups, |U| objects whose box passed, |D| drawn occludees.");
    let mut imgs = Vec::new();
    let mut t = Table::new(&["scene", "method", "|V|", "|O|", "|G|", "|U|", "|D|", "nodes/ray"]);
    for s in &d.scenes {
        let rows = hroc_rows(s);
        if rows.is_empty() {
            continue;
        }
        // Bottom to top in stage order, which is the order a frame runs them (§3).
        let stages: std::collections::BTreeSet<Stage> = rows.iter().flat_map(|r| r.stages_ms.keys().copied()).collect();
        let categories: Vec<String> = rows.iter().map(|r| r.method.to_string()).collect();
        let layers: Vec<(String, Vec<f64>)> = stages.iter().map(|st| (st.to_string(), rows.iter().map(|r| r.stages_ms.get(st).copied().unwrap_or(0.0)).collect())).collect();
        let title = format!("{}: HROC GPU ms per stage", s.spec);
        let fig = plot::stacked_bars(&StackedBars { title: &title, y_label: "GPU ms", categories: &categories, layers: &layers }, PLOT)?;
        let stem = format!("stages-{}", stem(&s.spec));
        fig.save(plots, &stem)?;
        imgs.push((format!("plots/{stem}.svg"), s.spec.clone()));
        for r in &rows {
            let g = |k: Stat| r.stats.get(&k).map_or("-".into(), |v| format!("{v:.0}"));
            t.row(vec![
                s.spec.clone(),
                r.method.to_string(),
                g(Stat::V),
                g(Stat::O),
                g(Stat::G),
                g(Stat::U),
                g(Stat::D),
                r.stats.get(&Stat::NodesPerRay).map_or("-".into(), |v| format!("{v:.1}")),
            ]);
        }
    }
    doc.images(imgs);
    doc.table(t);
    invocations(doc, d);
    shape(doc, d);
    Ok(())
}

/// The frame's shape of every method (`FrameShape`): what the culler
/// records per frame, counts that repeat from run to run.
fn shape(doc: &mut Doc, d: &ReportData) {
    let rows = |s: &SceneResult| s.main.rows.iter().filter(|r| r.stats.contains_key(&Stat::ComputePasses)).cloned().collect::<Vec<MethodRow>>();
    if d.scenes.iter().all(|s| rows(s).is_empty()) {
        return;
    }
    doc.heading("The frame's shape");
    doc.para("Per frame, mean over the run: the compute and render passes the culler opens, its dispatches (indirect in brackets), its own draw calls, the lists it hands the host (one host draw each), buffer clears and copies, buffers mapped for reading, and the CPU ms of recording the frame (`View::cull`, the host's draw callbacks included). Passes, dispatches and clears cost a GPU whatever they hold.");
    let mut t = Table::new(&["scene", "method", "compute passes", "render passes", "dispatches", "own draws", "lists", "clears", "copies", "maps", "record ms"]);
    for s in &d.scenes {
        for r in rows(s) {
            let g = |k: Stat| r.stats.get(&k).copied().unwrap_or(0.0);
            let n = |k: Stat| format!("{:.1}", g(k));
            t.row(vec![
                s.spec.clone(),
                r.method.to_string(),
                n(Stat::ComputePasses),
                n(Stat::RenderPasses),
                format!("{:.1} ({:.1})", g(Stat::Dispatches), g(Stat::IndirectDispatches)),
                n(Stat::OwnDraws),
                n(Stat::Lists),
                n(Stat::Clears),
                n(Stat::Copies),
                n(Stat::Maps),
                format!("{:.3}", g(Stat::RecordMs)),
            ]);
        }
    }
    doc.table(t);
}

/// Shader invocations per frame of every method and stage (pipeline
/// statistics): the work behind the times, independent of machine noise.
fn invocations(doc: &mut Doc, d: &ReportData) {
    if d.scenes.iter().all(|s| s.main.rows.iter().all(|r| r.invocations.is_empty())) {
        return;
    }
    doc.heading("Shader invocations per stage");
    doc.para("Vertex, fragment and compute shader invocations per frame from pipeline-statistics queries, mean over the timed frames; `culling` sums the stages that do not draw scene geometry. Unlike times, these counts do not depend on how busy the machine is.");
    let mut t = Table::new(&["scene", "method", "stage", "vertex", "fragment", "compute"]);
    for s in &d.scenes {
        for r in s.main.rows.iter().filter(|r| !r.invocations.is_empty()) {
            let mut row = |stage: String, i: &crate::bench::InvocationsMean| {
                t.row(vec![s.spec.clone(), r.method.to_string(), stage, format!("{:.0}", i.vertex), format!("{:.0}", i.fragment), format!("{:.0}", i.compute)]);
            };
            for (stage, i) in &r.invocations {
                row(stage.to_string(), i);
            }
            row("culling".into(), &r.culling_invocations());
        }
    }
    doc.table(t);
}

fn overdraw(doc: &mut Doc, d: &ReportData) {
    let h = &d.heat;
    doc.heading("Overdraw (Lee et al. 2021 Figure 7; Lee's thesis, Figure 17)");
    doc.para(format!(
        "Fragments per pixel of {} at frame {} (black 0 → blue → green → yellow → red → white 8 or more); the differences are white where equal, red where the first draws more, blue where it draws less.",
        d.scenes.first().map_or("", |s| s.spec.as_str()),
        h.frame
    ));
    doc.images(h.maps.iter().map(|m| (m.file.clone(), format!("{}: {:.2} fragments/pixel", m.name, m.mean))).collect());
    doc.images(h.diffs.iter().map(|m| (m.file.clone(), format!("{}: {:+.2} fragments/pixel", m.name, m.mean))).collect());
}

fn sweep(doc: &mut Doc, d: &ReportData, plots: &Path) -> Result<()> {
    let Some(first) = d.sweep.first() else { return Ok(()) };
    doc.heading("Scale sweep");
    doc.para(format!(
        "`{}` grown from {} to {} objects, {} frames each. Culling-only cost: GPU ms of the stages that do not draw scene geometry (everything but clearing, drawing, the occlusion map and occludee rendering). {}",
        first.report.scene,
        first.objects,
        d.sweep.last().map_or(0, |p| p.objects),
        first.report.frames,
        d.sweep_stopped.as_deref().map_or(String::new(), |s| format!("The sweep {s}."))
    ));
    let methods: Vec<Method> = first.report.rows.iter().map(|r| r.method).collect();
    let mut head = vec!["objects".to_string(), "triangles".to_string()];
    head.extend(methods.iter().map(|m| format!("{m} ms (culling)")));
    let mut t = Table { head, rows: Vec::new() };
    for p in &d.sweep {
        let mut cells = vec![p.objects.to_string(), p.report.triangles.to_string()];
        cells.extend(methods.iter().map(|&m| row(&p.report, m).map_or("-".into(), |r| format!("{} ({})", ms(r.ms_mean), culling_ms(r).map_or("-".into(), ms)))));
        t.row(cells);
    }
    doc.table(t);
    let series = |f: &dyn Fn(&MethodRow) -> Option<f64>| -> Vec<Series> {
        methods
            .iter()
            .map(|&m| Series { name: m.to_string(), points: d.sweep.iter().filter_map(|p| row(&p.report, m).and_then(f).map(|v| (p.objects as f64, v))).collect() })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    let frame = series(&|r| Some(r.ms_mean));
    // noc culls nothing: its zero has no place on a log axis.
    let cull = series(&|r| culling_ms(r).filter(|&v| v > 0.0));
    let mut imgs = Vec::new();
    for (stem, title, s) in [("sweep-frame", "ms per frame", &frame), ("sweep-culling", "culling-only GPU ms", &cull)] {
        if s.is_empty() {
            continue;
        }
        let fig = plot::line_plot(&LinePlot { title, x_label: "objects", y_label: "ms", series: s, log_x: true, log_y: true }, PLOT)?;
        fig.save(plots, stem)?;
        imgs.push((format!("plots/{stem}.svg"), title.to_string()));
    }
    doc.images(imgs);
    Ok(())
}

fn hires(doc: &mut Doc, d: &ReportData) {
    doc.heading("High resolution (HROC paper Table 2)");
    let Some(r) = &d.hires else {
        doc.para(format!("Not run: {}.", d.hires_skipped.as_deref().unwrap_or("left out (--hires none)")));
        return;
    };
    doc.para(format!("`{}` at {}, {} frames.", r.scene, r.resolution, r.frames));
    let noc = row(r, Method::Noc).map(|x| x.ms_mean);
    let mut t = Table::new(&["method", "ms/frame", "× noc", "C/R", "false neg", "missing px"]);
    for x in &r.rows {
        t.row(vec![
            x.method.to_string(),
            ms(x.ms_mean),
            noc.filter(|&n| n > 0.0).map_or("-".into(), |n| format!("{:.2}", x.ms_mean / n)),
            format!("{:.3}", x.c_over_r),
            x.false_negatives.to_string(),
            x.missing_pixels.to_string(),
        ]);
    }
    doc.table(t);
}

fn motion(doc: &mut Doc, d: &ReportData) {
    let Some(first) = d.motion.first() else { return };
    doc.heading("Moving objects (HROC paper §6)");
    doc.para(format!(
        "{}, {} frames per fraction. The moving objects are refit into the BVH every frame; the object update (boxes, refit or rebuild, uploads landed) is shared by every method of a run and is not in their frame times, so the last columns add it back: a method's frame plus the update over its static frame.",
        crate::bench::table::motion_caption(first),
        first.frames
    ));
    let (head, rows) = crate::bench::table::motion_grid(&d.motion);
    doc.table(Table { head, rows });
}

fn clusters(doc: &mut Doc, d: &ReportData) {
    let Some(first) = d.clusters.first() else { return };
    doc.heading("Clusters");
    doc.para(format!(
        "{}, {} frames, as whole objects and split into clusters of at most T triangles (meshoptimizer's spatial clustering; each cluster a cullable object with its own box). Triangles: drawn per frame, and their share of the scene's.",
        first.report.scene, first.report.frames
    ));
    let mut t = Table::new(&["clusters", "objects", "method", "ms/frame", "× noc", "C/R", "drawn/frame", "triangles/frame"]);
    for run in &d.clusters {
        let r = &run.report;
        let noc = row(r, Method::Noc).map(|x| x.ms_mean);
        for row in &r.rows {
            t.row(vec![
                run.triangles.map_or("none".into(), |t| t.to_string()),
                r.objects.to_string(),
                row.method.to_string(),
                ms(row.ms_mean),
                noc.map_or("-".into(), |n| format!("{:.2}", row.ms_mean / n)),
                format!("{:.3}", row.c_over_r),
                format!("{:.0}", row.drawn_mean),
                format!("{:.0} ({:.1} %)", row.triangles_mean, 100.0 * row.triangles_fraction),
            ]);
        }
    }
    doc.table(t);
}

/// A file-name-safe form of a scene spec (a key, or a path).
fn stem(spec: &str) -> String {
    let base = std::path::Path::new(spec).file_stem().and_then(|s| s.to_str()).unwrap_or(spec);
    base.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' }).collect()
}
