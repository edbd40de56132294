//! One bench run, frame by frame: update the objects, draw the truth (the
//! camera's and each cascade's `noc` picture), run each method with its
//! cascades and check it, then the rows.

use std::collections::{BTreeMap, HashMap};

use super::check::{Check, Truth};
use super::rows::{BenchReport, InvocationsMean, MethodRow};
use super::session::{FrameResult, Session, SessionDesc};
use super::{capabilities_name, mean, percentile, BenchOptions};
use crate::error::Result;
use crate::gpu::Headless;
use crate::render::cascades::CascadeView;
use crate::scene::{CameraPath, Scene};
use hroc::{Method, View};

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
        None => Ok(CameraPath::from_file(spec)?),
    }
}

/// Frames of a run: `o.frames`, or `fps × duration + 1` over `path`,
/// once the options pass [`BenchOptions::check`].
pub fn frame_count(o: &BenchOptions, path: &CameraPath) -> Result<usize> {
    o.check()?;
    let Some(fps) = o.fps else { return Ok(o.frames) };
    let dur = path.duration() - path.keys.first().map_or(0.0, |k| k.t);
    Ok((fps * dur).round() as usize + 1)
}

/// Loads the inputs `o` names and runs them ([`run_scene`]).
pub fn run(gpu: &Headless, o: &BenchOptions) -> Result<BenchReport> {
    let (scene, path) = load_inputs(o)?;
    run_scene(gpu, o, scene, path)
}

/// Every method of `o` over `scene` (on `path`, else the scene's own),
/// side by side per frame, each frame checked against `noc`'s.
pub fn run_scene(gpu: &Headless, o: &BenchOptions, scene: Scene, path: Option<CameraPath>) -> Result<BenchReport> {
    let mut run = Run::new(gpu, o, scene, path)?;
    let bar = if o.progress { indicatif::ProgressBar::new(run.frames as u64) } else { indicatif::ProgressBar::hidden() };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames, {elapsed} (eta {eta})").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(format!("bench {}", run.s.scene.name));
    for k in 0..run.frames {
        let update = run.update_objects(k)?;
        let mut truths = run.truths(k)?;
        run.noc(k, &mut truths, update)?;
        run.methods(k, &truths, update)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    run.validated()?;
    Ok(run.report(gpu))
}

/// A run in progress: the session, the moving objects, the methods' views
/// and what each has summed.
struct Run<'g, 'o> {
    o: &'o BenchOptions,
    s: Session<'g>,
    frames: usize,
    warm: usize,
    /// Objects that move, their transforms at frame 0, and the scene's centre.
    movers: Vec<u32>,
    base: Vec<glam::Mat4>,
    centre: glam::Vec3,
    /// Each method but `noc`: its camera view and its cascades' views.
    cullers: Vec<(Method, View, Vec<View>)>,
    accs: HashMap<Method, Acc>,
    /// Objects `noc`'s pictures leave out, summed over views and frames: C/R's R.
    ref_culled: u64,
    motion: Motion,
}

/// The objects' updates, per frame that moved them.
struct Motion {
    update_ms: Vec<f64>,
    refit_ms: Vec<f64>,
    host_ms: Vec<f64>,
    rebuilds: usize,
    growth: Option<f64>,
}

impl Default for Motion {
    /// Nothing moved: the BVH as built (SAH growth 1).
    fn default() -> Self {
        Motion { update_ms: Vec::new(), refit_ms: Vec::new(), host_ms: Vec::new(), rebuilds: 0, growth: Some(1.0) }
    }
}

/// One frame's truths: the camera's, then each cascade's, with the
/// cascades' views of the frame.
struct Truths {
    camera: (FrameResult, Truth),
    cascades: Vec<CascadeView>,
    shadows: Vec<(FrameResult, Truth)>,
}

impl<'g, 'o> Run<'g, 'o> {
    fn new(gpu: &'g Headless, o: &'o BenchOptions, scene: Scene, path: Option<CameraPath>) -> Result<Self> {
        // Checks the options (once) before anything uses them.
        let frames = frame_count(o, path.as_ref().unwrap_or(&scene.path))?;
        let movers = crate::scene::motion::moving_objects(scene.objects.len(), o.moving);
        let base = scene.objects.iter().map(|ob| ob.transform).collect();
        let centre = scene.bounds().center();
        let desc = SessionDesc { path, timestamps: o.timestamps, samples: o.msaa, split: o.split, validate: o.validate, ..SessionDesc::new(frames, o.resolution) };
        let mut s = Session::with(gpu, scene, desc)?;
        s.set_shadow_cascades(o.shadow_cascades)?;
        s.set_projection(o.projection);
        s.culler.set_motion(o.motion)?;
        s.set_oriented_boxes(o.oriented_boxes)?;
        if o.dynamic {
            let flags: Vec<(u32, hroc::ObjectFlags)> = movers.iter().map(|&i| (i, hroc::ObjectFlags::DYNAMIC)).collect();
            s.culler.set_many_flags(&flags)?;
        }
        s.options = o.method_options.clone();
        s.shadow_triangles = o.shadow_triangles;
        let cascade_views = |m: Method| (0..s.cascade_count()).map(|c| s.create_cascade(m, c)).collect::<Result<Vec<_>>>();
        let cullers = o.methods.iter().filter(|&&m| m != Method::Noc).map(|&m| Ok((m, s.create(m)?, cascade_views(m)?))).collect::<Result<Vec<_>>>()?;
        let frames = s.cameras.len();
        Ok(Run { o, s, frames, warm: warmup_frames(frames), movers, base, centre, cullers, accs: HashMap::new(), ref_culled: 0, motion: Motion::default() })
    }

    /// Moves this frame's objects; the update's ms where any moved.
    fn update_objects(&mut self, k: usize) -> Result<Option<f64>> {
        if self.movers.is_empty() {
            return Ok(None);
        }
        let s = &mut self.s;
        let time = s.times[k];
        let moves: Vec<(u32, glam::Mat4)> = self.movers.iter().map(|&i| (i, crate::scene::motion::moved(&s.scene.name, self.centre, &self.base[i as usize], i, time))).collect();
        let t = std::time::Instant::now();
        let culler_ms = s.move_objects(&moves)?;
        // The host's uploads land now too, not in the next timed frame.
        s.gpu.queue.submit([]);
        s.gpu.wait()?;
        let m = &mut self.motion;
        m.update_ms.push(culler_ms);
        m.host_ms.push(t.elapsed().as_secs_f64() * 1e3 - culler_ms);
        let u = s.culler.last_update();
        m.refit_ms.push(u.cpu_ms);
        m.rebuilds += u.rebuilt as usize;
        m.growth = u.sah_growth;
        Ok(Some(culler_ms))
    }

    /// `noc`'s pictures of frame `k`: the camera's and each cascade's.
    fn truths(&mut self, k: usize) -> Result<Truths> {
        let n = self.s.renderer.object_count as u64;
        let camera = self.s.truth(k)?;
        let (cascades, time) = (self.s.cascades(k), self.s.times[k]);
        let shadows = if cascades.is_empty() { Vec::new() } else { self.s.cascade_truths(&cascades, time)? };
        self.ref_culled += std::iter::once(&camera).chain(&shadows).map(|(_, t)| n - t.visible.len() as u64).sum::<u64>();
        Ok(Truths { camera, cascades, shadows })
    }

    /// `noc`'s own row, from the truths' frames.
    fn noc(&mut self, k: usize, t: &mut Truths, update: Option<f64>) -> Result<()> {
        if !self.o.methods.contains(&Method::Noc) {
            return Ok(());
        }
        let (r, truth) = &mut t.camera;
        let mut c = self.s.check(r, truth)?;
        let mut views = vec![c.drawn];
        for (cs, (rc, tc)) in t.shadows.iter().enumerate() {
            let cc = self.s.check_cascade(cs as u32, rc, tc)?;
            views.push(cc.drawn);
            r.add(rc);
            c += cc;
        }
        self.record(Method::Noc, k, r, c, &views, Vec::new(), update);
        Ok(())
    }

    /// Each method's frame, with its cascades, checked against the truths.
    fn methods(&mut self, k: usize, t: &Truths, update: Option<f64>) -> Result<()> {
        let mut cullers = std::mem::take(&mut self.cullers);
        let result = cullers.iter_mut().try_for_each(|(method, view, shadow_views)| {
            let truth = &t.camera.1;
            if view.wants_oracle() {
                view.set_oracle(&self.s.culler, &truth.visible)?;
            }
            let mut r = self.s.run_frame(view, k)?;
            let mut chk = self.s.check(&r, truth)?;
            let mut stats = view.stats(&self.s.culler)?;
            let mut views = vec![chk.drawn];
            for (sv, (_, shadow_truth)) in shadow_views.iter_mut().zip(&t.shadows) {
                if sv.wants_oracle() {
                    sv.set_oracle(&self.s.culler, &shadow_truth.visible)?;
                }
            }
            let results = if shadow_views.is_empty() { Vec::new() } else { self.s.run_cascades(shadow_views, &t.cascades, self.s.times[k])? };
            for (cs, (rc, sv)) in results.iter().zip(shadow_views.iter()).enumerate() {
                let cc = self.s.check_cascade(cs as u32, rc, &t.shadows[cs].1)?;
                views.push(cc.drawn);
                // The frame's shape is every view's.
                for (st, v) in sv.shape_stats() {
                    if let Some(x) = stats.iter_mut().find(|x| x.0 == st) {
                        x.1 += v;
                    }
                }
                r.add(rc);
                chk += cc;
            }
            self.record(*method, k, &r, chk, &views, stats, update);
            Ok(())
        });
        self.cullers = cullers;
        result
    }

    /// Adds a method's frame `k` (its views' objects drawn in `views`) to its sums.
    #[allow(clippy::too_many_arguments)]
    fn record(&mut self, method: Method, k: usize, r: &FrameResult, c: Check, views: &[usize], stats: Vec<(hroc::stats::Stat, f64)>, update: Option<f64>) {
        let (n, warm) = (self.s.renderer.object_count as u64, self.warm);
        let a = self.accs.entry(method).or_default();
        a.view_drawn.resize(views.len(), 0);
        for (sum, &d) in a.view_drawn.iter_mut().zip(views) {
            *sum += d as u64;
        }
        if k >= warm {
            a.drawn_max = a.drawn_max.max(views.first().copied().unwrap_or(0) as u64);
        }
        for (st, v) in stats {
            match st {
                hroc::stats::Stat::Chosen => a.chosen.push(Method::ALL.get(v as usize).copied().unwrap_or(Method::Auto)),
                _ => {
                    if st == hroc::stats::Stat::Cut && v > 0.0 {
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
                *a.stages.entry(hroc::stats::Stage::ObjectUpdate).or_default() += ms;
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
    }

    /// The findings of validation the last frames left: every view's,
    /// once the GPU is done.
    fn validated(&mut self) -> Result<()> {
        if !self.o.validate {
            return Ok(());
        }
        let _ = self.s.gpu.device.poll(wgpu::PollType::wait_indefinitely());
        for (_, view, cascades) in self.cullers.iter_mut() {
            for v in std::iter::once(view).chain(cascades.iter_mut()) {
                v.validation(&self.s.culler)?;
            }
        }
        Ok(())
    }

    /// The rows, and the run's facts.
    fn report(self, gpu: &Headless) -> BenchReport {
        let (o, s, frames, warm) = (self.o, &self.s, self.frames, self.warm);
        let n = s.renderer.object_count as u64;
        let scene_triangles = s.scene.stats().triangles;
        let rows = o.methods.iter().map(|m| self.accs[m].row(*m, o, n, frames, warm, scene_triangles, self.ref_culled)).collect();
        let st = s.scene.stats();
        let m = self.motion;
        BenchReport {
            scene: s.scene.name.clone(),
            objects: st.objects,
            triangles: st.triangles,
            resolution: format!("{}x{}", o.resolution.0, o.resolution.1),
            adapter: gpu.adapter_name(),
            capabilities: capabilities_name(s.culler.capabilities()),
            validated: o.validate,
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
            moved_objects: self.movers.len(),
            update_ms_mean: mean(&m.update_ms),
            refit_ms_mean: mean(&m.refit_ms),
            host_update_ms_mean: mean(&m.host_ms),
            sah_growth: m.growth,
            dynamic: o.dynamic,
            refit: format!("{:?}", o.motion.refit).to_lowercase(),
            rebuilds: m.rebuilds,
            rows,
        }
    }
}

/// What one method's frames sum to.
#[derive(Default)]
struct Acc {
    wall: Vec<f64>,
    gpu: Vec<f64>,
    stages: BTreeMap<hroc::stats::Stage, f64>,
    invocations: BTreeMap<hroc::stats::Stage, hroc::stats::Invocations>,
    stats: BTreeMap<hroc::stats::Stat, f64>,
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

impl Acc {
    /// The method's row: `n` objects, over `frames` (the first `warm` untimed).
    #[allow(clippy::too_many_arguments)]
    fn row(&self, method: Method, o: &BenchOptions, n: u64, frames: usize, warm: usize, scene_triangles: u64, ref_culled: u64) -> MethodRow {
        let timed = &self.wall[warm.min(self.wall.len().saturating_sub(1))..];
        let timed_frames = self.gpu.len().max(1) as f64;
        let c_over_r = match (ref_culled, self.culled) {
            (0, 0) => 1.0,
            (0, _) => f64::INFINITY,
            (r, c) => c as f64 / r as f64,
        };
        MethodRow {
            method,
            ms_mean: mean(timed),
            ms_p95: percentile(timed, 0.95),
            gpu_ms_mean: o.timestamps.then(|| mean(&self.gpu)),
            c_over_n: self.culled as f64 / (n * frames as u64 * (1 + o.shadow_cascades as u64)) as f64,
            c_over_r,
            false_negatives: self.fneg,
            missing_pixels: self.missing,
            stray_pixels: self.stray,
            drawn_mean: self.drawn as f64 / frames as f64,
            drawn_per_view: self.view_drawn.iter().map(|&d| d as f64 / frames as f64).collect(),
            drawn_max: self.drawn_max,
            triangles_mean: self.triangles as f64 / frames as f64,
            triangles_fraction: self.triangles as f64 / (frames as f64 * self.view_drawn.len().max(1) as f64 * scene_triangles.max(1) as f64),
            stages_ms: self.stages.iter().map(|(k, v)| (*k, v / timed_frames)).collect(),
            invocations: self.invocations.iter().map(|(k, v)| (*k, InvocationsMean::of(v, timed_frames))).collect(),
            stats: self.stats.iter().map(|(k, v)| (*k, v / frames as f64)).collect(),
            frame_ms: self.wall.clone(),
            frame_triangles: self.frame_triangles.clone(),
            cut_frames: self.cut_frames.clone(),
            frame_methods: self.chosen.clone(),
            missed_frames: self.missed.clone(),
        }
    }
}
