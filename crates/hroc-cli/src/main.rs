//! `hroc`: benchmark, render and inspect occlusion culling methods.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

use hroc::options::Seed;
use hroc::{Method, MethodOptions};
use hroc_bench::bench::{self, parse_resolution, BenchOptions, MethodList, Session};
use hroc_bench::bvh::{Bvh, Split};
use hroc_bench::gpu::{Backend, Headless, Tier};
use hroc_bench::render::pictures::{self, Picture};
use hroc_bench::{Error, Result};

mod viewer;

/// The default bench: sized to finish in about a minute on a 2-core CPU with lavapipe.
const DEFAULT_SCENE: &str = "radial-city";

#[derive(Parser)]
#[command(name = "hroc", version, about = "GPU occlusion culling of massive scenes: benchmark, render, inspect")]
struct Cli {
    #[command(subcommand)]
    cmd: Option<Cmd>,
}

#[derive(Subcommand)]
enum Cmd {
    /// Runs methods side by side over one camera path; one row per method.
    Bench(BenchArgs),
    /// Renders one frame of a method to a PNG.
    Render(RenderArgs),
    /// Scene statistics and BVH build times.
    Scene {
        #[command(subcommand)]
        cmd: SceneCmd,
    },
    /// Lists the methods.
    Methods,
    /// Runs the benchmark over scenes and methods and writes the papers'
    /// tables and figures to a folder (index.html, report.md, plots).
    Report(bench::report::ReportArgs),
    /// Opens a window to fly through a scene and switch methods live.
    View(viewer::ViewArgs),
}

#[derive(clap::Args)]
struct SceneArgs {
    /// Built-in scene key or a .gltf/.glb/.obj path.
    #[arg(long, default_value = DEFAULT_SCENE)]
    scene: String,
    /// Object count of a generated scene (its default when omitted).
    #[arg(long)]
    objects: Option<usize>,
    /// Frames sampled uniformly over the camera path.
    #[arg(long, default_value_t = 60)]
    frames: usize,
    /// Frames per second of camera path instead of --frames (bench):
    /// fps × duration + 1 frames, 1/fps s apart.
    #[arg(long)]
    fps: Option<f32>,
    #[arg(long, default_value = "640x360", value_parser = parse_resolution)]
    resolution: (u32, u32),
    #[arg(long, default_value_t = Split::Sah)]
    split: Split,
    /// Split every mesh of at least twice T triangles into clusters of at
    /// most T (a multiple of 4), each a cullable object with its own box
    /// (meshoptimizer's spatial clustering): T, `off`, or `auto` (files:
    /// 256, where a one-mesh interior measured 0.43 × noc against 1.14
    /// without; generated scenes, whose small props measured no better:
    /// off).
    #[arg(long, default_value = "auto", value_parser = parse_clusters)]
    clusters: Clusters,
    /// Give the culler each rotated object's mesh (or cluster) box in its
    /// own frame, which HROC tests where it meets the world box: `true` or
    /// `false`.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    oriented_boxes: bool,
    /// JSON camera path file (keys of t, eye, target, up, fov_y_deg), or a
    /// built-in path of the scene: `hard` (cuts, the eye inside boxes,
    /// boxes across the near plane) or `cuts` (a cut every second to a
    /// random eye and height, 720°/s turns).
    #[arg(long)]
    camera_path: Option<PathBuf>,
    /// Graphics API: `vulkan`, or `gl` (OpenGL through EGL, no display).
    #[arg(long, default_value_t = Backend::Vulkan)]
    backend: Backend,
    /// What the culler runs with: `full` (the indirect draw count, early-Z
    /// marks, read-only depth attachments), `portable` (an emulated count,
    /// ID marks, box tests that load depth: what every backend has, and
    /// what Metal runs), what wgpu 30 gives `gl` or `dx12`, or `boxes` (the
    /// full device, marks from boxes: an engine's shaders that do not
    /// mark); the most the device allows when omitted.
    #[arg(long)]
    tier: Option<Tier>,
    #[command(flatten)]
    m: MethodArgs,
}

impl SceneArgs {
    /// The device these arguments ask for.
    fn device(&self) -> Result<Headless> {
        open_device(self.backend, self.tier)
    }
}

/// An MSAA sample count wgpu takes on every device: 1 or 4 (clap value parser).
fn parse_msaa(s: &str) -> std::result::Result<u32, String> {
    let n = s.parse::<u32>().map_err(|_| format!("--msaa {s} is not a count of samples"))?;
    bench::session::check_samples(n).map_err(|e| e.to_string())?;
    Ok(n)
}

/// The methods of `hroc bench` with no `--methods`: no culling, frustum
/// culling, the ideal and HROC.
const DEFAULT_TABLE: [Method; 4] = [Method::Noc, Method::Vfc, Method::Ref, Method::HROC];

/// `START:BOTTOM`, BVH depths from the root (0), START <= BOTTOM (`--ioc-range`).
fn parse_ioc_range(s: &str) -> std::result::Result<(u32, u32), String> {
    let (a, b) = s.split_once(':').ok_or_else(|| format!("IOC range '{s}' is not START:BOTTOM"))?;
    let start: u32 = a.trim().parse().map_err(|_| format!("bad start depth in IOC range '{s}'"))?;
    let bottom: u32 = b.trim().parse().map_err(|_| format!("bad bottom depth in IOC range '{s}'"))?;
    if start > bottom {
        return Err(format!("IOC range '{s}': start depth {start} is deeper than the bottom depth {bottom}"));
    }
    Ok((start, bottom))
}

fn open_device(backend: Backend, tier: Option<Tier>) -> Result<Headless> {
    let mut gpu = Headless::open(backend)?;
    gpu.capabilities = tier.map(Tier::capabilities);
    Ok(gpu)
}

/// Method parameters (`hroc::MethodOptions`; defaults as documented there).
#[derive(clap::Args)]
struct MethodArgs {
    /// soq: BASE_TIME of Kovalčík & Sochor 2005, seconds of camera path.
    #[arg(long, default_value_t = 2.0 / 3.0, value_parser = parse_positive)]
    soq_base_time: f32,
    /// chc++: previously invisible nodes per query batch (b).
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    chc_batch: u64,
    /// chc++: frames a visible leaf goes unqueried (n_av).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..))]
    chc_nav: u32,
    /// chc++: levels of descendants for tighter bounds (d_max).
    #[arg(long, default_value_t = 4)]
    chc_dmax: u32,
    /// chc++: largest summed-area ratio of tighter bounds (s_max).
    #[arg(long, default_value_t = 1.4, value_parser = parse_positive)]
    chc_smax: f32,
    /// ioc: BVH depths START:BOTTOM tested level by level (root = 0;
    /// default: the middle of the BVH, depth/2-1:depth/2+1).
    #[arg(long, value_parser = parse_ioc_range)]
    ioc_range: Option<(u32, u32)>,
    /// hroc: when a coarse ray grid seeds the occluders: cuts (and where
    /// the occluders' depth leaves holes), cuts-only, always, never.
    #[arg(long, default_value = "cuts")]
    hroc_seed: Seed,
    /// hroc: pixels per side of the occlusion test's blocks, 1 to 8 (one
    /// ray per block; the largest size up to this that divides the resolution).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=8))]
    hroc_test_scale: u32,
    /// hroc with OF: occluder filtering reads one pixel in every S × S,
    /// 1 to 8 (1: every pixel, the paper's).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=8))]
    hroc_filter_stride: u32,
    /// hroc: rounds of occludee rendering, 1 to 4 (1: the paper's, every
    /// occludee drawn; more: front to back, each round drawing the
    /// occludees nearest in some block and testing the rest again).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=MethodOptions::MAX_HROC_ROUNDS as i64))]
    hroc_rounds: u32,
    /// hroc: draw V front to back too: the objects nearest in some block
    /// first, then those still in front of them; the rest join the
    /// occludees.
    #[arg(long)]
    hroc_occluder_rounds: bool,
    /// hroc: in a view where occlusion culled less than this share of the
    /// frustum's objects (measured one frame in 8), cull by the frustum
    /// alone until the next measurement, 0 to 1 (0: always by occlusion).
    #[arg(long, default_value_t = 0.05, value_parser = parse_share)]
    hroc_frustum_below: f32,
    /// hroc, in the shadow cascades' views (drawn depth only): ... or
    /// where it culled under half of them and fewer triangles than this
    /// many per pixel of the view (a light's cascade culling a few roofs),
    /// 0 or more (0: the share alone decides; cameras always).
    #[arg(long, default_value_t = hroc::options::DEPTH_ONLY_TRIANGLES)]
    hroc_frustum_triangles: f32,
    /// Degrees the view may turn between frames before the frame is culled
    /// as after a camera cut (`inf`: never).
    #[arg(long, default_value_t = 45.0)]
    cut_turn: f32,
    /// Fraction of the scene's diagonal the eye may move between frames
    /// before the frame is culled as after a camera cut (`inf`: never).
    #[arg(long, default_value_t = 0.1)]
    cut_move: f32,
}

impl MethodArgs {
    fn options(&self) -> MethodOptions {
        MethodOptions {
            soq_base_time: self.soq_base_time,
            chc_batch: self.chc_batch as usize,
            chc_nav: self.chc_nav,
            chc_dmax: self.chc_dmax,
            chc_smax: self.chc_smax,
            ioc_range: self.ioc_range,
            hroc_seed: self.hroc_seed,
            hroc_test_scale: self.hroc_test_scale,
            hroc_filter_stride: self.hroc_filter_stride,
            hroc_rounds: self.hroc_rounds,
            hroc_occluder_rounds: self.hroc_occluder_rounds,
            hroc_frustum_below: self.hroc_frustum_below,
            // (The bench hands it to the cascades' views alone.)
            hroc_frustum_triangles: 0.0,
            box_marks_scale: 1,
            cut_turn_deg: self.cut_turn,
            cut_move: self.cut_move,
        }
    }
}

fn parse_share(s: &str) -> std::result::Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a share from 0 to 1")),
    }
}

fn parse_positive(s: &str) -> std::result::Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("'{s}' is not a positive number")),
    }
}

#[derive(clap::Args)]
struct BenchArgs {
    #[command(flatten)]
    s: SceneArgs,
    /// Comma-separated methods, or `all`.
    #[arg(long, default_value_t = MethodList(DEFAULT_TABLE.to_vec()))]
    methods: MethodList,
    /// Writes the report as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Prints the table as Markdown.
    #[arg(long)]
    markdown: bool,
    /// Also prints GPU ms per stage (timestamp queries, which only this
    /// turns on: each one flushes a CPU rasterizer, adding to ms/frame),
    /// per-frame method statistics, and shader invocations per stage
    /// (pipeline-statistics queries, where the device has them).
    #[arg(long)]
    breakdown: bool,
    /// Validate every view's draws on the GPU (hroc::CullerDesc::validation):
    /// a host mistake fails the run with what it was and its fix. Adds a
    /// few passes to every frame; the table states whether it ran.
    #[arg(long)]
    validate: bool,
    /// Samples per pixel of the camera's colour, depth and object-ID
    /// targets: 1 (none) or 4 (the count wgpu multisamples on every
    /// device; the IDs then `Rg16Uint`).
    #[arg(long, default_value_t = 1, value_parser = parse_msaa)]
    msaa: u32,
    /// Light the scene with a directional light whose shadow map has this
    /// many cascades (0 to 4): each an orthographic view, drawn with depth
    /// bias into a layer of one depth array, culled by every method as a
    /// view of its own and checked against its own unculled picture.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=4))]
    shadow_cascades: u32,
    /// How the camera projects: `perspective`, or `orthographic` (parallel
    /// rays through a box as large as the perspective frustum at the
    /// distance of the scene's centre: the path seen as a light's cascade
    /// sees a scene).
    #[arg(long, default_value = "perspective")]
    projection: bench::Projection,
    /// Fractions of the objects that move every frame, 0 to 1, each run in
    /// turn (e.g. `0,0.1,1`), with a motion table after them; the query
    /// methods take static scenes only.
    #[arg(long, default_value = "0", value_delimiter = ',')]
    moving: Vec<f32>,
    /// Flag the moving objects DYNAMIC (tested alone, HROC §6's hybrid)
    /// instead of refitting them into the BVH.
    #[arg(long)]
    dynamic: bool,
    /// Where the BVH is refit: cpu or gpu.
    #[arg(long, default_value = "cpu", value_parser = parse_refit)]
    refit: hroc::options::Refit,
    /// Rebuild the BVH when refits raise its SAH cost past this multiple of
    /// its cost as built (`inf`: never).
    #[arg(long, default_value_t = hroc::options::MotionOptions::default().rebuild_sah_growth)]
    rebuild_growth: f64,
}

fn parse_refit(s: &str) -> std::result::Result<hroc::options::Refit, String> {
    match s {
        "cpu" => Ok(hroc::options::Refit::Cpu),
        "gpu" => Ok(hroc::options::Refit::Gpu),
        _ => Err(format!("'{s}' is not cpu or gpu")),
    }
}

#[derive(clap::Args)]
struct RenderArgs {
    #[command(flatten)]
    s: SceneArgs,
    #[arg(long, default_value_t = Method::Noc)]
    method: Method,
    /// Frame of the path to render (earlier frames run first: methods use temporal coherence).
    #[arg(long, default_value_t = 0)]
    frame: usize,
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value_t = Picture::Color)]
    view: Picture,
}

#[derive(Subcommand)]
enum SceneCmd {
    /// Objects, triangles, vertices, BVH nodes, depth and build ms per split.
    Info {
        /// Built-in scene key or a .gltf/.glb/.obj path.
        scene: String,
        #[arg(long)]
        objects: Option<usize>,
    },
    /// Lists the built-in scenes.
    List,
    /// Writes a scene out as .obj or .glb (and its camera path as JSON):
    /// generated scenes measured as the files real assets come in.
    Export {
        /// Built-in scene key or a .gltf/.glb/.obj path.
        scene: String,
        #[arg(long)]
        objects: Option<usize>,
        /// The file to write: .obj or .glb.
        #[arg(long)]
        out: PathBuf,
        /// The whole scene as one mesh in world space (one object), as
        /// interiors and city blocks often come.
        #[arg(long)]
        single_mesh: bool,
        /// Also write the scene's camera path here (for `--camera-path`).
        #[arg(long)]
        path_out: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    // The Vulkan loader warns on every start without it.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        let dir = std::env::temp_dir().join("hroc-xdg");
        if std::fs::create_dir_all(&dir).is_ok() {
            std::env::set_var("XDG_RUNTIME_DIR", dir);
        }
    }
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    // No subcommand: the default bench.
    let cmd = match cli.cmd {
        Some(c) => c,
        None => Cli::parse_from(["hroc", "bench"]).cmd.ok_or_else(|| Error::Options("no command".into()))?,
    };
    match cmd {
        Cmd::Bench(a) => bench_cmd(a),
        Cmd::Render(a) => render_cmd(a),
        Cmd::Scene { cmd: SceneCmd::Info { scene, objects } } => scene_info(&scene, objects),
        Cmd::Scene { cmd: SceneCmd::Export { scene, objects, out, single_mesh, path_out } } => {
            let mut s = loading(&scene, || Ok(hroc_bench::scene::load(&scene, objects, 0)?))?;
            if single_mesh {
                s = s.merged();
            }
            hroc_bench::scene::export::write(&s, &out)?;
            if let Some(p) = path_out {
                hroc_bench::scene::export::write_path(&s.path, &p)?;
            }
            let st = s.stats();
            eprintln!("wrote {}: {} objects, {} triangles", out.display(), st.objects, st.triangles);
            Ok(())
        }
        Cmd::Scene { cmd: SceneCmd::List } => {
            for g in hroc_bench::scene::generators::keys() {
                println!("{g}");
            }
            Ok(())
        }
        Cmd::Report(a) => bench::report::run(a),
        Cmd::View(a) => viewer::run(a),
        Cmd::Methods => {
            for (name, what) in hroc::Method::names().into_iter().map(|(n, _, w)| (n, w)) {
                println!("{name:<8} {what}");
            }
            Ok(())
        }
    }
}

fn check_frames(frames: usize) -> Result<()> {
    if frames == 0 {
        return Err(Error::Options("--frames must be at least 1".into()));
    }
    Ok(())
}

fn bench_cmd(a: BenchArgs) -> Result<()> {
    check_frames(a.s.frames)?;
    let methods = a.methods.0.clone();
    // Load and check the inputs before touching the GPU: bad files fail fast.
    let clusters = a.s.clusters.triangles(&a.s.scene);
    let (backend, tier) = (a.s.backend, a.s.tier);
    let opts = BenchOptions {
        scene: a.s.scene,
        objects: a.s.objects,
        methods,
        frames: a.s.frames,
        fps: a.s.fps,
        resolution: a.s.resolution,
        split: a.s.split,
        clusters,
        oriented_boxes: a.s.oriented_boxes,
        method_options: a.s.m.options(),
        camera_path: a.s.camera_path,
        progress: true,
        moving: a.moving.first().copied().unwrap_or(0.0),
        dynamic: a.dynamic,
        motion: hroc::options::MotionOptions { refit: a.refit, rebuild_sah_growth: a.rebuild_growth, ..Default::default() },
        timestamps: a.breakdown,
        validate: a.validate,
        msaa: a.msaa,
        shadow_cascades: a.shadow_cascades,
        shadow_triangles: a.s.m.hroc_frustum_triangles,
        projection: a.projection,
    };
    for &moving in &a.moving {
        BenchOptions { moving, ..opts.clone() }.check()?;
    }
    let (scene, path) = loading(&opts.scene, || bench::load_inputs(&opts))?;
    let gpu = open_device(backend, tier)?;
    let mut reports = Vec::new();
    for (k, &moving) in a.moving.iter().enumerate() {
        let o = BenchOptions { moving, ..opts.clone() };
        // Each fraction starts from the scene as generated.
        let (scene, path) = if k + 1 == a.moving.len() { (scene.clone(), path.clone()) } else { bench::load_inputs(&o)? };
        let report = bench::run_scene(&gpu, &o, scene, path)?;
        if k > 0 {
            println!();
        }
        print!("{}", bench::table::render(&report, a.markdown));
        if a.breakdown {
            print!("\n{}", bench::table::breakdown(&report, a.markdown));
            if let Some(t) = bench::table::invocations(&report, a.markdown) {
                print!("\nShader invocations per frame (pipeline statistics)\n{t}");
            }
        }
        reports.push(report);
    }
    if reports.len() > 1 {
        print!("\n{}", bench::table::motion(&reports, a.markdown));
    }
    if let Some(path) = a.json {
        let text = match reports.as_slice() {
            [one] => serde_json::to_string_pretty(one),
            all => serde_json::to_string_pretty(all),
        }
        .map_err(|e| Error::Options(e.to_string()))?;
        std::fs::write(&path, text).map_err(|e| Error::Write { path, source: e })?;
    }
    Ok(())
}

fn render_cmd(a: RenderArgs) -> Result<()> {
    check_frames(a.s.frames)?;
    let method = a.method;
    if a.frame >= a.s.frames {
        return Err(Error::Options(format!("--frame {} is past the last frame ({} frames)", a.frame, a.s.frames)));
    }
    let s = &a.s;
    let mut scene = loading(&s.scene, || Ok(hroc_bench::scene::load(&s.scene, s.objects, 0)?))?;
    if let Some(t) = s.clusters.triangles(&s.scene) {
        scene = scene.clustered(hroc_bench::scene::ClusterOptions::new(t))?;
    }
    let path = s.camera_path.as_deref().map(|p| bench::load_path(&scene, p)).transpose()?;
    let gpu = s.device()?;
    let mut session = Session::new(&gpu, scene, path, s.frames, s.resolution, s.split)?;
    session.set_oriented_boxes(s.oriented_boxes)?;
    session.options = s.m.options();
    let mut culler = session.create(method)?;
    let mut last = None;
    for k in 0..=a.frame {
        if culler.wants_oracle() {
            let (_, truth) = session.truth(k)?;
            culler.set_oracle(&session.culler, &truth.visible)?;
        }
        last = Some(session.run_frame(&mut culler, k)?);
    }
    let lists = last.map(|r| r.lists).unwrap_or_default();
    let px = if a.view == Picture::Groups {
        let nodes = culler
            .tested_nodes(&session.culler)?
            .ok_or_else(|| Error::Options(format!("{method} tests no boxes; the groups view is for box-testing methods (hroc, roc, roc-all, ioc)")))?;
        let mut px = pictures::capture(&gpu, &session.renderer, Picture::Color, &lists)?;
        let boxes: Vec<_> = nodes.iter().map(|&n| (session.bvh().aabb(n), if session.bvh().is_leaf(n) { [255, 220, 0, 255] } else { [255, 40, 40, 255] })).collect();
        let vp = session.cameras[a.frame].view_proj(session.renderer.aspect());
        pictures::draw_boxes(&mut px, s.resolution, &vp, &boxes);
        px
    } else {
        pictures::capture(&gpu, &session.renderer, a.view, &lists)?
    };
    pictures::save_png(&a.out, s.resolution.0, s.resolution.1, &px)?;
    eprintln!("wrote {}", a.out.display());
    Ok(())
}

/// `--clusters`: a cluster size, none, or the default for the scene.
#[derive(Clone, Copy, Debug)]
enum Clusters {
    Off,
    Auto,
    Triangles(u32),
}

/// Cluster size of loaded files under `--clusters auto` (BENCHMARKS.md:
/// rooms as one mesh, 64–1024 measured; 256 keeps draws few).
const AUTO_FILE_CLUSTERS: u32 = 256;

impl Clusters {
    /// The cluster size for scene `spec`, if any.
    fn triangles(self, spec: &str) -> Option<u32> {
        match self {
            Clusters::Off => None,
            Clusters::Triangles(t) => Some(t),
            Clusters::Auto => hroc_bench::scene::generators::find(spec).is_none().then_some(AUTO_FILE_CLUSTERS),
        }
    }
}

fn parse_clusters(s: &str) -> std::result::Result<Clusters, String> {
    match s {
        "off" => Ok(Clusters::Off),
        "auto" => Ok(Clusters::Auto),
        t => t.parse().map(Clusters::Triangles).map_err(|_| format!("'{t}' is not a cluster size in triangles, off or auto")),
    }
}

/// Runs `load` with a spinner and the elapsed time on a terminal (big files
/// and clustering take seconds); nothing is drawn when stderr is not one.
fn loading<T>(what: &str, load: impl FnOnce() -> Result<T>) -> Result<T> {
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_style(indicatif::ProgressStyle::with_template("{spinner} loading {msg} ({elapsed})").unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()));
    bar.set_message(what.to_string());
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    let r = load();
    bar.finish_and_clear();
    r
}

fn scene_info(spec: &str, objects: Option<usize>) -> Result<()> {
    let t = std::time::Instant::now();
    let scene = loading(spec, || Ok(hroc_bench::scene::load(spec, objects, 0)?))?;
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let st = scene.stats();
    println!("scene      {}", scene.name);
    println!("objects    {}", st.objects);
    println!("meshes     {}", st.meshes);
    println!("triangles  {} ({} stored)", st.triangles, st.unique_triangles);
    println!("vertices   {}", st.vertices);
    let b = scene.bounds();
    println!("bounds     {:?} .. {:?}", b.min.to_array(), b.max.to_array());
    println!("load ms    {load_ms:.1}");
    let boxes: Vec<_> = scene.objects.iter().map(|o| o.bounds).collect();
    println!("{:<6} {:>10} {:>6} {:>10} {:>10}", "split", "BVH nodes", "depth", "build ms", "SAH cost");
    for split in [Split::Sah, Split::Mid, Split::Eq] {
        let bvh = Bvh::build(&boxes, split);
        println!("{:<6} {:>10} {:>6} {:>10.1} {:>10.1}", split.to_string(), bvh.nodes.len(), bvh.depth(), bvh.build_ms, bvh.sah_cost());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn ioc_ranges_parse() {
        assert_eq!(super::parse_ioc_range("9:11"), Ok((9, 11)));
        assert_eq!(super::parse_ioc_range("0:0"), Ok((0, 0)));
        for bad in ["11:9", "9", "a:3", "3:", "-1:2"] {
            assert!(super::parse_ioc_range(bad).is_err(), "{bad}");
        }
    }
}
