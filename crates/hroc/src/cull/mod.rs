//! The culling methods, each behind one [`CullMethod`] trait, and the
//! recording context [`Frame`] they run in.
//!
//! A method never owns the draw: per frame it hands the host draw lists
//! (indirect commands + a GPU count, object order kept) through
//! [`Frame::draw`], tagged with their [`Phase`], and records its own passes
//! between them. [`crate::View::cull`] builds the frame from what the host
//! hands in, so the benchmark and any engine drive a method the same way.

pub mod compact;
pub mod hroc;
pub mod hzb;
pub mod ioc;
pub mod noc;
pub mod queries;
pub mod reference;
pub mod roc;
pub mod vfc;
pub mod woc;

use std::any::Any;
use std::fmt;
use std::str::FromStr;

use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::frustum::ViewGeometry;
use crate::gpu::{Gpu, GpuTimer, InvocationCounter, PassCount};
use crate::host::{Draw, DrawHost, FlagSplit, Phase, SharedObjects, Targets};
use crate::layout::FrameUniform;

/// A packed list of draw commands and the GPU count the draw reads.
/// `max_count` bounds the count (N, or a read-back count with CR).
#[derive(Clone, Debug)]
pub struct DrawList {
    /// [`crate::layout::DrawCommand`]s, object order kept.
    pub commands: wgpu::Buffer,
    /// One u32: how many commands to draw.
    pub count: wgpu::Buffer,
    /// Upper bound on the count.
    pub max_count: u32,
}

/// Recorded in place of a method's frame (`View::cull_with`, for tests).
pub type FrameBody<'b> = &'b mut dyn FnMut(&mut Frame) -> Result<()>;

/// Everything a method sees while recording one frame of one view.
pub struct Frame<'a> {
    /// The device the culler was created on.
    pub gpu: &'a Gpu,
    /// The view as the host renders it this frame.
    pub geometry: ViewGeometry,
    /// The `Frame` uniform written for this view and frame.
    pub uniform: FrameUniform,
    /// Seconds on the host's clock, for methods whose statistics expire with
    /// time (`soq`).
    pub time: f32,
    pub(crate) objects: &'a SharedObjects,
    pub(crate) targets: &'a Targets,
    pub(crate) encoder: &'a mut wgpu::CommandEncoder,
    pub(crate) host: &'a mut dyn DrawHost,
    pub(crate) timer: Option<&'a mut GpuTimer>,
    pub(crate) counter: Option<&'a mut InvocationCounter>,
    /// The stage begun last ([`Frame::stage`]).
    pub(crate) current: Stage,
    pub(crate) split: Option<&'a mut FlagSplit>,
    pub(crate) sink: &'a wgpu::BindGroup,
    pub(crate) work: &'a mut WorkCounts,
    pub(crate) tally: &'a mut crate::tally::DrawTally,
    /// A debug group named after the current stage is open on the encoder,
    /// so a GPU profiler groups the passes as the paper's steps.
    pub(crate) group_open: bool,
}

/// Work of one frame that does not depend on how busy the machine is:
/// mid-frame submits, waits for the GPU, and bytes read back to the CPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkCounts {
    /// Mid-frame submits ([`Frame::flush`]).
    pub submits: u64,
    /// Mid-frame waits for the GPU (read-backs that block).
    pub waits: u64,
    /// Bytes read back to the CPU, waited for or not.
    pub bytes_read: u64,
}

impl<'a> Frame<'a> {
    /// The encoder to record into (the host's; replaced after a mid-frame submit).
    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.encoder
    }

    /// Begins GPU stage `stage` here (ends the previous one).
    pub fn stage(&mut self, stage: Stage) {
        self.current = stage;
        self.end_group();
        self.encoder.push_debug_group(stage.name());
        self.group_open = true;
        if let Some(t) = self.timer.as_deref_mut() {
            t.mark(self.encoder, stage);
        }
    }

    /// The encoder, and a pipeline-statistics slot for the pass about to be
    /// recorded into it ([`Frame::pass_count`]).
    pub fn counted(&mut self) -> (&mut wgpu::CommandEncoder, PassCount) {
        let count = self.pass_count();
        (self.encoder, count)
    }

    /// A pipeline-statistics slot for the next pass, counted under the
    /// current stage (nothing when the view does not count): the pass
    /// records its commands inside [`PassCount::around`].
    pub fn pass_count(&self) -> PassCount {
        match self.counter.as_deref() {
            Some(c) => c.pass(self.current),
            None => PassCount::NONE,
        }
    }

    /// Hands `list` to the host to draw in `phase`; with `marks`, the host's
    /// fragments that pass the depth test mark their object there.
    pub fn draw(&mut self, phase: Phase, list: &DrawList, marks: Option<&wgpu::BindGroup>) {
        let split;
        let split_count = if self.split.is_some() { self.pass_count() } else { PassCount::NONE };
        let list = match self.split.as_deref_mut() {
            Some(s) => {
                split = s.split(self.gpu, self.encoder, &self.objects.bounds, list, &split_count);
                &split
            }
            None => list,
        };
        let statistics = self.pass_count();
        let draw = Draw { phase, commands: &list.commands, count: &list.count, max_count: list.max_count, marks: marks.unwrap_or(self.sink), mark: marks.is_some(), statistics };
        self.host.draw(self.encoder, &draw);
        self.tally.count(self.gpu, self.encoder, list);
    }

    /// Submits what is recorded so far and continues in a fresh encoder (for
    /// methods that read back mid-frame).
    pub fn flush(&mut self) {
        self.tally.write_limits(self.gpu);
        let open = self.group_open;
        self.end_group();
        let enc = std::mem::replace(self.encoder, self.gpu.encoder("hroc frame"));
        self.gpu.queue.submit([enc.finish()]);
        self.work.submits += 1;
        if open {
            self.encoder.push_debug_group(self.current.name());
            self.group_open = true;
        }
    }

    /// Closes the current stage's debug group, if one is open.
    pub(crate) fn end_group(&mut self) {
        if std::mem::take(&mut self.group_open) {
            self.encoder.pop_debug_group();
        }
    }

    /// Reads `count` u32s of `buf` mid-frame: submits and waits (a stall,
    /// which is what CR-style methods pay for).
    pub fn read_u32(&mut self, buf: &wgpu::Buffer, count: u64) -> Result<Vec<u32>> {
        self.flush();
        self.work.waits += 1;
        self.work.bytes_read += count * 4;
        self.gpu.read(buf, 0, count)
    }

    /// Submits, then maps and reads the first `bytes` of the `MAP_READ`
    /// buffer `staging` (a stall, as [`Frame::read_u32`]).
    pub fn map_read(&mut self, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>> {
        self.flush();
        self.work.waits += 1;
        self.work.bytes_read += bytes;
        self.gpu.map_read(staging, bytes)
    }

    /// Counts `bytes` read back without waiting (a staging buffer that
    /// arrived mapped).
    pub fn count_async_read(&mut self, bytes: u64) {
        self.work.bytes_read += bytes;
    }

    /// The host's depth attachment, for the method's own box passes.
    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.targets.depth_attachment
    }

    /// Width and height of the depth attachment.
    pub fn size(&self) -> (u32, u32) {
        self.targets.size
    }

    /// Registered objects.
    pub fn object_count(&self) -> u32 {
        self.objects.count
    }

    /// Every object in object order (`noc`'s list).
    pub fn all(&self) -> DrawList {
        self.objects.all()
    }
}

/// What a method may build from: the culler's shared buffers and the view's
/// own targets.
pub struct MethodContext<'a> {
    /// The host's device.
    pub gpu: &'a Gpu,
    /// The object BVH shared by every view.
    pub bvh: &'a Bvh,
    /// The BVH nodes on the GPU (`BvhNode`), shared by every view.
    pub bvh_nodes: &'a wgpu::Buffer,
    /// Leaf node of every object on the GPU, shared by every view.
    pub leaf_of_object: &'a wgpu::Buffer,
    /// Object boxes (`ObjectBounds`), shared by every view.
    pub bounds: &'a wgpu::Buffer,
    /// Object boxes in their own frames (`OrientedBounds`), shared by every view.
    pub oriented: &'a wgpu::Buffer,
    /// One command per object in object order, shared by every view.
    pub commands: &'a wgpu::Buffer,
    /// Object slots: every per-object buffer covers them.
    pub object_count: u32,
    /// Nodes the BVH can grow to over the slots (rebuilds keep the buffers).
    pub node_capacity: u32,
    /// This view's `Frame` uniform.
    pub frame: &'a wgpu::Buffer,
    /// This view's depth attachment (for box passes) and sampling views.
    pub targets: &'a Targets,
    /// Layout of a marks bind group (one `array<u32>` at binding 0).
    pub marks_layout: &'a wgpu::BindGroupLayout,
    /// Method parameters.
    pub options: &'a MethodOptions,
}

impl MethodContext<'_> {
    /// A marks bind group over `marks` (u32 per object), for [`Frame::draw`].
    pub fn marks_bind(&self, marks: &wgpu::Buffer) -> wgpu::BindGroup {
        self.gpu.bind_buffers(self.marks_layout, &[marks])
    }
}

/// A culling method: what a [`crate::View`] runs every frame.
pub trait CullMethod: Any {
    /// Which method this is.
    fn method(&self) -> Method;

    /// Records (and may submit) the frame's culling passes and hands the
    /// host its draw lists.
    fn frame(&mut self, f: &mut Frame) -> Result<()>;

    /// Forgets what earlier frames taught (a camera cut): the next frame is
    /// culled as a first frame. Every method with temporal state overrides it.
    fn reset(&mut self, _enc: &mut wgpu::CommandEncoder) {}

    /// `ref` only: the objects that own a pixel in `noc`'s ID target this
    /// frame, sorted.
    fn set_oracle(&mut self, _gpu: &Gpu, _visible: &[u32]) -> Result<()> {
        Ok(())
    }

    /// Per-frame method statistics of the frame just run (set sizes, nodes
    /// per ray...). Reads back; call after the frame.
    fn stats(&mut self, _gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        Ok(Vec::new())
    }

    /// BVH nodes whose boxes the method rasterized in its last frame (for
    /// `hroc render --view groups`); `None` for methods that test no boxes.
    fn tested_nodes(&self, _gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(None)
    }
}

/// Method parameters the command line can set (`hroc bench`/`render`).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOptions {
    /// `soq`: Kovalčík & Sochor 2005's BASE_TIME, in seconds.
    pub soq_base_time: f32,
    /// `chc++`: previously invisible nodes per query batch, b. The HROC
    /// paper ran b = 4000 on scenes of 7k–120k objects ("optimized for our
    /// scenes"); Lee's thesis 1000. Scenes here are scaled down, so 1000.
    pub chc_batch: usize,
    /// `chc++`: frames a visible leaf is assumed visible between queries, n_av.
    pub chc_nav: u32,
    /// `chc++`: tighter bounds from descendants down to d_max levels.
    pub chc_dmax: u32,
    /// `chc++`: tighter bounds only while their summed area is within s_max × the node's.
    pub chc_smax: f32,
    /// `ioc`: BVH depths [start, bottom] (root = 0); `None` picks
    /// [depth/2 - 1, depth/2 + 1] of the BVH (`ioc::cpu::default_range`).
    pub ioc_range: Option<(u32, u32)>,
    /// `hroc`: when a coarse grid of rays seeds the occluders V.
    pub hroc_seed: Seed,
    /// `hroc`: pixels per side of the blocks the batch occlusion test
    /// works on: one box fragment and one ray per block, against the
    /// block's farthest depth, with boxes padded for it (conservative at
    /// any scale). 2 casts a quarter of the rays at 640 × 360 for a little
    /// culling; the largest scale up to this one that divides the target's
    /// width and height is used, 1 being the paper's per-pixel test.
    pub hroc_test_scale: u32,
    /// `hroc` with OF: occluder filtering (§4.2) reads one pixel of the
    /// ID target in every `S × S` (1: every pixel, the paper's). Objects
    /// that cover no sampled pixel leave V: only speed and culling change,
    /// as V may be any set of objects. A sparser read costs 1/S² of the
    /// filter's threads and keeps small objects out of next frame's
    /// untested V, but measured fewer occluders cull less (BENCHMARKS.md),
    /// so the default reads every pixel.
    pub hroc_filter_stride: u32,
    /// `hroc`: rounds of occludee rendering, 1 to [`hroc::MAX_ROUNDS`]. 1
    /// is the paper's: every object the batch test marks (U) is drawn. With
    /// more, each round but the last draws the marked objects whose box is
    /// nearest at some block, and tests the rest again against the depth
    /// those draws left; objects hidden by what came into view this frame
    /// are then culled too. Rounds only change which of U are drawn, never
    /// what passes: every object they drop is behind drawn depth.
    pub hroc_rounds: u32,
    /// `hroc`: draw the occlusion map in one front-to-back round too: the
    /// objects of V whose box is nearest at some block first, then those
    /// whose box is still in front of the depth they left. V holds last
    /// frame's visible set, and on a moving camera many of them are hidden
    /// this frame behind others of V; left out, they are not occluders,
    /// and the batch test takes them with the other occludees. The hidden
    /// ones it culls leave the occluder set O, so G and next frame's V
    /// shrink too; every object that owns a pixel is still drawn.
    pub hroc_occluder_rounds: bool,
    /// A frame whose view direction turned more than this many degrees
    /// since the last frame is culled as after a camera cut (the host need
    /// not say so): 45° is an eighth of a turn, past which most of last
    /// frame's visible set is off screen. `f32::INFINITY` turns it off.
    pub cut_turn_deg: f32,
    /// ... or whose eye moved more than this fraction of the scene's
    /// diagonal (the BVH root's box): a tenth of a city is a new street.
    pub cut_move: f32,
}

/// When HROC seeds its occluders V with the objects a coarse grid of rays
/// meets first (`seed` in `hroc_groups.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seed {
    /// On the first frame and after every camera cut, signalled or detected
    /// (the default): last frame's V is stale then.
    Cuts,
    /// Every frame, added to last frame's V.
    Always,
    /// Never: after a cut V is empty and the root is the one group (the
    /// paper's first frame).
    Never,
}

impl FromStr for Seed {
    type Err = Error;
    fn from_str(s: &str) -> Result<Seed> {
        match s {
            "cuts" => Ok(Seed::Cuts),
            "always" => Ok(Seed::Always),
            "never" => Ok(Seed::Never),
            _ => Err(Error::Arg(format!("unknown seed '{s}': expected cuts, always or never"))),
        }
    }
}

impl Default for MethodOptions {
    fn default() -> Self {
        MethodOptions {
            soq_base_time: queries::soq::DEFAULT_BASE_TIME,
            chc_batch: 1000,
            chc_nav: 10,
            chc_dmax: 4,
            chc_smax: 1.4,
            ioc_range: None,
            hroc_seed: Seed::Cuts,
            hroc_test_scale: 2,
            hroc_filter_stride: 1,
            hroc_rounds: 1,
            hroc_occluder_rounds: false,
            cut_turn_deg: 45.0,
            cut_move: 0.1,
        }
    }
}

/// How HROC bounds its indirect draws' `max_count` (HROC §4.1, §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Counters {
    /// The list's capacity, N (no acceleration, `na`).
    Capacity,
    /// Counter read-back (§4.1, `cr`): each count is read back mid-frame,
    /// a submit and a wait per list.
    ReadBack,
    /// Stall-free (`sf`, what §6 asks for): last frames' counts, read
    /// without waiting, plus a margin; a second indirect-count draw takes
    /// whatever overflows the estimate, its count (count − estimate, at
    /// least 0) computed on the GPU, so nothing is dropped.
    StallFree,
}

/// HROC's accelerations (§4): how draw counts are bounded, and occluder filtering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    /// How `max_count` of each indirect draw is bounded.
    pub counters: Counters,
    /// Occluder filtering: next frame's occluders are the objects owning a
    /// pixel of the object-ID target.
    pub of: bool,
}

impl Variant {
    /// `hroc-na`: no accelerations.
    pub const NA: Variant = Variant { counters: Counters::Capacity, of: false };
    /// `hroc-cr`: counter read-back.
    pub const CR: Variant = Variant { counters: Counters::ReadBack, of: false };
    /// `hroc-of`: occluder filtering.
    pub const OF: Variant = Variant { counters: Counters::Capacity, of: true };
    /// `hroc-cr+of`: both of the paper's accelerations (§4).
    pub const CR_OF: Variant = Variant { counters: Counters::ReadBack, of: true };
    /// `hroc-sf`: stall-free counters.
    pub const SF: Variant = Variant { counters: Counters::StallFree, of: false };
    /// `hroc-sf+of` (= `hroc`): stall-free counters (§6) and occluder filtering.
    pub const SF_OF: Variant = Variant { counters: Counters::StallFree, of: true };
}

/// Every implemented method: one registry, in table order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// No culling: draw every object. Also the ground truth.
    Noc,
    /// GPU view-frustum culling.
    Vfc,
    /// Ideal: exactly the objects visible in `noc`'s ID target. Benchmark
    /// only: it needs that target before the frame.
    Ref,
    /// Hierarchical stop-and-wait occlusion queries.
    Oq,
    /// Statistically skipped occlusion queries.
    Soq,
    /// CHC++.
    Chc,
    /// Raster occlusion culling.
    Roc,
    /// Raster occlusion culling testing every object's box.
    RocAll,
    /// ROC over BVH levels.
    Ioc,
    /// Two-phase Hi-Z culling.
    Hzb,
    /// Warping-based occlusion culling (not conservative).
    Woc,
    /// Hierarchical Raster Occlusion Culling with the given accelerations;
    /// `hroc` is `sf+of`.
    Hroc(Variant),
}

impl Method {
    /// HROC's default variant (SF + OF): occluder filtering, and counts
    /// bounded without the read-back's stall, which the paper's CR pays
    /// three times a frame (HROC §6).
    pub const HROC: Method = Method::Hroc(Variant::SF_OF);

    /// Every method once, in table order (`hroc` last, after its variants).
    pub const ALL: [Method; 17] = [
        Method::Noc,
        Method::Vfc,
        Method::Ref,
        Method::Oq,
        Method::Soq,
        Method::Chc,
        Method::Roc,
        Method::RocAll,
        Method::Ioc,
        Method::Hzb,
        Method::Woc,
        Method::Hroc(Variant::NA),
        Method::Hroc(Variant::CR),
        Method::Hroc(Variant::OF),
        Method::Hroc(Variant::CR_OF),
        Method::Hroc(Variant::SF),
        Method::HROC,
    ];

    /// The methods of `hroc bench` with no `--methods`: no culling, frustum
    /// culling, the ideal and HROC.
    pub const DEFAULT_TABLE: [Method; 4] = [Method::Noc, Method::Vfc, Method::Ref, Method::HROC];

    /// The name on the command line and in tables. `hroc` and `hroc-sf+of`
    /// are the same method; this returns `hroc` for it, and
    /// [`Method::names`] lists both names.
    pub fn name(self) -> &'static str {
        match self {
            Method::Noc => "noc",
            Method::Vfc => "vfc",
            Method::Ref => "ref",
            Method::Oq => "oq",
            Method::Soq => "soq",
            Method::Chc => "chc++",
            Method::Roc => "roc",
            Method::RocAll => "roc-all",
            Method::Ioc => "ioc",
            Method::Hzb => "hzb",
            Method::Woc => "woc",
            Method::Hroc(Variant { counters: Counters::Capacity, of: false }) => "hroc-na",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: false }) => "hroc-cr",
            Method::Hroc(Variant { counters: Counters::Capacity, of: true }) => "hroc-of",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: true }) => "hroc-cr+of",
            Method::Hroc(Variant { counters: Counters::StallFree, of: false }) => "hroc-sf",
            Method::Hroc(Variant { counters: Counters::StallFree, of: true }) => "hroc",
        }
    }

    /// Every (name, method, one-line description), in table order.
    /// `hroc-sf+of` also parses, as `hroc`.
    pub fn names() -> Vec<(&'static str, Method, &'static str)> {
        Method::ALL.iter().map(|&m| (m.name(), m, m.description())).collect()
    }

    /// One line on what the method does.
    pub fn description(self) -> &'static str {
        match self {
            Method::Noc => "no culling: draw every object",
            Method::Vfc => "GPU view-frustum culling",
            Method::Ref => "ideal: draw exactly the objects visible in noc's ID target",
            Method::Oq => "hierarchical stop-and-wait occlusion queries, front to back (004's simple OC)",
            Method::Soq => "occlusion queries skipped for recently visible nodes (004's statistical OC)",
            Method::Chc => "CHC++: batched multiqueries, randomized re-queries, tighter bounds",
            Method::Roc => "raster occlusion culling: draw V, rasterize the boxes of the rest with early-Z, draw what passed",
            Method::RocAll => "raster occlusion culling testing every object's box (the HROC paper's ROC)",
            Method::Ioc => "ROC over BVH levels [start, bottom] with a queue read-back per level (HPG 2020 poster)",
            Method::Hzb => "two-phase Hi-Z culling (Nanite, niagara, Bevy)",
            Method::Woc => "warping-based: last frame's depth reprojected, Hi-Z test before drawing (not conservative)",
            Method::Hroc(Variant { counters: Counters::Capacity, of: false }) => "HROC without accelerations",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: false }) => "HROC with counter read-back",
            Method::Hroc(Variant { counters: Counters::Capacity, of: true }) => "HROC with occluder filtering",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: true }) => "HROC with counter read-back and occluder filtering",
            Method::Hroc(Variant { counters: Counters::StallFree, of: false }) => "HROC with stall-free counters (earlier frames' counts, GPU overflow draw)",
            Method::Hroc(Variant { counters: Counters::StallFree, of: true }) => "HROC, the default variant: stall-free counters and occluder filtering (also hroc-sf+of)",
        }
    }

    /// False for the methods that may miss visible objects (`woc`).
    pub fn is_conservative(self) -> bool {
        self != Method::Woc
    }

    /// True when the method reads the host's object-ID target (HROC with OF).
    pub fn needs_ids(self) -> bool {
        matches!(self, Method::Hroc(Variant { of: true, .. }))
    }

    /// True for `ref`, which only the benchmark can feed (`View::set_oracle`).
    pub fn is_benchmark_only(self) -> bool {
        self == Method::Ref
    }

    /// True when the method follows objects that move ([`crate::Culler::set_bounds`]):
    /// every method that reads the culler's boxes and BVH on the GPU. The
    /// query methods keep a CPU copy of the BVH (and CHC++ its tighter
    /// bounds) from their creation, so they take static scenes only.
    pub fn takes_motion(self) -> bool {
        !matches!(self, Method::Oq | Method::Soq | Method::Chc)
    }

    /// True when the method culls objects outside the BVH too:
    /// [`crate::ObjectFlags::DYNAMIC`] ones and those added since the last
    /// build. HROC tests them on their own (its §6 hybrid); the per-object
    /// methods never read the tree. IOC culls through the tree alone.
    pub fn takes_dynamic(self) -> bool {
        self.takes_motion() && self != Method::Ioc
    }

    /// True when the method's per-view state holds the BVH's shape (IOC's
    /// level queues, the query methods' copies): its views start over when
    /// the culler rebuilds the tree.
    pub fn keeps_tree(self) -> bool {
        matches!(self, Method::Ioc | Method::Oq | Method::Soq | Method::Chc)
    }

    /// True when the method takes reversed depth (`woc`'s warp does not).
    pub fn supports_reversed_depth(self) -> bool {
        self != Method::Woc
    }

    /// Parses `a,b,c` or `all` ([`Method::ALL`]) into methods, in the
    /// order given, without repeats.
    pub fn parse_list(spec: &str) -> Result<Vec<Method>> {
        if spec.trim() == "all" {
            return Ok(Method::ALL.to_vec());
        }
        let mut out = Vec::new();
        for m in spec.split(',').map(str::trim).filter(|m| !m.is_empty()) {
            let m: Method = m.parse()?;
            if !out.contains(&m) {
                out.push(m);
            }
        }
        if out.is_empty() {
            return Err(Error::Arg("no methods given".into()));
        }
        Ok(out)
    }

    pub(crate) fn create(self, cx: &MethodContext) -> Result<Box<dyn CullMethod>> {
        Ok(match self {
            Method::Noc => Box::new(noc::NoCulling),
            Method::Vfc => Box::new(vfc::FrustumCuller::new(cx)),
            Method::Ref => Box::new(reference::Reference::new(cx)?),
            Method::Oq => Box::new(queries::oq::Oq::new(cx)?),
            Method::Soq => Box::new(queries::soq::Soq::new(cx)?),
            Method::Chc => Box::new(queries::chc::Chc::new(cx)?),
            Method::Roc => Box::new(roc::Roc::new(cx, false)),
            Method::RocAll => Box::new(roc::Roc::new(cx, true)),
            Method::Ioc => Box::new(ioc::Ioc::new(cx, cx.options.ioc_range)?),
            Method::Hzb => Box::new(hzb::Hzb::new(cx)),
            Method::Woc => Box::new(woc::Woc::new(cx)),
            Method::Hroc(v) => Box::new(hroc::Hroc::new(v, cx)?),
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = Error;
    /// A name of [`Method::names`], or `hroc-sf+of` (the default HROC
    /// variant's full name) for `hroc`.
    fn from_str(s: &str) -> Result<Method> {
        if s == "hroc-sf+of" {
            return Ok(Method::HROC);
        }
        Method::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| {
            let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
            Error::Arg(format!("unknown method '{s}': expected one of {}, hroc-sf+of or all", names.join(", ")))
        })
    }
}

macro_rules! named_enum {
    ($(#[$doc:meta])* $name:ident { $($(#[$vdoc:meta])* $v:ident => $s:literal,)* }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum $name { $($(#[$vdoc])* $v,)* }
        impl $name {
            /// Every value, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$v,)*];
            /// The name in tables, JSON and reports.
            pub fn name(self) -> &'static str {
                match self { $($name::$v => $s,)* }
            }
        }
        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_enum!(
    /// A GPU stage of a frame, timed by timestamps when the device has them.
    Stage {
        /// Draws of a method without stages of its own.
        Draw => "draw",
        /// `vfc`'s frustum test.
        FrustumCull => "frustum cull",
        /// `vfc`'s list compaction.
        Compact => "compact",
        /// HROC's ray-grid seed of V after a camera cut.
        Seed => "occluder seed",
        /// Drawing last frame's visible set (HROC §3.1).
        OcclusionMap => "occlusion map",
        /// HROC's front-to-back round over V: nearest boxes, the re-test
        /// and their lists ([`MethodOptions::hroc_occluder_rounds`]).
        OccluderRounds => "occluder rounds",
        /// HROC's bottom-up group extraction (§3.2).
        GroupExtraction => "group extraction",
        /// Box rasterization, ray casting or Hi-Z tests (HROC §3.3).
        OcclusionTest => "occlusion test",
        /// Drawing the objects that passed (HROC §3.4).
        OccludeeRendering => "occludee rendering",
        /// HROC's front-to-back occludee rounds: nearest boxes, re-tests
        /// and their lists ([`MethodOptions::hroc_rounds`]).
        OccludeeRounds => "occludee rounds",
        /// HROC's occluder filtering (§4.2).
        Filtering => "filtering",
        /// Hi-Z pyramid build.
        HiZBuild => "hi-z build",
        /// Counter read-back (HROC §4.1), a mid-frame submit and wait.
        ReadBack => "read-back",
        /// Query methods' interleaved queries and draws.
        QueriesAndDraws => "queries and draws",
        /// `woc`: keeping this frame's depth.
        SaveDepth => "save depth",
        /// `woc`: warping last frame's depth.
        Warp => "warp",
        /// Objects flagged never-culled or not-occluder, drawn by the culler.
        FlaggedObjects => "flagged objects",
        /// The frame's change of objects, shared by every view: boxes
        /// uploaded, the BVH refit or rebuilt (HROC §6). Timed by the host
        /// around [`crate::Culler::set_bounds`] and the upload's completion.
        ObjectUpdate => "object update",
    }
);

impl Stage {
    /// True for the stages that draw the scene's geometry (the host's
    /// draws); the others are the cost of culling.
    pub fn draws_scene(self) -> bool {
        matches!(self, Stage::Draw | Stage::OcclusionMap | Stage::OccludeeRendering | Stage::FlaggedObjects)
    }
}

named_enum!(
    /// A per-frame statistic a method reports.
    Stat {
        /// |V|: last frame's visible set, drawn first.
        V => "V",
        /// |O|: effective occluders.
        O => "O",
        /// |G|: occludee groups tested.
        G => "G",
        /// |U|: occludees that passed the test.
        U => "U",
        /// Occludees drawn in the front lists of HROC's rounds before the last.
        Front => "front",
        /// |D|: occludees with a fragment through early-Z.
        D => "D",
        /// Rays cast by HROC's test.
        Rays => "rays",
        /// BVH nodes visited per ray.
        NodesPerRay => "nodes_per_ray",
        /// Boxes rasterized.
        Boxes => "boxes",
        /// Mid-frame read-backs.
        Readbacks => "readbacks",
        /// BVH levels tested (`ioc`).
        Levels => "levels",
        /// BVH nodes tested (`ioc`).
        NodesTested => "nodes_tested",
        /// Objects tested (`hzb`, `woc`).
        Tested => "tested",
        /// Objects crossing the near plane, visible untested.
        Near => "near",
        /// Warped-depth texels no splat reached (`woc`).
        FarTexels => "far_texels",
        /// Occlusion queries issued.
        Queries => "queries",
        /// Query result read-backs.
        QueryBatches => "query_batches",
        /// Boxes drawn inside queries.
        QueryBoxes => "query_boxes",
        /// Host ms waiting for query results.
        WaitMs => "wait_ms",
        /// Draw calls handed to the host.
        DrawCalls => "draw_calls",
        /// CHC++ multiqueries.
        Multiqueries => "multiqueries",
        /// CHC++ randomized re-queries.
        Requeried => "requeried",
        /// Nodes rendered without a query.
        RenderedUnqueried => "rendered_unqueried",
        /// 1 when the frame was culled as after a camera cut (signalled or detected).
        Cut => "cut",
        /// 1 when HROC seeded V with its ray grid this frame.
        Seeded => "seeded",
        /// Mid-frame submits.
        Submits => "submits",
        /// Mid-frame waits for the GPU.
        Waits => "waits",
        /// Bytes read back to the CPU during the frame.
        BytesRead => "bytes_read",
    }
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_round_trips_every_name() {
        let names = Method::names();
        for (name, m, what) in &names {
            assert_eq!(name.parse::<Method>().unwrap(), *m, "{name}");
            assert!(!what.is_empty());
        }
        let mut unique: Vec<_> = names.iter().map(|n| n.0).collect();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), names.len(), "a name is listed twice");
        // Every method of ALL is listed, under its own name.
        for m in Method::ALL {
            assert!(names.iter().any(|n| n.1 == m && n.0 == m.name()), "{m:?}");
        }
        assert_eq!("hroc-sf+of".parse::<Method>().unwrap(), Method::HROC);
        let e = "hroc-xyz".parse::<Method>().unwrap_err().to_string();
        assert!(e.contains("unknown method 'hroc-xyz'") && e.contains("chc++"), "{e}");
        assert_eq!(Method::parse_list("vfc, hroc-cr+of,vfc").unwrap(), [Method::Vfc, Method::Hroc(Variant::CR_OF)]);
        assert_eq!(Method::parse_list("hroc,hroc-sf+of").unwrap(), [Method::HROC]);
        assert_eq!(Method::parse_list("all").unwrap(), Method::ALL);
        assert!(Method::parse_list(" ").is_err());
    }

    #[test]
    fn stage_and_stat_names_are_unique() {
        let mut s: Vec<_> = Stage::ALL.iter().map(|s| s.name()).collect();
        s.sort_unstable();
        s.dedup();
        assert_eq!(s.len(), Stage::ALL.len());
        let mut t: Vec<_> = Stat::ALL.iter().map(|s| s.name()).collect();
        t.sort_unstable();
        t.dedup();
        assert_eq!(t.len(), Stat::ALL.len());
    }
}
