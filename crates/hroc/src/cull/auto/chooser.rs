//! Which candidate `auto` runs each frame: a cost model per candidate,
//! calibrated by the frames it measures, with probes and hysteresis.
//!
//! The model: a frame of candidate `m` costs `a_m + k · T_m` ms, where
//! `T_m` is the triangles it draws and `k` the device's cost of a drawn
//! triangle, shared by every candidate. `a_m` holds the candidate's own
//! passes and whatever else its frames cost. What a candidate would draw
//! now is known without running it: `noc` draws every triangle, `vfc` those
//! in the frustum (counted on the CPU), and an occlusion method the share
//! of the frustum's triangles it drew when it last ran. `k` is fitted
//! within candidates (least squares with an intercept per candidate, over
//! recent frames, less one standard error), so a change of view moves
//! every prediction as far as the frames show triangles to cost. An
//! occlusion method's frames after a camera cut are its warm-up from
//! nothing: left out of its estimate, they price a cut, and the recent rate
//! of cuts adds them to its prediction. A view's cost is more than its
//! triangles (the eye inside a box, every candidate costs 200 ms; out of
//! it, HROC costs 10), so an isolated camera cut starts each candidate's
//! estimate anew with its first steady frame after the cut, and until
//! then a warm-up frame of the new view bounds it from above (a warm-up
//! costs no less than a steady frame). Frames are measured by GPU
//! timestamps read back without a stall (or, without them, the CPU clock's
//! frame period).
//!
//! The choice:
//! - **Calibration.** Every candidate runs before any is chosen, the last
//!   given first (the one that culls most), unless a prediction of it is
//!   past [`Params::plausible`] times the best: on radial-city's own path
//!   at 20k objects `noc` never runs. A frame of any candidate that drew the whole
//!   frustum, or every object, is an upper bound of what `vfc`, or `noc`,
//!   costs: the caller observes it for them too (`hzb` taking over cold draws
//!   the frustum). After a camera cut, such a frame of the new view also
//!   bounds an estimate of them from before the cut. The last runs on until the measurements arrive, and
//!   the calibration ends with a switch to the best.
//! - **Hysteresis.** A switch needs the best prediction below
//!   `1 - margin` times the current one (`1 - 2 · margin` from one
//!   occlusion method to another that would draw more triangles) in
//!   `confirm` decisions in a row,
//!   `dwell` frames since the last switch (a saving past `3 · margin`
//!   needs neither: a mistake is undone at once), a saving over the
//!   next `probe_every` frames above what the switch costs (the warm-up
//!   frames of the candidate taking over, measured over its steady cost),
//!   and an estimate of the best measured within `dwell` frames: an older
//!   one is first checked by a probe (a heavier view raises every
//!   candidate's cost, but only the running one's estimate sees it).
//! - **Probes** (`probes.rs`). After the calibration, at most one frame in
//!   `probe_every` probes: the candidate measured longest ago (past
//!   `stale` frames, or `probe_every` where its estimate is one frame), if
//!   plausible (an estimate of one frame, a spike maybe, within
//!   [`Params::plausible_once`] times the best), runs for its warm-up
//!   frames and one more. A candidate that keeps
//!   state between frames takes frames after taking over to reach its
//!   steady cost (`auto` gives `hzb` and HROC two: HROC's first is the
//!   cut's seeded frame, `hzb`'s draws what its stale visible set and an
//!   empty pyramid pass); those are left out of its estimate, and so is a
//!   candidate's first frame ever (lazy set-up in drivers), which like a
//!   warm-up frame bounds its estimate from above (a stateless
//!   candidate's of one frame too: one spike of `vfc` in the calibration
//!   had a small scene on HROC for thirty frames). A probe of every candidate
//!   at least every `forced` frames keeps an unlucky estimate from sticking.
//! - **Probes after a change of view.** An occlusion method's share of the
//!   frustum holds for the view it was learnt on: after a camera cut, or
//!   once the frustum holds `view_change` times more or fewer triangles
//!   than when it was measured, it says nothing, and a cut leaves every
//!   occlusion method cold anyway. So while `vfc` or `noc` runs, the
//!   occlusion method predicted cheapest whose estimate is from another
//!   view is probed, at most one frame in `cut_probe_every` and while the
//!   probes' cost over the candidates they left stays within
//!   `probe_share` of the time measured (`spend.rs`): often where a probe
//!   is cheap, rarely where it is dear. After a change of the frustum
//!   alone, only a method whose intercept `a_m` (its frame drawing
//!   nothing) is below the running candidate's predicted frame is probed
//!   (a fuller frustum does not make its frame cheaper than that), and
//!   only once its cold frames too fit the probes' share: on a small
//!   scene a fuller frustum makes every method dearer, pixels more than
//!   triangles, and HROC's probe there cost more than its passes could
//!   save. While an occlusion method runs, `vfc` or `noc` measured before
//!   a cut is probed (if plausible): its estimate holds the view's own
//!   cost from before. So is `vfc` while `noc` runs (it draws no more
//!   than `noc`): with the eye inside boxes, where every candidate draws
//!   the whole scene and `noc` is cheapest, its estimate says nothing of
//!   the view after the cut.
//! - **Camera cuts.** At an isolated cut, the occlusion method running
//!   starts from nothing as another would, so a switch there costs no
//!   warm-up of its own: `hzb`, whose frames from nothing draw the whole
//!   frustum, hands over to HROC, reseeded by rays, where HROC's cold
//!   frames and first steady frame cost less ([`Chooser::cold_ms`]).
//!
//! A candidate taking over (`fresh`) starts from the visible set of the
//! last candidate that keeps one (`hzb` and HROC do) if that one ran
//! within [`ARRIVAL`] frames and no camera cut came since, or from its own
//! set where that is as recent and smaller ([`Decision::from`]: itself,
//! after a probe of `vfc` or `noc`, or HROC after a probe of `hzb`,
//! resumes); else it starts as after a cut. Its warm-up is counted for
//! the way it starts ([`WarmUp`]).

use super::fit::Fit;
use super::params::Params;
use super::spend::Spend;

/// Frames within which a frame's measurement arrives (the read-back ring
/// holds three); one lost is not waited for longer. Also the oldest
/// visible set a candidate taking over starts from.
const ARRIVAL: u64 = 8;

mod io;
pub use io::{Decision, Load, Observation, WarmUp};

#[derive(Clone, Copy, Debug)]
struct Probe {
    candidate: usize,
    left: u32,
    back_to: usize,
}

/// The per-view chooser.
#[derive(Clone, Debug)]
pub struct Chooser {
    loads: Vec<Load>,
    /// Frames each candidate takes after taking over to reach its steady cost.
    warm: Vec<WarmUp>,
    /// The candidate of the last decision.
    last: Option<usize>,
    /// The last frame of each candidate whose visible set a candidate
    /// taking over may start from (none before it ran, after a camera cut,
    /// and where the set is the frustum: [`WarmUp::cold_frustum`]).
    sets: Vec<Option<u64>>,
    /// Warm-up frames left of the candidate running.
    warming: u32,
    /// ... from nothing (not from a visible set handed over).
    warming_cold: bool,
    fits: Vec<Fit>,
    /// The frame each candidate last ran, first ran, and last was measured.
    ran: Vec<Option<u64>>,
    started: Vec<Option<u64>>,
    measured: Vec<Option<u64>>,
    /// The frustum's triangles in each candidate's last measured frame.
    measured_frustum: Vec<f64>,
    current: Option<usize>,
    /// The frame of the last switch (none before calibration ended).
    switched_at: Option<u64>,
    better: u32,
    /// The last probe checking a candidate's old estimate before a switch to it, and its frame.
    checked: Option<(usize, u64)>,
    probe: Option<Probe>,
    last_probe: u64,
    params: Params,
    /// Frames each candidate ran, probes included.
    pub frames_run: Vec<u64>,
    /// Frames spent probing, and of them in the calibration.
    pub probe_frames: u64,
    calibration_frames: u64,
    /// What a warm-up frame of each candidate costs over its steady frame,
    /// ms: starting cold, and from a visible set handed over.
    switch_ms: Vec<[Option<f64>; 2]>,
    /// The least cost of a frame of another candidate that drew what this
    /// one would (the whole frustum for `vfc`, everything for `noc`) since
    /// the last cut, and the last such frame: an upper bound of its cost,
    /// used until it is measured itself, or again after a cut.
    bound_ms: Vec<Option<(u64, f64)>>,
    /// The last warm-up frame of each candidate measured after its last
    /// steady frame, and its cost: an upper bound of its steady cost in
    /// that frame's view.
    warm_ms: Vec<Option<(u64, f64)>>,
    /// The frame of the first decision.
    first_frame: Option<u64>,
    /// A camera cut came since the last decision; the frame of the last.
    cut_seen: bool,
    last_cut: Option<u64>,
    /// The share of recent frames that were camera cuts (decayed as the fits are).
    cut_rate: f64,
    /// What the probes after the calibration cost.
    spend: Spend,
}

impl Chooser {
    /// A chooser over candidates with these loads; `warm[i]` frames after
    /// taking over, candidate `i` reaches its steady cost. A candidate
    /// with [`Load::Occluded`] keeps a visible set it hands over.
    ///
    /// # Panics
    /// With no candidates, or `warm` not one per candidate.
    pub fn new(loads: Vec<Load>, warm: Vec<WarmUp>, params: Params) -> Chooser {
        let n = loads.len();
        assert!(n > 0 && warm.len() == n, "one load and one warm-up per candidate");
        Chooser {
            loads,
            warm,
            last: None,
            sets: vec![None; n],
            warming: 0,
            warming_cold: false,
            fits: vec![Fit::default(); n],
            ran: vec![None; n],
            started: vec![None; n],
            measured: vec![None; n],
            measured_frustum: vec![0.0; n],
            current: None,
            switched_at: None,
            better: 0,
            checked: None,
            probe: None,
            last_probe: 0,
            params,
            frames_run: vec![0; n],
            probe_frames: 0,
            switch_ms: vec![[None; 2]; n],
            bound_ms: vec![None; n],
            warm_ms: vec![None; n],
            first_frame: None,
            calibration_frames: 0,
            cut_seen: false,
            last_cut: None,
            cut_rate: 0.0,
            spend: Spend::default(),
        }
    }

    /// Takes a measured frame of candidate `o.candidate` (an index below the
    /// candidates' count; frames in any order). A steady frame's cost counts up to twice the candidate's prediction
    /// (a camera jump's spike moves the estimate, but not as far as one
    /// frame would pull a mean); a warm-up frame's excess over the
    /// prediction is what a switch to the candidate costs, and bounds its
    /// prediction from above until a steady frame after it is measured or
    /// a camera cut comes (a warm-up frame costs no less than a steady
    /// one, and after a cut the estimate is from another view). After an
    /// isolated cut ([`Params::isolated_cuts`]) the first steady frame
    /// starts the candidate's estimate anew.
    pub fn observe(&mut self, o: &Observation) {
        if !o.cost_ms.is_finite() || o.cost_ms < 0.0 {
            return;
        }
        if self.switched_at.is_some() {
            self.spend.measured(o.frame, o.cost_ms);
        }
        let i = o.candidate;
        let (predicted, measured) = self.model(i, o.frustum_triangles, f64::INFINITY);
        if o.warm_up {
            if measured {
                let excess = (o.cost_ms - predicted).max(0.0);
                let e = &mut self.switch_ms[i][o.handed as usize];
                *e = Some(e.map_or(excess, |e| 0.5 * (e + excess)));
            }
            let after = |f: Option<u64>| f.is_none_or(|f| o.frame > f);
            if after(self.measured[i]) && after(self.warm_ms[i].map(|w| w.0)) {
                self.warm_ms[i] = Some((o.frame, o.cost_ms));
            }
            return;
        }
        // An isolated camera cut starts the estimate anew with the first
        // steady frame after it: frames of another view weigh on a fit
        // for dozens of frames, and a view's cost is more than its
        // triangles (the eye inside a box, every candidate costs 200 ms;
        // out of it, HROC 10). On a path of cuts, one view is as good a
        // guide to the next as any.
        let before_cut = |f: Option<u64>| self.last_cut.is_some() && f.is_none_or(|f| !self.in_view(f));
        if before_cut(Some(o.frame)) && !before_cut(self.measured[i]) {
            return;
        }
        let anew = before_cut(self.measured[i]) && !before_cut(Some(o.frame)) && self.cut_rate < self.params.isolated_cuts;
        if anew {
            self.fits[i] = Fit::default();
        }
        let cost_ms = if measured && !anew && self.loads[i] != Load::All { o.cost_ms.min(2.0 * predicted) } else { o.cost_ms };
        self.fits[i].add(&Observation { cost_ms, ..*o }, self.params.decay);
        if self.measured[i].is_none_or(|m| o.frame >= m) {
            self.measured[i] = Some(o.frame);
            self.measured_frustum[i] = o.frustum_triangles;
            // A stateless candidate's estimate of one frame may be a spike
            // (lavapipe's `vfc` frames on a small scene: one in six at
            // twice the rest): its first frame still bounds it.
            let one = self.fits[i].n < 1.5 && self.loads[i] != Load::Occluded;
            self.warm_ms[i] = self.warm_ms[i].filter(|w| w.0 > o.frame || one);
        }
    }

    /// Takes a measured frame ([`Chooser::observe`]) of a view holding
    /// `all` triangles; a frame that drew the whole frustum (or every
    /// object) bounds what `vfc` (or `noc`) costs from above
    /// ([`Chooser::bound`]). A candidate's `first` frame ever pays for
    /// lazy set-up besides: a warm-up frame of its own, it bounds that
    /// candidate's cost and no other's.
    pub fn observe_frame(&mut self, o: &Observation, all: f64, first: bool) {
        if first {
            self.observe(&Observation { warm_up: true, ..*o });
            return;
        }
        self.observe(o);
        for (load, drew) in [(Load::Frustum, o.triangles >= 0.95 * o.frustum_triangles), (Load::All, o.triangles >= 0.95 * all)] {
            if let Some(b) = self.with_load(load).filter(|&b| drew && b != o.candidate) {
                self.bound(b, o.frame, o.cost_ms);
            }
        }
    }

    /// The candidate to run at `frame`, with `frustum` of `all` triangles
    /// in the view.
    /// Call once per frame, with frame numbers that do not decrease.
    pub fn decide(&mut self, frame: u64, frustum: f64, all: f64) -> Decision {
        self.first_frame.get_or_insert(frame);
        let cut = std::mem::take(&mut self.cut_seen);
        if cut {
            self.last_cut = Some(frame);
        }
        self.cut_rate = self.cut_rate * self.params.decay + (1.0 - self.params.decay) * cut as u32 as f64;
        let mut d = self.decide_inner(frame, frustum, all);
        if let Some(pr) = self.probe.filter(|_| d.probe && self.switched_at.is_some()) {
            let left = self.predict(pr.back_to, frustum, all).0;
            self.spend.probe(frame, left);
        }
        d.fresh &= self.last != Some(d.candidate);
        d.from = self.source(frame, d.candidate).filter(|_| d.fresh && self.loads[d.candidate] == Load::Occluded);
        if d.fresh {
            // A candidate's first frames ever also pay for lazy set-up.
            self.warming = self.warm[d.candidate].frames(d.from.is_some()).max(self.first(d.candidate) as u32);
            self.warming_cold = d.from.is_none();
        } else if cut && self.switched_at.is_some() && self.loads[d.candidate] == Load::Occluded {
            // An occlusion method running through a cut starts from
            // nothing: its frames until it settles price the cut, not its
            // steady cost (they made HROC look cheap on a path of cuts,
            // its reseeded frames read as triangles).
            self.warming = self.warming.max(self.warm[d.candidate].cold);
            self.warming_cold = true;
        }
        self.last = Some(d.candidate);
        if self.loads[d.candidate] == Load::Occluded {
            // A frame from nothing that draws the whole frustum (`hzb`'s)
            // leaves a visible set of the frustum: handed to HROC it had
            // HROC draw the frustum (38.8 ms, where HROC from nothing,
            // reseeded, takes 13); the next to take over starts cold.
            let frustum_set = self.warming > 0 && self.warming_cold && self.warm[d.candidate].cold_frustum;
            self.sets[d.candidate] = (!frustum_set).then_some(frame);
        }
        d.measured = self.warming == 0;
        d.first = self.first(d.candidate);
        self.warming = self.warming.saturating_sub(1);
        self.frames_run[d.candidate] += 1;
        self.probe_frames += d.probe as u64;
        self.calibration_frames += (d.probe && self.switched_at.is_none()) as u64;
        self.ran[d.candidate] = Some(frame);
        d
    }

    fn decide_inner(&mut self, frame: u64, frustum: f64, all: f64) -> Decision {
        let p = self.params;
        let n = self.loads.len();
        let predictions: Vec<(f64, bool)> = (0..n).map(|i| self.predict(i, frustum, all)).collect();
        let measured_best = measured_best(&predictions);
        let plausible = |i: usize| self.plausible(i, &predictions);
        // Calibration: every plausible candidate runs, one after another,
        // each judged once the measurements before it arrived.
        // Waiting, from when a candidate first ran, for its first measurement.
        let arriving = |i: usize| self.started[i].is_some_and(|r| frame < r.saturating_add(ARRIVAL)) && self.measured[i].is_none();
        let waiting = (0..n).any(arriving) || !measured_best.is_finite();
        // After it, `noc` is tried only while `vfc` runs: it differs from
        // `vfc` by `vfc`'s passes and the triangles out of the frustum.
        let against = |i: usize| self.switched_at.is_none() || self.loads[i] != Load::All || self.current.is_some_and(|c| self.loads[c] == Load::Frustum);
        let untried = (0..n).rev().find(|&i| self.ran[i].is_none() && plausible(i) && against(i)).filter(|_| !waiting);
        // A probe under way runs to its end, then hands on to the
        // calibration's next, or back. The calibration's last probe runs
        // on while measurements are on their way, then the calibration
        // ends (below) with one switch, not one back and another.
        if let Some(pr) = self.probe.as_mut() {
            let last = self.switched_at.is_none() && untried.is_none();
            if pr.left > 0 || (last && waiting) {
                pr.left = pr.left.saturating_sub(1);
                return Decision { candidate: pr.candidate, fresh: false, probe: true, measured: true, first: false, from: None };
            }
            let back = pr.back_to;
            self.probe = None;
            self.current = Some(back);
            if let Some(i) = untried {
                return self.start_probe(frame, i, back);
            }
            if !last {
                return Decision { candidate: back, fresh: true, probe: false, measured: true, first: false, from: None };
            }
        }
        let Some(current) = self.current else {
            let first = n - 1;
            self.current = Some(first);
            self.started[first] = Some(frame);
            return Decision { candidate: first, fresh: true, probe: false, measured: true, first: false, from: None };
        };
        if let Some(i) = untried {
            return self.start_probe(frame, i, current);
        }
        if waiting {
            return Decision { candidate: current, fresh: false, probe: false, measured: true, first: false, from: None };
        }
        // An isolated camera cut, with an occlusion method running.
        if let Some(b) = self.cut_takeover(frame, current, &predictions, frustum, all) {
            self.better = 0;
            self.current = Some(b);
            self.switched_at = Some(frame);
            return Decision { candidate: b, fresh: true, probe: false, measured: true, first: false, from: None };
        }
        // Probes: of a stale estimate, else of one from another view.
        if let Some(i) = self.stale_probe(frame, current, &predictions).or_else(|| self.view_probe(frame, current, &predictions, frustum)) {
            return self.start_probe(frame, i, current);
        }
        // The choice, with hysteresis.
        let occluding = |i: usize| self.loads[i] == Load::Occluded;
        let best = (0..n).filter(|&i| predictions[i].1).min_by(|&a, &b| predictions[a].0.total_cmp(&predictions[b].0)).unwrap_or(current);
        // The calibration's end: straight to the best, or, where that is
        // an occlusion method, to the one of them within twice the margin
        // of it that draws least (as a switch asks, below).
        let Some(switched_at) = self.switched_at else {
            let best = (0..n)
                .filter(|&i| occluding(best) && occluding(i) && predictions[i].1 && (1.0 - 2.0 * p.margin) * predictions[i].0 <= predictions[best].0)
                .min_by(|&a, &b| self.load(a, frustum, all).total_cmp(&self.load(b, frustum, all)))
                .unwrap_or(best);
            self.switched_at = Some(frame);
            self.current = Some(best);
            // Fresh unless it ran last frame (`decide`).
            return Decision { candidate: best, fresh: true, probe: false, measured: true, first: false, from: None };
        };
        // A switch pays the warm-up of the candidate taking over: worth it
        // when the saving over the next `probe_every` frames covers it.
        let handed = self.source(frame, best).is_some();
        let switch_ms = self.warm[best].frames(handed) as f64 * self.switch_ms[best][handed as usize].unwrap_or(0.0);
        let saving = predictions[current].0 - predictions[best].0;
        // Between occlusion methods, trading culling for fixed cost asks
        // twice the margin: the one that draws more pays for disocclusions
        // its estimate has not seen (what `vfc` and `noc` draw is counted
        // each frame).
        let margin = if occluding(best) && occluding(current) && self.load(best, frustum, all) > self.load(current, frustum, all) { 2.0 * p.margin } else { p.margin };
        if best != current && saving > margin * predictions[current].0 && saving * p.probe_every as f64 > switch_ms {
            self.better += 1;
        } else {
            self.better = 0;
        }
        // A saving past three margins switches at once, without the dwell
        // or the confirmation: a switch that measures far worse than the
        // candidate it left is undone, and a probe that finds a candidate
        // far cheaper is followed.
        let far = saving > 3.0 * p.margin * predictions[current].0 && self.better > 0;
        if far || (self.better >= p.confirm && frame >= switched_at.saturating_add(p.dwell)) {
            // An estimate older than the dwell is checked by a probe first:
            // what every candidate costs moves with the view, and a stale
            // estimate only sees the triangles move.
            let recent = self.measured[best].is_some_and(|m| frame <= m.saturating_add(p.dwell));
            if !recent {
                if self.checked.is_none_or(|(c, f)| c != best || frame > f.saturating_add(ARRIVAL)) {
                    self.checked = Some((best, frame));
                    self.better = 0;
                    return self.start_probe(frame, best, current);
                }
                return Decision { candidate: current, fresh: false, probe: false, measured: true, first: false, from: None };
            }
            self.better = 0;
            self.current = Some(best);
            self.switched_at = Some(frame);
            return Decision { candidate: best, fresh: true, probe: false, measured: true, first: false, from: None };
        }
        Decision { candidate: current, fresh: false, probe: false, measured: true, first: false, from: None }
    }

    /// The candidate whose visible set candidate `c` taking over at
    /// `frame` starts from: of the sets left within [`ARRIVAL`] frames,
    /// the last, or `c`'s own where it drew a smaller share of the
    /// frustum. A set larger than its own has a candidate draw what it
    /// would have culled: HROC resuming from `hzb`'s set after a probe of
    /// `hzb` cost 1.21 × its frame (median over five matrices), from its
    /// own after a probe of `vfc` 1.04 ×, and `hzb` from HROC's set 0.95 ×.
    fn source(&self, frame: u64, c: usize) -> Option<usize> {
        let recent = |i: usize| self.sets[i].filter(|&f| frame <= f.saturating_add(ARRIVAL));
        let last = (0..self.sets.len()).filter_map(|i| recent(i).map(|f| (f, i))).max()?.1;
        let smaller = |a: usize, b: usize| self.fits[a].n > 0.0 && self.fits[b].n > 0.0 && self.fits[a].share < self.fits[b].share;
        Some(if recent(c).is_some() && smaller(c, last) { c } else { last })
    }

    /// A candidate's first frame ever, left out of its estimate: it may pay
    /// for lazy set-up in drivers that [`crate::cull::CullMethod::warm`]
    /// does not reach (first touches of its buffers; HROC's pipelines), and
    /// with frame times as noisy as lavapipe's, the calibration's second
    /// frame of each candidate keeps one spike from deciding (measuring the
    /// first frame of a warmed `vfc` made the replays 0.4-4 % dearer).
    fn first(&self, i: usize) -> bool {
        self.ran[i].is_none()
    }

    /// A camera cut: the candidate running reset its state, and the next
    /// to take over starts from nothing.
    pub fn cut(&mut self) {
        self.sets.fill(None);
        self.cut_seen = true;
    }

    fn start_probe(&mut self, frame: u64, i: usize, back_to: usize) -> Decision {
        self.last_probe = frame;
        self.started[i].get_or_insert(frame);
        let warm = self.warm[i].frames(self.source(frame, i).is_some() && self.loads[i] == Load::Occluded);
        // In the calibration an occlusion method, near its steady cost from
        // a visible set handed over, measures two frames.
        let second = (self.switched_at.is_none() && self.loads[i] == Load::Occluded) as u32;
        self.probe = Some(Probe { candidate: i, left: warm.max(self.first(i) as u32) + second, back_to });
        Decision { candidate: i, fresh: true, probe: true, measured: true, first: false, from: None }
    }

    /// Whether frame `frame`, decided `d`, is to be measured: every frame
    /// of the calibration, of a probe and of a warm-up, every frame within
    /// the dwell after a switch (where a mistake is undone), and else one
    /// in [`Params::time_every`] (timing a frame has a cost: on an H200
    /// two timestamps, their resolve and copy took 5 % of a 0.8 ms frame).
    /// Call after [`Chooser::decide`].
    pub fn times(&self, d: &Decision, frame: u64) -> bool {
        let settling = self.switched_at.is_none_or(|s| frame < s.saturating_add(self.params.dwell));
        d.fresh || !d.measured || settling || self.probe.is_some() || frame.is_multiple_of(self.params.time_every.max(1))
    }

    /// The candidate with `load`, if any.
    pub fn with_load(&self, load: Load) -> Option<usize> {
        self.loads.iter().position(|&l| l == load)
    }

    /// Replaces the constants (tests make it switch often).
    pub fn set_params(&mut self, params: Params) {
        self.params = params;
    }
}

mod predict;
use predict::measured_best;
mod probes;

#[cfg(test)]
mod replay;
#[cfg(test)]
mod tests;
