//! Culling methods, all behind one [`Culler`] trait.
//!
//! A culler does not own "the" draw: per frame it hands the host renderer
//! draw lists (indirect commands + GPU count, object order kept), and runs
//! its own passes between them (DESIGN.md "Library shape"). The [`Frame`]
//! records every list drawn, so the benchmark can check what was drawn
//! against `noc` without trusting the method.

pub mod hroc;
pub mod hzb;
pub mod ioc;
pub mod noc;
pub mod queries;
pub mod reference;
pub mod roc;
pub mod vfc;
pub mod woc;

use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::gpu::{Gpu, GpuTimer};
use crate::render::{layout::FrameUniform, DrawList, Renderer};
use crate::scene::{Camera, Scene};

/// Everything a culler sees while recording one frame.
pub struct Frame<'a> {
    pub gpu: &'a Gpu,
    pub renderer: &'a Renderer,
    pub camera: Camera,
    pub uniform: FrameUniform,
    /// Camera-path time of this frame in seconds (frames are uniform over
    /// the path; 0 outside a session), for methods whose statistics expire
    /// with time (`soq`).
    pub path_time: f32,
    encoder: Option<wgpu::CommandEncoder>,
    timer: &'a mut GpuTimer,
    drawn: Vec<DrawList>,
    submits: u32,
}

impl<'a> Frame<'a> {
    /// Starts a frame: uploads the camera and clears the targets.
    pub fn begin(gpu: &'a Gpu, renderer: &'a Renderer, timer: &'a mut GpuTimer, camera: Camera, node_count: u32) -> Self {
        let uniform = renderer.frame_uniform(&camera, node_count);
        renderer.write_frame(gpu, &uniform);
        timer.begin_frame();
        let mut encoder = gpu.encoder("frame");
        timer.mark(&mut encoder, "clear");
        renderer.clear(&mut encoder);
        Frame { gpu, renderer, camera, uniform, path_time: 0.0, encoder: Some(encoder), timer, drawn: Vec::new(), submits: 0 }
    }

    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.encoder.get_or_insert_with(|| self.gpu.encoder("frame"))
    }

    /// Begins GPU stage `name` here (ends the previous one).
    pub fn stage(&mut self, name: &'static str) {
        let enc = self.encoder.get_or_insert_with(|| self.gpu.encoder("frame"));
        self.timer.mark(enc, name);
    }

    /// Draws `list` into the frame's targets and records it as drawn.
    pub fn draw(&mut self, list: &DrawList, marks: Option<&wgpu::BindGroup>) {
        let enc = self.encoder.get_or_insert_with(|| self.gpu.encoder("frame"));
        self.renderer.draw(enc, list, marks);
        self.drawn.push(list.clone());
    }

    /// Submits what is recorded so far (for methods that read back mid-frame).
    pub fn flush(&mut self) {
        if let Some(enc) = self.encoder.take() {
            self.gpu.queue.submit([enc.finish()]);
            self.submits += 1;
        }
    }

    /// Reads `count` u32s of `buf` mid-frame: submits and waits (a stall,
    /// which is what CR-style methods pay for).
    pub fn read_u32(&mut self, buf: &wgpu::Buffer, count: u64) -> Result<Vec<u32>> {
        self.flush();
        self.gpu.read(buf, 0, count)
    }

    /// Ends the frame: resolves timestamps, submits, waits for the GPU.
    /// Returns the lists drawn.
    pub fn finish(mut self) -> Result<Vec<DrawList>> {
        let enc = self.encoder.get_or_insert_with(|| self.gpu.encoder("frame"));
        self.timer.mark(enc, "end");
        self.timer.resolve(enc);
        self.flush();
        self.gpu.wait()?;
        Ok(std::mem::take(&mut self.drawn))
    }
}

/// A culling method.
pub trait Culler {
    fn name(&self) -> &str;

    /// True for `ref`: it is handed `noc`'s visible set before each frame,
    /// outside the timed region.
    fn wants_oracle(&self) -> bool {
        false
    }

    /// The objects that own a pixel in `noc`'s ID target this frame, sorted.
    fn set_oracle(&mut self, _gpu: &Gpu, _visible: &[u32]) -> Result<()> {
        Ok(())
    }

    /// Records (and may submit) the frame's culling passes and draws.
    fn frame(&mut self, f: &mut Frame) -> Result<()>;

    /// Per-frame method statistics of the frame just run (set sizes,
    /// nodes per ray...). Called after the frame, outside the timed region.
    fn stats(&mut self, _gpu: &Gpu) -> Result<Vec<(&'static str, f64)>> {
        Ok(Vec::new())
    }

    /// BVH nodes whose boxes the method rasterized in its last frame (for
    /// `hroc render --view groups`); `None` for methods that test no boxes.
    fn tested_nodes(&self, _gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(None)
    }
}

/// What a culler may build from.
pub struct SceneContext<'a> {
    pub gpu: &'a Gpu,
    pub scene: &'a Scene,
    pub bvh: &'a Bvh,
    pub renderer: &'a Renderer,
    pub options: &'a MethodOptions,
}

/// Method parameters the command line can set (`hroc bench`/`render`).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOptions {
    /// `soq`: paper 004's BASE_TIME, in seconds of camera path.
    pub soq_base_time: f32,
    /// `chc++`: previously invisible nodes per query batch, b. The HROC
    /// paper ran b = 4000 on scenes of 7k–120k objects ("optimized for our
    /// scenes"); the EOVC thesis 1000. Scenes here are scaled down, so 1000.
    pub chc_batch: usize,
    /// `chc++`: frames a visible leaf is assumed visible between queries, n_av.
    pub chc_nav: u32,
    /// `chc++`: tighter bounds from descendants down to d_max levels.
    pub chc_dmax: u32,
    /// `chc++`: tighter bounds only while their summed area is within s_max × the node's.
    pub chc_smax: f32,
    /// `ioc`: BVH depths [start, bottom] (root = 0); `None` picks
    /// [depth/2 - 1, depth/2 + 1] of the scene's BVH (`ioc::cpu::default_range`).
    pub ioc_range: Option<(u32, u32)>,
}

impl Default for MethodOptions {
    fn default() -> Self {
        MethodOptions { soq_base_time: queries::soq::DEFAULT_BASE_TIME, chc_batch: 1000, chc_nav: 10, chc_dmax: 4, chc_smax: 1.4, ioc_range: None }
    }
}

/// Implemented methods, in table order, with one line each.
pub const METHODS: &[(&str, &str)] = &[
    ("noc", "no culling: draw every object"),
    ("vfc", "GPU view-frustum culling"),
    ("ref", "ideal: draw exactly the objects visible in noc's ID target"),
    ("oq", "hierarchical stop-and-wait occlusion queries, front to back (004's simple OC)"),
    ("soq", "occlusion queries skipped for recently visible nodes (004's statistical OC)"),
    ("chc++", "CHC++: batched multiqueries, randomized re-queries, tighter bounds"),
    ("roc", "raster occlusion culling: draw V, rasterize the boxes of the rest with early-Z, draw what passed"),
    ("roc-all", "raster occlusion culling testing every object's box (the HROC paper's ROC)"),
    ("ioc", "ROC over BVH levels [start, bottom] with a queue read-back per level (HPG 2020 poster)"),
    ("hzb", "two-phase Hi-Z culling (Nanite, niagara, Bevy)"),
    ("woc", "warping-based: last frame's depth reprojected, Hi-Z test before drawing (not conservative)"),
    ("hroc-na", "HROC without accelerations"),
    ("hroc-cr", "HROC with counter read-back"),
    ("hroc-of", "HROC with occluder filtering"),
    ("hroc-cr+of", "HROC with counter read-back and occluder filtering"),
    ("hroc", "HROC, the default variant (cr+of)"),
];

pub fn method_names() -> Vec<&'static str> {
    METHODS.iter().map(|m| m.0).collect()
}

/// Parses `a,b,c` or `all` into method names.
pub fn parse_methods(spec: &str) -> Result<Vec<String>> {
    if spec.trim() == "all" {
        return Ok(method_names().into_iter().map(String::from).collect());
    }
    let mut out = Vec::new();
    for m in spec.split(',').map(str::trim).filter(|m| !m.is_empty()) {
        if !METHODS.iter().any(|(n, _)| *n == m) {
            return Err(Error::Arg(format!("unknown method '{m}': expected one of {} or all", method_names().join(", "))));
        }
        if !out.iter().any(|o| o == m) {
            out.push(m.to_string());
        }
    }
    if out.is_empty() {
        return Err(Error::Arg("no methods given".into()));
    }
    Ok(out)
}

pub fn create(name: &str, cx: &SceneContext) -> Result<Box<dyn Culler>> {
    Ok(match name {
        "noc" => Box::new(noc::NoCulling),
        "vfc" => Box::new(vfc::FrustumCuller::new(cx)),
        "ref" => Box::new(reference::Reference::new(cx)?),
        "oq" => Box::new(queries::oq::Oq::new(cx)?),
        "soq" => Box::new(queries::soq::Soq::new(cx)?),
        "chc++" => Box::new(queries::chc::Chc::new(cx)?),
        "roc" => Box::new(roc::Roc::new(cx, false)),
        "roc-all" => Box::new(roc::Roc::new(cx, true)),
        "ioc" => Box::new(ioc::Ioc::new(cx, cx.options.ioc_range)?),
        "hzb" => Box::new(hzb::Hzb::new(cx)),
        "woc" => Box::new(woc::Woc::new(cx)),
        _ => match hroc::Variant::parse(name) {
            Some(v) => Box::new(hroc::Hroc::new(name, v, cx)?),
            None => return Err(Error::Arg(format!("unknown method '{name}'"))),
        },
    })
}
