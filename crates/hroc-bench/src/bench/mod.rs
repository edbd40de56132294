//! `hroc bench`: every method over the same camera path in one process,
//! side by side per frame, checked against `noc`.

pub mod plot;
pub mod report;
pub mod session;
pub mod table;

use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;

use crate::bvh::Split;
use crate::cull::Method;
use crate::error::Result;
use crate::gpu::Headless;
use crate::scene::{CameraPath, Scene};
pub use session::{Check, FrameResult, Projection, Session, Truth};

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: String,
    pub objects: Option<usize>,
    pub methods: Vec<Method>,
    pub frames: usize,
    /// Frames per second of camera path (`--fps`): replaces `frames` with
    /// `fps × duration + 1`, so runs at 5, 30 and 60 sample the same path
    /// at a known rate.
    pub fps: Option<f32>,
    pub resolution: (u32, u32),
    pub split: Split,
    /// Split meshes into clusters of at most this many triangles, each a
    /// cullable object (`--clusters`; [`crate::scene::Scene::clustered`]).
    pub clusters: Option<u32>,
    /// Give the culler the rotated objects' oriented boxes
    /// (`--oriented-boxes`; [`Session::set_oriented_boxes`]).
    pub oriented_boxes: bool,
    /// A camera path file, or a built-in path of the scene by name
    /// (`hard`, `cuts`: [`crate::scene::paths::builtin`]).
    pub camera_path: Option<PathBuf>,
    pub progress: bool,
    /// Fraction of the objects that move every frame (`--moving`), 0 to 1,
    /// each as its scene moves them ([`crate::scene::motion`]).
    pub moving: f32,
    /// Flag the moving objects [`hroc::ObjectFlags::DYNAMIC`] (HROC §6's
    /// hybrid) instead of refitting them into the BVH (`--dynamic`).
    pub dynamic: bool,
    /// Refit and rebuild policy (`--refit`, `--rebuild-growth`).
    pub motion: hroc::MotionOptions,
    /// Parameters of the methods (`--soq-base-time`, `--chc-*`).
    pub method_options: crate::cull::MethodOptions,
    /// Time every stage with GPU timestamps (`--breakdown`). Each stamp is a
    /// point the GPU must reach before the next command (on lavapipe, a
    /// flush of the rasterizer), which costs methods of many stages most:
    /// runs compare ms/frame without them.
    pub timestamps: bool,
    /// Samples per pixel of the camera's targets (`--msaa`; 1: none).
    pub msaa: u32,
    /// Cascades of a directional light's shadow map (`--shadow-cascades`,
    /// 0 to 4), each a view of its own culled by every method and checked
    /// against its own `noc` picture.
    pub shadow_cascades: u32,
    /// How the camera projects (`--projection`).
    pub projection: Projection,
}

impl BenchOptions {
    /// `hroc bench`'s defaults for `scene`, `objects` (the scene's own
    /// count when `None`) and `methods`: 60 frames at 640 × 360, SAH, no
    /// clusters, oriented boxes, the scene's own path, nothing moving, no
    /// timestamps.
    pub fn new(scene: &str, objects: Option<usize>, methods: Vec<Method>) -> BenchOptions {
        BenchOptions {
            scene: scene.to_string(),
            objects,
            methods,
            frames: 60,
            fps: None,
            resolution: (640, 360),
            split: Split::Sah,
            clusters: None,
            oriented_boxes: true,
            camera_path: None,
            progress: false,
            moving: 0.0,
            dynamic: false,
            motion: hroc::MotionOptions::default(),
            method_options: crate::cull::MethodOptions::default(),
            timestamps: false,
            msaa: 1,
            shadow_cascades: 0,
            projection: Projection::Perspective,
        }
    }
}

/// One row of the table. Later methods add fields; these names never change.
#[derive(Clone, Debug, Serialize)]
pub struct MethodRow {
    /// By its name in the JSON.
    #[serde(serialize_with = "method_name")]
    pub method: Method,
    pub ms_mean: f64,
    pub ms_p95: f64,
    /// Summed stage times; `None` without timestamps.
    pub gpu_ms_mean: Option<f64>,
    pub c_over_n: f64,
    pub c_over_r: f64,
    pub false_negatives: u64,
    /// The frames with a false negative or a missing pixel, each with its
    /// counts (frame, false negatives, missing pixels): where to look.
    pub missed_frames: Vec<(usize, u32, u32)>,
    pub missing_pixels: u64,
    /// `noc`'s stray fragments the method did not reproduce (`Check::stray_pixels`).
    pub stray_pixels: u64,
    /// Mean objects drawn per frame, over every view.
    pub drawn_mean: f64,
    /// Mean objects drawn per frame by each view: the camera's, then each
    /// shadow cascade's.
    pub drawn_per_view: Vec<f64>,
    /// Most objects the camera view drew in one timed frame (after the
    /// warm-up): a frame whose visible set collapsed.
    pub drawn_max: u64,
    /// Mean triangles drawn per frame, and their fraction of the scene's
    /// (of every view's scene, with shadow cascades).
    pub triangles_mean: f64,
    pub triangles_fraction: f64,
    /// Mean GPU ms per stage, in stage order (by name in the JSON).
    #[serde(serialize_with = "by_stage_name")]
    pub stages_ms: BTreeMap<hroc::Stage, f64>,
    /// Mean shader invocations per frame and stage, from pipeline-statistics
    /// queries (with `--breakdown` on devices that have them): work that
    /// does not depend on how busy the machine is. Empty without them.
    #[serde(serialize_with = "by_stage_name")]
    pub invocations: BTreeMap<hroc::Stage, InvocationsMean>,
    /// Mean per frame of the method's own statistics (HROC: V, O, G, U, D,
    /// rays, nodes_per_ray), by name in the JSON: the camera view's. Empty
    /// for methods without any.
    #[serde(serialize_with = "by_stat_name")]
    pub stats: BTreeMap<hroc::Stat, f64>,
    /// Wall ms of every frame (warm-up frames included).
    pub frame_ms: Vec<f64>,
    /// Triangles drawn in every frame, by every view (warm-up frames
    /// included): with `vfc`'s, the frustum's count each frame.
    pub frame_triangles: Vec<u64>,
    /// Frames the camera view took as camera cuts.
    pub cut_frames: Vec<usize>,
    /// `auto`: the method that culled each frame of the camera view
    /// (empty for the other methods).
    #[serde(serialize_with = "method_names")]
    pub frame_methods: Vec<Method>,
}

impl MethodRow {
    /// `auto`: each method it ran and the share of frames it ran, most first.
    pub fn choices(&self) -> Vec<(Method, f64)> {
        let mut out: Vec<(Method, f64)> = Vec::new();
        for m in &self.frame_methods {
            match out.iter_mut().find(|(x, _)| x == m) {
                Some(e) => e.1 += 1.0,
                None => out.push((*m, 1.0)),
            }
        }
        out.iter_mut().for_each(|e| e.1 /= self.frame_methods.len() as f64);
        out.sort_by(|a, b| b.1.total_cmp(&a.1));
        out
    }

    /// Invocations per frame of the stages that do not draw scene
    /// geometry: the work of culling itself.
    pub fn culling_invocations(&self) -> InvocationsMean {
        self.invocations.iter().filter(|(stage, _)| !stage.draws_scene()).fold(InvocationsMean::default(), |a, (_, i)| InvocationsMean {
            vertex: a.vertex + i.vertex,
            fragment: a.fragment + i.fragment,
            compute: a.compute + i.compute,
        })
    }
}

/// Mean shader invocations per frame of one stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct InvocationsMean {
    pub vertex: f64,
    pub fragment: f64,
    pub compute: f64,
}

impl InvocationsMean {
    fn of(sum: &hroc::testing::gpu::Invocations, frames: f64) -> Self {
        InvocationsMean { vertex: sum.vertex as f64 / frames, fragment: sum.fragment as f64 / frames, compute: sum.compute as f64 / frames }
    }
}

/// Serializes a per-stage map by stage name, in stage order.
fn by_stage_name<T: Serialize, S: serde::Serializer>(m: &BTreeMap<hroc::Stage, T>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_map(m.iter().map(|(k, v)| (k.name(), v)))
}

/// Serializes a per-statistic map by statistic name, in declaration order.
fn by_stat_name<S: serde::Serializer>(m: &BTreeMap<hroc::Stat, f64>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_map(m.iter().map(|(k, v)| (k.name(), v)))
}

#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub scene: String,
    pub objects: usize,
    pub triangles: u64,
    pub resolution: String,
    pub adapter: String,
    /// What the culler ran with: `full`, `portable`, or the two capabilities.
    #[serde(default)]
    pub capabilities: String,
    pub frames: usize,
    /// Frames per second of camera path: how far apart in time the frames
    /// are (the coherence a method can rely on).
    pub frames_per_second: f64,
    /// The camera path: `own` (the scene's), `hard`, `cuts`, or a file.
    pub path: String,
    /// Samples per pixel of the camera's targets.
    pub msaa: u32,
    /// Shadow cascades, each a view culled beside the camera's.
    pub shadow_cascades: u32,
    /// How the camera projects.
    pub projection: Projection,
    /// Frames at the start left out of the timing statistics (not of the checks).
    pub warmup_frames: usize,
    pub split: String,
    pub bvh_nodes: usize,
    pub bvh_build_ms: f64,
    /// Fraction of the objects moved every frame.
    pub moving: f64,
    /// Objects moved every frame.
    pub moved_objects: usize,
    /// Mean per-frame object update, ms: the culler's part
    /// (`Culler::set_bounds`: boxes, BVH refit or rebuild, uploads landed on
    /// the GPU), shared by every method of the run and untimed in their
    /// rows; the `object update` stage.
    pub update_ms_mean: f64,
    /// The CPU part of it, ms per frame.
    pub refit_ms_mean: f64,
    /// The bench host's own part, ms per frame: tight boxes from the new
    /// transforms, and the transforms uploaded.
    pub host_update_ms_mean: f64,
    /// BVH SAH cost after the last frame's refit over the cost as last
    /// built (1 for a static scene): how much the refit tree degraded.
    /// `None` with the GPU refit, whose boxes the CPU does not see.
    pub sah_growth: Option<f64>,
    /// Moving objects flagged DYNAMIC (tested alone, not refit).
    pub dynamic: bool,
    /// Where the BVH was refit (`cpu`, `gpu`).
    pub refit: String,
    /// Rebuilds of the BVH over the run.
    pub rebuilds: usize,
    pub rows: Vec<MethodRow>,
}

#[derive(Default)]
struct Acc {
    wall: Vec<f64>,
    gpu: Vec<f64>,
    stages: BTreeMap<hroc::Stage, f64>,
    invocations: BTreeMap<hroc::Stage, hroc::testing::gpu::Invocations>,
    stats: BTreeMap<hroc::Stat, f64>,
    culled: u64,
    drawn: u64,
    triangles: u64,
    fneg: u64,
    missing: u64,
    stray: u64,
    /// Objects drawn by each view, summed over frames.
    view_drawn: Vec<u64>,
    /// Triangles drawn in every frame.
    frame_triangles: Vec<u64>,
    /// Frames taken as camera cuts.
    cut_frames: Vec<usize>,
    /// `auto`: the method of every frame.
    chosen: Vec<Method>,
    missed: Vec<(usize, u32, u32)>,
    drawn_max: u64,
}

/// Like the paper (§5.1), the first frames pay for lazy initialisation and
/// are left out of the timings; every frame is still checked.
pub fn warmup_frames(frames: usize) -> usize {
    if frames >= 20 {
        4
    } else {
        0
    }
}

/// Loads the scene and camera path the options name (no GPU needed).
pub fn load_inputs(o: &BenchOptions) -> Result<(Scene, Option<CameraPath>)> {
    let mut scene = crate::scene::load(&o.scene, o.objects, 0)?;
    if let Some(t) = o.clusters {
        scene = scene.clustered(crate::scene::ClusterOptions::new(t))?;
    }
    let path = o.camera_path.as_deref().map(|p| load_path(&scene, p)).transpose()?;
    Ok((scene, path))
}

/// A built-in path of `scene` by name (`hard`, `cuts`), else a path file.
pub fn load_path(scene: &Scene, spec: &std::path::Path) -> Result<CameraPath> {
    match spec.to_str().and_then(|name| crate::scene::paths::builtin(scene, name)) {
        Some(builtin) => Ok(builtin),
        None => CameraPath::from_file(spec),
    }
}

/// Frames of a run: `o.frames`, or `fps × duration + 1` over `path`.
pub fn frame_count(o: &BenchOptions, path: &CameraPath) -> Result<usize> {
    let Some(fps) = o.fps else { return Ok(o.frames) };
    if !(fps > 0.0 && fps <= 1000.0) {
        return Err(crate::Error::Arg(format!("--fps {fps} is not a rate from 0 to 1000 frames per path second")));
    }
    let dur = path.duration() - path.keys.first().map_or(0.0, |k| k.t);
    Ok((fps * dur).round() as usize + 1)
}

pub fn run(gpu: &Headless, o: &BenchOptions) -> Result<BenchReport> {
    let (scene, path) = load_inputs(o)?;
    run_scene(gpu, o, scene, path)
}

pub fn run_scene(gpu: &Headless, o: &BenchOptions, scene: Scene, path: Option<CameraPath>) -> Result<BenchReport> {
    if !(0.0..=1.0).contains(&o.moving) {
        return Err(crate::Error::Arg(format!("--moving {} is not a fraction from 0 to 1", o.moving)));
    }
    if o.moving > 0.0 {
        if let Some(m) = o.methods.iter().find(|m| !m.takes_motion()) {
            return Err(crate::Error::Arg(format!("{m} keeps its own copy of the BVH and takes static scenes only: drop it, or use --moving 0")));
        }
    }
    let movers = crate::scene::motion::moving_objects(scene.objects.len(), o.moving);
    let base: Vec<glam::Mat4> = scene.objects.iter().map(|ob| ob.transform).collect();
    let centre = scene.bounds().center();
    let frames = frame_count(o, path.as_ref().unwrap_or(&scene.path))?;
    let mut s = Session::new_msaa(gpu, scene, path, frames, o.resolution, o.split, o.timestamps, o.msaa)?;
    s.set_shadow_cascades(o.shadow_cascades)?;
    s.set_projection(o.projection);
    s.culler.set_motion(o.motion)?;
    s.set_oriented_boxes(o.oriented_boxes)?;
    if o.dynamic {
        let flags: Vec<(u32, hroc::ObjectFlags)> = movers.iter().map(|&i| (i, hroc::ObjectFlags::DYNAMIC)).collect();
        s.culler.set_many_flags(&flags)?;
    }
    let (mut update_ms, mut refit_ms, mut host_ms, mut rebuilds, mut growth) = (Vec::new(), Vec::new(), Vec::new(), 0, Some(1.0));
    s.options = o.method_options.clone();
    let cascade_views = |m: Method| (0..s.cascade_count()).map(|c| s.create_cascade(m, c)).collect::<Result<Vec<_>>>();
    let mut cullers = o.methods.iter().filter(|&&m| m != Method::Noc).map(|&m| Ok((m, s.create(m)?, cascade_views(m)?))).collect::<Result<Vec<_>>>()?;
    let n = s.renderer.object_count as u64;
    let scene_triangles = s.scene.stats().triangles;
    let frames = s.cameras.len();
    let warm = warmup_frames(frames);
    let bar = if o.progress { indicatif::ProgressBar::new(frames as u64) } else { indicatif::ProgressBar::hidden() };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames, {elapsed} (eta {eta})").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(format!("bench {}", s.scene.name));
    let mut accs: HashMap<Method, Acc> = HashMap::new();
    let mut ref_culled = 0u64;
    let mut record = |method: Method, k: usize, r: &FrameResult, c: Check, views: &[usize], stats: Vec<(hroc::Stat, f64)>, update: Option<f64>| {
        let a = accs.entry(method).or_default();
        a.view_drawn.resize(views.len(), 0);
        for (sum, &d) in a.view_drawn.iter_mut().zip(views) {
            *sum += d as u64;
        }
        if k >= warm {
            a.drawn_max = a.drawn_max.max(views.first().copied().unwrap_or(0) as u64);
        }
        for (st, v) in stats {
            match st {
                hroc::Stat::Chosen => a.chosen.push(Method::ALL.get(v as usize).copied().unwrap_or(Method::Auto)),
                _ => {
                    if st == hroc::Stat::Cut && v > 0.0 {
                        a.cut_frames.push(k);
                    }
                    *a.stats.entry(st).or_default() += v;
                }
            }
        }
        a.wall.push(r.wall_ms);
        a.frame_triangles.push(c.triangles);
        if k >= warm {
            a.gpu.push(r.gpu_ms());
            for (st, ms) in &r.stages {
                *a.stages.entry(*st).or_default() += ms;
            }
            for (st, inv) in &r.invocations {
                *a.invocations.entry(*st).or_default() += *inv;
            }
            if let Some(ms) = update {
                *a.stages.entry(hroc::Stage::ObjectUpdate).or_default() += ms;
            }
        }
        a.culled += n * views.len() as u64 - c.drawn as u64;
        a.drawn += c.drawn as u64;
        a.triangles += c.triangles;
        a.fneg += c.false_negatives as u64;
        if c.false_negatives + c.missing_pixels > 0 {
            a.missed.push((k, c.false_negatives as u32, c.missing_pixels as u32));
        }
        a.missing += c.missing_pixels as u64;
        a.stray += c.stray_pixels as u64;
    };
    for k in 0..frames {
        if !movers.is_empty() {
            let time = s.times[k];
            let moves: Vec<(u32, glam::Mat4)> = movers.iter().map(|&i| (i, crate::scene::motion::moved(&s.scene.name, centre, &base[i as usize], i, time))).collect();
            let t = std::time::Instant::now();
            let culler_ms = s.move_objects(&moves)?;
            // The host's uploads land now too, not in the next timed frame.
            s.gpu.queue.submit([]);
            s.gpu.wait()?;
            update_ms.push(culler_ms);
            host_ms.push(t.elapsed().as_secs_f64() * 1e3 - culler_ms);
            let u = s.culler.last_update();
            refit_ms.push(u.cpu_ms);
            rebuilds += u.rebuilt as usize;
            growth = u.sah_growth;
        }
        let update = update_ms.last().copied().filter(|_| !movers.is_empty());
        let (mut noc_frame, truth) = s.truth(k)?;
        ref_culled += n - truth.visible.len() as u64;
        // Each cascade's own picture, drawn by noc.
        let (cascades, time) = (s.cascades(k), s.times[k]);
        let mut shadow_truths = Vec::new();
        for (c, cascade) in cascades.iter().enumerate() {
            let (r, t) = s.cascade_truth(c as u32, cascade, time)?;
            ref_culled += n - t.visible.len() as u64;
            shadow_truths.push((r, t));
        }
        if o.methods.contains(&Method::Noc) {
            let mut c = s.check(&noc_frame, &truth)?;
            let mut views = vec![c.drawn];
            for (cs, (r, t)) in shadow_truths.iter().enumerate() {
                let cc = s.check_cascade(cs as u32, r, t)?;
                views.push(cc.drawn);
                noc_frame.add(r);
                c += cc;
            }
            record(Method::Noc, k, &noc_frame, c, &views, Vec::new(), update);
        }
        for (method, c, shadow_views) in cullers.iter_mut() {
            if c.wants_oracle() {
                c.set_oracle(&s.culler, &truth.visible)?;
            }
            let mut r = s.run_frame(c, k)?;
            let mut chk = s.check(&r, &truth)?;
            let stats = c.stats(&s.culler)?;
            let mut views = vec![chk.drawn];
            for (cs, view) in shadow_views.iter_mut().enumerate() {
                if view.wants_oracle() {
                    view.set_oracle(&s.culler, &shadow_truths[cs].1.visible)?;
                }
                let rc = s.run_cascade(view, cs as u32, &cascades[cs], time)?;
                let cc = s.check_cascade(cs as u32, &rc, &shadow_truths[cs].1)?;
                views.push(cc.drawn);
                r.add(&rc);
                chk += cc;
            }
            record(*method, k, &r, chk, &views, stats, update);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let rows = o
        .methods
        .iter()
        .map(|m| {
            let a = &accs[m];
            let timed = &a.wall[warm.min(a.wall.len().saturating_sub(1))..];
            let timed_frames = a.gpu.len().max(1) as f64;
            MethodRow {
                method: *m,
                ms_mean: mean(timed),
                ms_p95: percentile(timed, 0.95),
                gpu_ms_mean: o.timestamps.then(|| mean(&a.gpu)),
                c_over_n: a.culled as f64 / (n * frames as u64 * (1 + o.shadow_cascades as u64)) as f64,
                c_over_r: if ref_culled == 0 {
                    if a.culled == 0 {
                        1.0
                    } else {
                        f64::INFINITY
                    }
                } else {
                    a.culled as f64 / ref_culled as f64
                },
                false_negatives: a.fneg,
                missing_pixels: a.missing,
                stray_pixels: a.stray,
                drawn_mean: a.drawn as f64 / frames as f64,
                drawn_per_view: a.view_drawn.iter().map(|&d| d as f64 / frames as f64).collect(),
                drawn_max: a.drawn_max,
                triangles_mean: a.triangles as f64 / frames as f64,
                triangles_fraction: a.triangles as f64 / (frames as f64 * a.view_drawn.len().max(1) as f64 * scene_triangles.max(1) as f64),
                stages_ms: a.stages.iter().map(|(k, v)| (*k, v / timed_frames)).collect(),
                invocations: a.invocations.iter().map(|(k, v)| (*k, InvocationsMean::of(v, timed_frames))).collect(),
                stats: a.stats.iter().map(|(k, v)| (*k, v / frames as f64)).collect(),
                frame_ms: a.wall.clone(),
                frame_triangles: a.frame_triangles.clone(),
                cut_frames: a.cut_frames.clone(),
                frame_methods: a.chosen.clone(),
                missed_frames: a.missed.clone(),
            }
        })
        .collect();
    let st = s.scene.stats();
    Ok(BenchReport {
        scene: s.scene.name.clone(),
        objects: st.objects,
        triangles: st.triangles,
        resolution: format!("{}x{}", o.resolution.0, o.resolution.1),
        adapter: gpu.adapter_name(),
        capabilities: capabilities_name(s.culler.capabilities()),
        frames,
        frames_per_second: {
            let dur = s.times.last().copied().unwrap_or(0.0) - s.times.first().copied().unwrap_or(0.0);
            if dur > 0.0 {
                (frames.max(1) - 1) as f64 / dur as f64
            } else {
                0.0
            }
        },
        path: o.camera_path.as_ref().map_or("own".into(), |p| p.display().to_string()),
        msaa: o.msaa,
        shadow_cascades: o.shadow_cascades,
        projection: o.projection,
        warmup_frames: warm,
        split: o.split.to_string(),
        bvh_nodes: s.bvh().nodes.len(),
        bvh_build_ms: s.bvh().build_ms,
        moving: o.moving as f64,
        moved_objects: movers.len(),
        update_ms_mean: mean(&update_ms),
        refit_ms_mean: mean(&refit_ms),
        host_update_ms_mean: mean(&host_ms),
        sah_growth: growth,
        dynamic: o.dynamic,
        refit: format!("{:?}", o.motion.refit).to_lowercase(),
        rebuilds,
        rows,
    })
}

/// Methods on the command line: `a,b,c` or `all` ([`Method::parse_list`]),
/// written back as their names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MethodList(pub Vec<Method>);

impl std::str::FromStr for MethodList {
    type Err = crate::Error;
    fn from_str(s: &str) -> Result<MethodList> {
        Ok(MethodList(Method::parse_list(s)?))
    }
}

impl std::fmt::Display for MethodList {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0.iter().map(|m| m.name()).collect::<Vec<_>>().join(","))
    }
}

/// Parses `a,b,c` or `all` into methods ([`Method::parse_list`]).
pub fn parse_methods(spec: &str) -> Result<Vec<Method>> {
    Ok(Method::parse_list(spec)?)
}

/// Methods by their names in the JSON rows.
fn method_names<S: serde::Serializer>(m: &[Method], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(m.iter().map(|m| m.name()))
}

/// A method by its name in the JSON rows.
fn method_name<S: serde::Serializer>(m: &Method, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(m.name())
}

/// Year, month, day of a day count since 1970-01-01 (H. Hinnant's `civil_from_days`).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// `WxH`, both sides positive (clap value parser).
pub fn parse_resolution(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s.split_once('x').ok_or_else(|| format!("resolution '{s}' is not WxH"))?;
    let w: u32 = w.parse().map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h.parse().map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 {
        return Err(format!("resolution '{s}' has a zero side"));
    }
    Ok((w, h))
}

pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Nearest-rank percentile.
pub fn percentile(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let rank = ((p * s.len() as f64).ceil() as usize).clamp(1, s.len());
    s[rank - 1]
}

/// The tier's name ([`crate::gpu::Tier`]), or the three capabilities
/// (draw count, marks, read-only depth).
pub fn capabilities_name(c: hroc::Capabilities) -> String {
    match crate::gpu::Tier::ALL.into_iter().find(|t| t.capabilities() == c) {
        Some(t) => t.name().into(),
        None => format!("{:?} draw count, {:?} marks, {} read-only depth", c.draw_count, c.marks, if c.read_only_depth { "with" } else { "without" }),
    }
}

#[cfg(test)]
mod tests {
    use super::civil_from_days;

    #[test]
    fn days_become_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }
}
