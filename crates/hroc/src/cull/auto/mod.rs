//! `auto`: per view and per frame, the cheapest of drawing everything
//! (`noc`), frustum culling (`vfc`), two-phase Hi-Z (`hzb`) and HROC, by
//! what each costs on this device, scene and path. A frame:
//! 1. measurements: the frames whose GPU time and triangles came back
//!    (timestamps read without a stall, [`crate::tally::FrameStats`]) feed each
//!    candidate's cost model (`chooser.rs`); without `TIMESTAMP_QUERY`,
//!    the CPU clock's frame period stands in for the GPU time. Every frame
//!    of a probe, a warm-up or a switch's dwell is timed, a steady frame
//!    one in four;
//! 2. load: the triangles in the frustum, counted on the CPU over the BVH
//!    (`load.rs`), which predicts what `noc` and `vfc` would cost now and
//!    scales the occlusion methods' draws;
//! 3. choice: the chooser's candidate, with hysteresis, a probe of a
//!    stale estimate at most one frame in thirty, and a probe of an
//!    occlusion method after a change of view (a camera cut, or a frustum
//!    three times fuller or emptier) while its cost stays a small share of
//!    the time;
//! 4. the candidate's frame. A candidate taking over starts from the
//!    visible set of the last `hzb` or HROC frame, if one ran in the last
//!    few frames ([`CullMethod::take_over`]; its own set after a probe of
//!    `vfc` or `noc`, or of a method whose set is larger), as from its
//!    own last frame; else, and after a camera cut, it culls as after a
//!    cut (HROC reseeds). The one handing
//!    over keeps its read-backs in flight (the stall-free counters take
//!    them when it runs again). The first frame also warms the other
//!    candidates' pipelines ([`CullMethod::warm`]): on lavapipe, `vfc`
//!    taking over for the first time cost 3-8 ms more than its next frame
//!    without it, and `hzb` as much.
//!
//! Every candidate is conservative, and each frame is one candidate's
//! whole frame, so `auto` is as conservative as they are.

mod chooser;
mod fit;
mod load;
mod params;
mod spend;

pub use chooser::{Chooser, Decision, Load, Observation, WarmUp};
pub use params::Params;

use crate::cull::facts::Facts;
use std::collections::VecDeque;

use super::{CullMethod, Frame, Method, Stat};
use crate::error::Result;
use crate::gpu::Gpu;
use load::FrustumLoad;

/// `auto`'s facts (its candidates are checked one by one: `Culler::auto_candidates`).
pub(crate) const FACTS: Facts = Facts { name: "auto", description: "adaptive: each frame the cheapest of noc, vfc, hzb and hroc, by measured and modelled cost", ..Facts::GPU };

/// A frame run, awaiting its measurement.
#[derive(Clone, Copy, Debug)]
struct Pending {
    frame: u64,
    candidate: usize,
    cpu_ms: f64,
    frustum_triangles: f64,
    /// Left out of the candidate's estimate: a warm-up frame after it took over.
    left_out: bool,
    /// ... from the visible set handed over.
    handed: bool,
    /// The candidate's first frame ever.
    first: bool,
    /// The CPU clock's period from this frame to the next (without timestamps).
    period_ms: Option<f64>,
}

/// Frames `m` takes after taking over from another method to reach its
/// steady cost. From nothing: HROC's first is the cut's (V seeded by
/// rays), and its second draws what the seed's depth left untested;
/// `hzb`'s first draws the frustum (an empty V and pyramid), its second
/// finds the visible set from the depth the first left. From a visible
/// set handed over: `hzb` is at once steady, HROC's first frame draws
/// `hzb`'s larger set.
fn warm_up(m: Method) -> WarmUp {
    match m {
        Method::Noc | Method::Vfc => WarmUp::NONE,
        Method::Hzb => WarmUp { cold: 2, handed: 0, cold_frustum: true },
        _ => WarmUp { cold: 2, handed: 1, cold_frustum: false },
    }
}

/// The `auto` method: its candidates' states and the chooser.
pub struct Auto {
    candidates: Vec<(Method, Box<dyn CullMethod>)>,
    chooser: Chooser,
    load: FrustumLoad,
    pending: VecDeque<Pending>,
    /// The last frame's decision.
    last: Option<Decision>,
    /// The device times frames with timestamps (else the CPU period stands in).
    timed: bool,
}

impl Auto {
    /// `auto` over `candidates` (created from `cx`): fails with none, with
    /// a candidate that is not conservative, needs an oracle, keeps its own
    /// tree, submits mid-frame or does not follow motion (only `noc`, `vfc`,
    /// `hzb`, `roc`, `roc-all` and the HROC variants without read-back
    /// qualify), or one that cannot be created.
    pub fn new(cx: &super::MethodContext, candidates: &[Method]) -> Result<Auto> {
        let unfit = |m: &Method| *m == Method::Auto || !m.is_conservative() || m.is_benchmark_only() || m.keeps_tree() || m.submits_mid_frame() || !m.takes_dynamic();
        if candidates.is_empty() {
            return Err(crate::error::Error::Arg("auto needs at least one candidate method".into()));
        }
        if let Some(m) = candidates.iter().find(|m| unfit(m)) {
            return Err(crate::error::Error::Arg(format!("{m} cannot be one of auto's candidates")));
        }
        // `auto` chooses the frustum itself: its HROC candidate culls every
        // frame it runs by occlusion.
        let whole = super::MethodOptions { hroc_frustum_below: 0.0, ..cx.options.clone() };
        let cx = &super::MethodContext { options: &whole, ..*cx };
        let methods = candidates.iter().map(|&m| Ok((m, m.create(cx)?))).collect::<Result<Vec<_>>>()?;
        let loads = candidates
            .iter()
            .map(|m| match m {
                Method::Noc => Load::All,
                Method::Vfc => Load::Frustum,
                _ => Load::Occluded,
            })
            .collect();
        let warm = candidates.iter().map(|&m| warm_up(m)).collect();
        Ok(Auto {
            candidates: methods,
            chooser: Chooser::new(loads, warm, Params::default()),
            load: FrustumLoad::default(),
            pending: VecDeque::new(),
            last: None,
            timed: cx.gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY),
        })
    }

    /// The chooser, to change its constants (tests make it switch often).
    pub fn chooser_mut(&mut self) -> &mut Chooser {
        &mut self.chooser
    }

    /// Step 1: takes the measurements that came back.
    fn measure(&mut self, f: &mut Frame) {
        let arrived = if self.timed { f.tally.latest_timed(f.gpu) } else { f.tally.latest(f.gpu) };
        let period = f.period_ms;
        let (chooser, timed, all) = (&mut self.chooser, self.timed, self.load.all);
        let mut observe = |p: &Pending, cost_ms: f64, triangles: f64| {
            let o = Observation { candidate: p.candidate, frame: p.frame, cost_ms, triangles, frustum_triangles: p.frustum_triangles, warm_up: p.left_out, handed: p.handed };
            chooser.observe_frame(&o, all, p.first);
        };
        // Without timestamps, the period since the last frame began is the
        // last frame's cost.
        if let (Some(p), Some(ms)) = (self.pending.back_mut(), period) {
            p.period_ms.get_or_insert(ms);
        }
        if let Some(s) = arrived {
            while let Some(p) = self.pending.front().copied().filter(|p| p.frame <= s.frame) {
                self.pending.pop_front();
                // A frame whose timestamps did not come back is not a measurement.
                let cost_ms = if timed { s.gpu_ns.map(|ns| ns as f64 / 1e6 + p.cpu_ms) } else { p.period_ms };
                if let (true, Some(c)) = (p.frame == s.frame, cost_ms) {
                    observe(&p, c, s.triangles as f64);
                }
            }
        }
        // Nothing older than the ring can still arrive.
        while self.pending.len() > 8 {
            self.pending.pop_front();
        }
    }
}

impl CullMethod for Auto {
    fn method(&self) -> Method {
        Method::Auto
    }

    fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        if let Some(d) = self.last {
            self.candidates[d.candidate].1.reset(enc);
        }
        self.chooser.cut();
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        // 1. Measurements.
        self.measure(f);
        // 2. Load.
        let (tree, generation) = f.tree;
        self.load.refresh(tree, generation, &f.objects.cpu_commands);
        let frustum = self.load.count(tree, &f.geometry.planes);
        // 3. Choice.
        let d = self.chooser.decide(f.number, frustum, self.load.all);
        if self.chooser.times(&d, f.number) {
            f.tally.start_clock(f.encoder);
        }
        if d.fresh && self.last.is_some() && d.from != Some(d.candidate) {
            let visible = d.from.and_then(|c| self.candidates[c].1.visible_set().cloned());
            self.candidates[d.candidate].1.take_over(f.encoder(), visible.as_ref());
        }
        if self.last.is_none() {
            // The first frame compiles the others' pipelines, which drivers
            // may leave to their first use (`CullMethod::warm`).
            for (i, (_, c)) in self.candidates.iter().enumerate() {
                if i != d.candidate {
                    c.warm(f.encoder());
                }
            }
        }
        let (method, imp) = &mut self.candidates[d.candidate];
        // 4. The candidate's frame (a failure part-way resets it: `reset`).
        f.culled_by = *method;
        self.last = Some(d);
        let start = std::time::Instant::now();
        imp.frame(f)?;
        self.pending.push_back(Pending {
            frame: f.number,
            candidate: d.candidate,
            cpu_ms: start.elapsed().as_secs_f64() * 1e3,
            frustum_triangles: frustum,
            left_out: !d.measured,
            handed: d.from.is_some(),
            first: d.first,
            period_ms: None,
        });
        Ok(())
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let Some(d) = self.last else { return Ok(Vec::new()) };
        let (method, imp) = &mut self.candidates[d.candidate];
        let mut s = imp.stats(gpu)?;
        let chosen = Method::ALL.iter().position(|m| m == method).unwrap_or(0);
        s.extend([(Stat::Chosen, chosen as f64), (Stat::Probe, d.probe as u32 as f64)]);
        Ok(s)
    }

    fn tested_nodes(&self, gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        match self.last {
            Some(d) => self.candidates[d.candidate].1.tested_nodes(gpu),
            None => Ok(None),
        }
    }
}
