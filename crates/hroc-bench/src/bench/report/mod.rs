//! `hroc report`: the papers' tables and figures for this machine, in one
//! folder: `index.html`, `report.md`, `data.json`, `plots/` (SVG + PNG) and
//! `images/` (overdraw heat maps).
//!
//! The run is a fixed sequence of measurements (each a [`super::run_scene`],
//! so every row is also checked against `noc`), then one pass that writes
//! the document: `sections` turns the measurements into tables and
//! figures, [`doc`] renders them as Markdown and HTML.

pub mod doc;
mod heat;
mod sections;

use serde::Serialize;
use std::path::{Path, PathBuf};

use super::{parse_resolution, BenchOptions, BenchReport, MethodList};
use crate::bvh::{Bvh, Split};
use crate::error::{Error, Result};
use crate::gpu::Headless;
use crate::scene::{self, generators, Scene};
use hroc::options::Variant;
use hroc::{Method, MethodOptions};

/// The default set: the HROC paper's three large scenes (RC, FC, ST), sized
/// so that the whole report takes under 15 minutes on a 2-core CPU with lavapipe.
pub const DEFAULT_SCENES: &str = "radial-city,factory,satellites";
/// Every conservative raster method; the query methods (`oq`, `soq`,
/// `chc++`) wait on the CPU per query batch and are opt-in.
pub fn default_methods() -> MethodList {
    let [na, cr, of, cr_of] = hroc_variants();
    MethodList(vec![Method::Noc, Method::Vfc, Method::Ref, Method::Roc, Method::Hzb, Method::Ioc, na, cr, of, cr_of])
}

/// The HROC paper's Table 3 columns: NA, CR, OF and CR+OF.
pub fn hroc_variants() -> [Method; 4] {
    [Variant::NA, Variant::CR, Variant::OF, Variant::CR_OF].map(Method::Hroc)
}

/// The peers of a sweep, the motion table and the high-resolution run.
fn peers(with: &[Method]) -> MethodList {
    MethodList([Method::Noc].iter().chain(with).chain(&[Method::Roc, Method::Hzb, Method::HROC]).copied().collect())
}

/// Command-line options of `hroc report`.
#[derive(clap::Args, Debug, Clone)]
pub struct ReportArgs {
    /// Output folder (created; files in it are overwritten).
    #[arg(long)]
    pub out: PathBuf,
    /// Comma-separated scenes: built-in keys or .gltf/.glb/.obj paths.
    #[arg(long, default_value = DEFAULT_SCENES)]
    pub scenes: String,
    /// Comma-separated methods, or `all`.
    #[arg(long, default_value_t = default_methods())]
    pub methods: MethodList,
    /// Objects per generated scene (files keep their own).
    #[arg(long, default_value_t = 10_000)]
    pub objects: usize,
    /// Frames sampled over each 10 s camera path.
    #[arg(long, default_value_t = 60)]
    pub frames: usize,
    #[arg(long, default_value = "640x360", value_parser = parse_resolution)]
    pub resolution: (u32, u32),
    /// BVH splits compared with the HROC variants (Lee's thesis, Table 4);
    /// `sah` alone leaves the table out.
    #[arg(long, default_value = "sah,mid,eq")]
    pub splits: String,
    /// Frame of the first scene's overdraw heat maps (default: mid-path).
    #[arg(long)]
    pub heat_frame: Option<usize>,
    /// Object counts of the scale sweep over the first generated scene, or `none`.
    #[arg(long, default_value = "100,1000,4000,16000,64000,256000,1000000")]
    pub sweep: String,
    /// The sweep's methods: the peers, and `auto` on top.
    #[arg(long, default_value_t = MethodList(peers(&[Method::Vfc]).0.into_iter().chain([Method::Auto]).collect()))]
    pub sweep_methods: MethodList,
    /// Frames of each sweep run (4 untimed; `auto` calibrates in its first
    /// ten or so).
    #[arg(long, default_value_t = 24)]
    pub sweep_frames: usize,
    /// Resolution of the high-resolution run on the first scene (the
    /// paper's Table 2, 4096x2160), or `none`.
    #[arg(long, default_value = "4096x2160")]
    pub hires: String,
    #[arg(long, default_value_t = peers(&[Method::Ref]))]
    pub hires_methods: MethodList,
    #[arg(long, default_value_t = 8)]
    pub hires_frames: usize,
    /// Moving fractions of the motion table over the first generated
    /// scene (each run in turn, like `hroc bench --moving`), or `none`.
    #[arg(long, default_value = "0,0.1,1")]
    pub motion: String,
    /// Methods of the motion table: those that take moving objects.
    #[arg(long, default_value_t = peers(&[Method::Vfc]))]
    pub motion_methods: MethodList,
    /// Cluster sizes (triangles) of the clusters table, each against the
    /// scene without clusters, or `none`.
    #[arg(long, default_value = "64,256")]
    pub clusters: String,
    /// Validate every view's draws in every measurement (`hroc bench
    /// --validate`); the report states whether it did.
    #[arg(long)]
    pub validate: bool,
    /// The clusters table's scene (a key or a file): factory's racks and
    /// machines are meshes large enough to split.
    #[arg(long, default_value = "factory")]
    pub cluster_scene: String,
    #[arg(long, default_value_t = MethodList(vec![Method::Noc, Method::Ref, Method::Hzb, Method::HROC]))]
    pub cluster_methods: MethodList,
}

/// The validated plan of a report.
struct Plan {
    scenes: Vec<String>,
    methods: Vec<Method>,
    splits: Vec<Split>,
    heat_frame: usize,
    sweep: Vec<usize>,
    sweep_methods: Vec<Method>,
    hires: Option<(u32, u32)>,
    hires_methods: Vec<Method>,
    motion: Vec<f64>,
    motion_methods: Vec<Method>,
    clusters: Vec<u32>,
    cluster_methods: Vec<Method>,
}

fn list(s: &str) -> Vec<String> {
    s.split(',').map(str::trim).filter(|x| !x.is_empty()).map(String::from).collect()
}

impl Plan {
    fn new(a: &ReportArgs) -> Result<Plan> {
        let scenes = list(&a.scenes);
        if scenes.is_empty() {
            return Err(Error::Options("--scenes names no scene".into()));
        }
        for (flag, n) in [("--frames", a.frames), ("--sweep-frames", a.sweep_frames), ("--hires-frames", a.hires_frames), ("--objects", a.objects)] {
            if n == 0 {
                return Err(Error::Options(format!("{flag} must be at least 1")));
            }
        }
        let heat_frame = a.heat_frame.unwrap_or(a.frames / 2);
        if heat_frame >= a.frames {
            return Err(Error::Options(format!("--heat-frame {heat_frame} is past the last frame ({} frames)", a.frames)));
        }
        let splits = list(&a.splits).iter().map(|s| s.parse::<Split>().map_err(|_| Error::Options(format!("unknown split '{s}' (sah, mid, eq)")))).collect::<Result<Vec<_>>>()?;
        let sweep = if a.sweep.trim() == "none" {
            Vec::new()
        } else {
            list(&a.sweep)
                .iter()
                .map(|s| s.parse::<usize>().ok().filter(|&n| n > 0).ok_or_else(|| Error::Options(format!("--sweep: '{s}' is not an object count"))))
                .collect::<Result<Vec<_>>>()?
        };
        let hires = if a.hires.trim() == "none" { None } else { Some(parse_resolution(&a.hires).map_err(Error::Options)?) };
        let motion = if a.motion.trim() == "none" {
            Vec::new()
        } else {
            list(&a.motion)
                .iter()
                .map(|s| s.parse::<f64>().ok().filter(|f| (0.0..=1.0).contains(f)).ok_or_else(|| Error::Options(format!("--motion: '{s}' is not a fraction from 0 to 1"))))
                .collect::<Result<Vec<_>>>()?
        };
        let motion_methods = with_noc(a.motion_methods.0.clone());
        if let Some(m) = motion_methods.iter().find(|m| !m.takes_motion()) {
            return Err(Error::Options(format!("--motion-methods: {m} takes static scenes only")));
        }
        let clusters = if a.clusters.trim() == "none" {
            Vec::new()
        } else {
            list(&a.clusters)
                .iter()
                .map(|s| {
                    s.parse::<u32>()
                        .ok()
                        .filter(|t| *t >= 4 && t.is_multiple_of(4))
                        .ok_or_else(|| Error::Options(format!("--clusters: '{s}' is not a cluster size (a multiple of 4)")))
                })
                .collect::<Result<Vec<_>>>()?
        };
        Ok(Plan {
            clusters,
            cluster_methods: with_noc(a.cluster_methods.0.clone()),
            scenes,
            methods: with_noc(a.methods.0.clone()),
            splits,
            heat_frame,
            sweep,
            sweep_methods: with_noc(a.sweep_methods.0.clone()),
            hires,
            hires_methods: with_noc(a.hires_methods.0.clone()),
            motion,
            motion_methods,
        })
    }
}

/// Every table states times relative to drawing everything: `noc` is always run.
fn with_noc(mut m: Vec<Method>) -> Vec<Method> {
    if !m.contains(&Method::Noc) {
        m.insert(0, Method::Noc);
    }
    m
}

/// One BVH build of a scene (Lee's thesis, Table 1).
#[derive(Clone, Debug, Serialize)]
pub struct BvhInfo {
    pub split: String,
    pub nodes: usize,
    pub depth: u32,
    pub build_ms: f64,
    pub sah_cost: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct SceneResult {
    pub spec: String,
    pub stats: scene::SceneStats,
    pub extent: [f32; 3],
    pub bvh: Vec<BvhInfo>,
    /// Every method with the SAH BVH.
    pub main: BenchReport,
    /// HROC variants with the other splits.
    pub splits: Vec<BenchReport>,
}

#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    pub objects: usize,
    pub report: BenchReport,
}

#[derive(Clone, Debug, Serialize)]
pub struct Meta {
    pub date: String,
    pub command: String,
    pub adapter: String,
    pub device_type: String,
    pub backend: String,
    pub driver: String,
    pub version: String,
    pub frames: usize,
    pub resolution: String,
    pub minutes: f64,
    /// Every measurement validated the views' draws, with no finding.
    #[serde(default)]
    pub validated: bool,
}

/// Everything measured; also written as `data.json`.
#[derive(Clone, Debug, Serialize)]
pub struct ReportData {
    pub meta: Meta,
    pub scenes: Vec<SceneResult>,
    pub heat: heat::HeatMaps,
    pub sweep: Vec<SweepPoint>,
    /// Why the sweep stopped early, if it did (a device limit, memory).
    pub sweep_stopped: Option<String>,
    pub hires: Option<BenchReport>,
    pub hires_skipped: Option<String>,
    /// The motion table's runs, one per moving fraction.
    pub motion: Vec<BenchReport>,
    /// The clusters table's runs: the first scene without clusters, then
    /// with each cluster size.
    pub clusters: Vec<ClusterRun>,
}

/// One run of the clusters table.
#[derive(Clone, Debug, Serialize)]
pub struct ClusterRun {
    /// Triangles per cluster at most; `None`: whole objects.
    pub triangles: Option<u32>,
    pub report: BenchReport,
}

pub fn run(a: ReportArgs) -> Result<()> {
    let plan = Plan::new(&a)?;
    let started = std::time::Instant::now();
    // Bad scene files fail here, before the GPU starts.
    let scenes = plan.scenes.iter().map(|s| scene::load(s, Some(a.objects), 0)).collect::<hroc_scene::Result<Vec<Scene>>>()?;
    if !plan.clusters.is_empty() {
        scene::load(&a.cluster_scene, Some(a.objects), 0)?;
    }
    let gpu = Headless::new()?;
    for dir in [a.out.clone(), a.out.join("plots"), a.out.join("images")] {
        std::fs::create_dir_all(&dir).map_err(|e| Error::Write { path: dir, source: e })?;
    }
    let steps = scenes.len() * (1 + usize::from(plan.splits.iter().any(|&s| s != Split::Sah)))
        + 1
        + plan.sweep.len()
        + usize::from(plan.hires.is_some())
        + plan.motion.len()
        + plan.clusters.len()
        + usize::from(!plan.clusters.is_empty());
    let mut r = Runner { gpu: &gpu, a: &a, plan: &plan, step: 0, steps };

    // The measurements, in the report's order.
    let results = plan.scenes.iter().zip(&scenes).map(|(spec, scene)| r.scene(spec, scene)).collect::<Result<Vec<_>>>()?;
    r.say(format!("{}: overdraw heat maps at frame {}", plan.scenes[0], plan.heat_frame));
    let heat = heat::render(&gpu, &scenes[0], a.frames, a.resolution, plan.heat_frame, &a.out.join("images"))?;
    let (sweep, sweep_stopped) = r.sweep();
    let (hires, hires_skipped) = r.hires(&scenes[0])?;
    let motion = r.motion()?;
    let clusters = r.clusters()?;

    let info = &gpu.info;
    let data = ReportData {
        meta: Meta {
            date: utc_now(),
            command: std::iter::once("hroc".to_string()).chain(std::env::args().skip(1)).collect::<Vec<_>>().join(" "),
            adapter: info.name.clone(),
            device_type: format!("{:?}", info.device_type),
            backend: format!("{:?}", info.backend),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            frames: a.frames,
            resolution: format!("{}x{}", a.resolution.0, a.resolution.1),
            minutes: started.elapsed().as_secs_f64() / 60.0,
            validated: a.validate,
        },
        scenes: results,
        heat,
        sweep,
        sweep_stopped,
        hires,
        hires_skipped,
        motion,
        clusters,
    };
    write(&a.out, &data)?;
    eprintln!("wrote {} in {:.1} min", a.out.join("index.html").display(), data.meta.minutes);
    Ok(())
}

/// Runs the report's measurements, numbering them on stderr.
struct Runner<'a> {
    gpu: &'a Headless,
    a: &'a ReportArgs,
    plan: &'a Plan,
    step: usize,
    steps: usize,
}

impl Runner<'_> {
    fn say(&mut self, what: String) {
        self.step += 1;
        eprintln!("[{}/{}] {what}", self.step, self.steps);
    }

    fn opts(&self, spec: &str, methods: &[Method], frames: usize, resolution: (u32, u32), split: Split) -> BenchOptions {
        BenchOptions {
            scene: spec.to_string(),
            objects: Some(self.a.objects),
            methods: methods.to_vec(),
            frames,
            fps: None,
            resolution,
            split,
            clusters: None,
            oriented_boxes: true,
            camera_path: None,
            progress: true,
            moving: 0.0,
            dynamic: false,
            motion: hroc::options::MotionOptions::default(),
            method_options: MethodOptions::default(),
            // The report plots HROC's stages (the paper's Figure 6).
            timestamps: true,
            msaa: 1,
            shadow_cascades: 0,
            shadow_triangles: hroc::options::DEPTH_ONLY_TRIANGLES,
            projection: super::Projection::Perspective,
            validate: self.a.validate,
        }
    }

    /// Every method with the SAH BVH, then the HROC variants with the other splits.
    fn scene(&mut self, spec: &str, scene: &Scene) -> Result<SceneResult> {
        let (a, plan) = (self.a, self.plan);
        self.say(format!("{spec}: {} methods, {} frames", plan.methods.len(), a.frames));
        let boxes: Vec<_> = scene.objects.iter().map(|o| o.bounds).collect();
        let bvh = [Split::Sah, Split::Mid, Split::Eq]
            .into_iter()
            .map(|split| {
                let b = Bvh::build(&boxes, split);
                BvhInfo { split: split.to_string(), nodes: b.nodes.len(), depth: b.depth(), build_ms: b.build_ms, sah_cost: b.sah_cost() }
            })
            .collect();
        let main = super::run_scene(self.gpu, &self.opts(spec, &plan.methods, a.frames, a.resolution, Split::Sah), scene.clone(), None)?;
        let mut splits = Vec::new();
        let others: Vec<Split> = plan.splits.iter().copied().filter(|&s| s != Split::Sah).collect();
        if !others.is_empty() {
            self.say(format!("{spec}: HROC variants with {} BVHs", others.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")));
            let methods = with_noc(hroc_variants().to_vec());
            for split in others {
                splits.push(super::run_scene(self.gpu, &self.opts(spec, &methods, a.frames, a.resolution, split), scene.clone(), None)?);
            }
        }
        Ok(SceneResult { spec: spec.to_string(), stats: scene.stats(), extent: scene.bounds().extent().to_array(), bvh, main, splits })
    }

    /// The first generated scene grown step by step (a file scene has one
    /// size). "As far as the machine allows": a size the device cannot
    /// hold ends the sweep, with the reason, not the report.
    fn sweep(&mut self) -> (Vec<SweepPoint>, Option<String>) {
        let spec = self.first_generated();
        let mut points = Vec::new();
        for &n in &self.plan.sweep {
            self.say(format!("scale sweep: {spec} with {n} objects"));
            let mut o = self.opts(&spec, &self.plan.sweep_methods, self.a.sweep_frames, self.a.resolution, Split::Sah);
            o.objects = Some(n);
            match super::run(self.gpu, &o) {
                Ok(report) => points.push(SweepPoint { objects: n, report }),
                Err(e) => {
                    eprintln!("scale sweep stopped at {n} objects: {e}");
                    return (points, Some(format!("stopped at {n} objects: {e}")));
                }
            }
        }
        (points, None)
    }

    /// The first generated scene at each moving fraction (HROC §6: moving
    /// objects), every method of the motion table side by side per run.
    fn motion(&mut self) -> Result<Vec<BenchReport>> {
        let spec = self.first_generated();
        let mut runs = Vec::new();
        for &f in &self.plan.motion {
            self.say(format!("motion: {spec} with {:.0}% of the objects moving", f * 100.0));
            let mut o = self.opts(&spec, &self.plan.motion_methods, self.a.frames, self.a.resolution, Split::Sah);
            o.moving = f as f32;
            runs.push(super::run(self.gpu, &o)?);
        }
        Ok(runs)
    }

    /// The clusters scene without clusters and with each size (a loaded
    /// file's one mesh, or a generated scene's props, split into clusters).
    fn clusters(&mut self) -> Result<Vec<ClusterRun>> {
        if self.plan.clusters.is_empty() {
            return Ok(Vec::new());
        }
        let spec = self.a.cluster_scene.clone();
        let mut runs = Vec::new();
        for t in std::iter::once(None).chain(self.plan.clusters.iter().map(|&t| Some(t))) {
            self.say(format!("clusters: {spec} {}", t.map_or("without clusters".to_string(), |t| format!("in clusters of {t} triangles"))));
            let mut o = self.opts(&spec, &self.plan.cluster_methods, self.a.frames, self.a.resolution, Split::Sah);
            o.clusters = t;
            runs.push(ClusterRun { triangles: t, report: super::run(self.gpu, &o)? });
        }
        Ok(runs)
    }

    /// The first generated scene of the report (a file has no motion and
    /// one size), or radial-city.
    fn first_generated(&self) -> String {
        self.plan.scenes.iter().find(|s| generators::find(s).is_some()).cloned().unwrap_or_else(|| "radial-city".into())
    }

    /// The first scene at the high resolution, when the device's textures reach it.
    fn hires(&mut self, scene: &Scene) -> Result<(Option<BenchReport>, Option<String>)> {
        let Some((w, h)) = self.plan.hires else { return Ok((None, None)) };
        let max = self.gpu.limits().max_texture_dimension_2d;
        if w > max || h > max {
            return Ok((None, Some(format!("{w}x{h} is over this device's largest texture ({max})"))));
        }
        let spec = &self.plan.scenes[0];
        self.say(format!("{spec}: {w}x{h}, {} frames", self.a.hires_frames));
        let o = self.opts(spec, &self.plan.hires_methods, self.a.hires_frames, (w, h), Split::Sah);
        Ok((Some(super::run_scene(self.gpu, &o, scene.clone(), None)?), None))
    }
}

/// Writes data.json, the plots, report.md and index.html.
pub fn write(out: &Path, data: &ReportData) -> Result<()> {
    let put = |name: &str, text: &str| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| Error::Write { path, source: e })
    };
    put("data.json", &serde_json::to_string_pretty(data).map_err(|e| Error::Options(e.to_string()))?)?;
    let doc = sections::build(data, &out.join("plots"))?;
    put("report.md", &doc.markdown())?;
    put("index.html", &doc.html())
}

/// `YYYY-MM-DD HH:MM UTC`.
fn utc_now() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (y, m, d) = super::civil_from_days((secs / 86_400) as i64);
    format!("{y:04}-{m:02}-{d:02} {:02}:{:02} UTC", secs / 3600 % 24, secs / 60 % 60)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        a: ReportArgs,
    }

    fn args(extra: &[&str]) -> ReportArgs {
        Cli::parse_from(["t", "--out", "x"].iter().chain(extra)).a
    }

    #[test]
    fn plan_defaults_and_errors() {
        let p = Plan::new(&args(&[])).unwrap();
        assert_eq!(p.scenes, ["radial-city", "factory", "satellites"]);
        assert_eq!(p.heat_frame, 30);
        assert_eq!(p.sweep, [100, 1000, 4000, 16000, 64000, 256000, 1_000_000]);
        assert_eq!(p.hires, Some((4096, 2160)));
        assert_eq!(p.splits, [Split::Sah, Split::Mid, Split::Eq]);
        let names = |m: &[Method]| m.iter().map(|m| m.name()).collect::<Vec<_>>();
        assert_eq!(names(&Plan::new(&args(&["--methods", "hroc"])).unwrap().methods), ["noc", "hroc"]);
        assert_eq!(names(&p.methods), ["noc", "vfc", "ref", "roc", "hzb", "ioc", "hroc-na", "hroc-cr", "hroc-of", "hroc-cr+of"]);
        assert_eq!(names(&p.sweep_methods), ["noc", "vfc", "roc", "hzb", "hroc", "auto"]);
        assert_eq!(names(&p.hires_methods), ["noc", "ref", "roc", "hzb", "hroc"]);
        assert_eq!(p.motion, [0.0, 0.1, 1.0]);
        assert_eq!(names(&p.motion_methods), ["noc", "vfc", "roc", "hzb", "hroc"]);
        assert_eq!((p.clusters.as_slice(), names(&p.cluster_methods).as_slice()), (&[64, 256][..], &["noc", "ref", "hzb", "hroc"][..]));
        let none = Plan::new(&args(&["--sweep", "none", "--hires", "none", "--motion", "none", "--clusters", "none"])).unwrap();
        assert!(none.sweep.is_empty() && none.hires.is_none() && none.motion.is_empty() && none.clusters.is_empty());
        for bad in [
            &["--scenes", ","][..],
            &["--frames", "0"],
            &["--heat-frame", "60"],
            &["--splits", "sah,foo"],
            &["--sweep", "10,x"],
            &["--hires", "4096"],
            &["--methods", "nope"],
            &["--motion", "2"],
            &["--motion-methods", "oq"],
            &["--clusters", "6"],
            &["--clusters", "x"],
        ] {
            // Refused by the argument parser (typed values) or by the plan.
            let parsed = Cli::try_parse_from(["t", "--out", "x"].iter().chain(bad));
            assert!(parsed.map_or(true, |c| Plan::new(&c.a).is_err()), "{bad:?}");
        }
    }

    #[test]
    fn utc_date_shape() {
        let d = utc_now();
        assert_eq!(d.len(), 20, "{d}");
        assert!(d.starts_with("20") && d.ends_with(" UTC"), "{d}");
    }
}
