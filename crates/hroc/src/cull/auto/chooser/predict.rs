//! What each candidate of `chooser.rs` is predicted to cost: the cost
//! model (an intercept per candidate and a triangle cost shared by all,
//! fitted within candidates), the bounds that stand in before it is
//! measured or where its estimate is from another view, and the price of
//! camera cuts.

use super::{Chooser, Load};

/// Standard errors taken off the fitted ms per triangle
/// ([`Chooser::triangle_ms`]).
const SLOPE_ERRORS: f64 = 1.0;

impl Chooser {
    /// ms per drawn triangle, clamped to `[0, least mean cost per mean
    /// triangle]`: that bound until the frames can fit a slope (a
    /// candidate measured twice, triangles that vary within a
    /// candidate); then the within-candidate least-squares slope less
    /// [`SLOPE_ERRORS`] standard errors (decayed frames, less one per
    /// candidate and one for the slope, are its degrees of freedom). Frame
    /// times vary from frame to frame more than a small change of
    /// triangles explains, and a slope the frames do not establish
    /// would have a change of view move every prediction: on a small
    /// scene, whose frame is its passes and its pixels, a fuller frustum
    /// made HROC look cheaper than `vfc` and had it probed.
    pub fn triangle_ms(&self) -> f64 {
        // Sums over candidates of (t - mean t)(c - mean c), (t - mean t)²
        // and (c - mean c)², and the residual's degrees of freedom.
        let (mut tc, mut tt, mut cc, mut dof, mut scale) = (0.0, 0.0, 0.0, -1.0, 0.0);
        let mut bound = f64::INFINITY;
        for f in self.fits.iter().filter(|f| f.n > 0.0) {
            scale += f.tt;
            if f.t > 0.0 {
                bound = bound.min(f.c / f.t);
            }
            if f.n > 1.0 {
                tc += f.tc - f.t * f.c / f.n;
                tt += f.tt - f.t * f.t / f.n;
                cc += f.cc - f.c * f.c / f.n;
                dof += f.n - 1.0;
            }
        }
        let bound = if bound.is_finite() { bound } else { 0.0 };
        if tt <= 1e-4 * scale || dof <= 0.0 {
            return bound;
        }
        let slope = tc / tt;
        let residual = (cc - slope * tc).max(0.0) / dof;
        (slope - SLOPE_ERRORS * (residual / tt).sqrt()).clamp(0.0, bound)
    }

    /// Frame `frame` is of the view now: no camera cut came after it.
    pub(super) fn in_view(&self, frame: u64) -> bool {
        self.last_cut.is_none_or(|c| frame >= c)
    }

    /// Triangles candidate `i` would draw now.
    /// The frustum's count is an estimate: `vfc` draws the share of it
    /// its frames drew, as an occlusion method does.
    pub(super) fn load(&self, i: usize, frustum: f64, all: f64) -> f64 {
        match self.loads[i] {
            Load::All => all,
            Load::Frustum | Load::Occluded => self.fits[i].share * frustum,
        }
    }

    /// Takes frame `frame` of another candidate that drew what candidate
    /// `i` would, costing `cost_ms`: an upper bound of `i`'s cost in that
    /// frame's view, which predicts it until `i` is measured (no fit, no
    /// staleness changes), and after a camera cut bounds an estimate of
    /// `i` from before the cut until `i` is measured again. The least of
    /// the bounds since the last cut is kept.
    pub fn bound(&mut self, i: usize, frame: u64, cost_ms: f64) {
        if !cost_ms.is_finite() || cost_ms < 0.0 {
            return;
        }
        self.bound_ms[i] = match self.bound_ms[i] {
            Some((f, b)) if self.in_view(f) == self.in_view(frame) => Some((f.max(frame), b.min(cost_ms))),
            // A frame from before the cut arriving late.
            Some(kept) if self.in_view(kept.0) => Some(kept),
            _ => Some((frame, cost_ms)),
        };
    }

    /// Predicted ms of candidate `i` now, and whether it was measured.
    /// Before it was: 0 (untried, so tried), except for drawing every
    /// object, which costs what drawing the frustum does plus the rest at
    /// [`Chooser::triangle_ms`]: until the frames fit a slope, the highest
    /// cost per triangle they allow (a guess on the high side: on
    /// radial-city's own path at 20k objects, `noc` is never tried), then
    /// the slope they fit (on a small scene, whose frame is its passes and
    /// pixels, `noc` drew 5,562 triangles against `vfc`'s 752 and cost 8 %
    /// less; the highest cost put it at seven times `vfc`'s).
    pub fn predict(&self, i: usize, frustum: f64, all: f64) -> (f64, bool) {
        let (ms, measured) = self.steady(i, frustum, all);
        (ms + if measured { self.cut_ms(i, frustum, all) } else { 0.0 }, measured)
    }

    /// What camera cuts add to a frame of candidate `i` at the recent rate
    /// of cuts: an occlusion method's frames after a cut are its warm-up
    /// from nothing, priced by [`Chooser::cold_ms`] (as measured, else
    /// bounded below where they draw the frustum: a known cost of HROC's
    /// cold frames made it dearer than `hzb`, whose cold frames cost more
    /// but were not yet measured).
    pub(super) fn cut_ms(&self, i: usize, frustum: f64, all: f64) -> f64 {
        match self.loads[i] {
            Load::Occluded => self.cut_rate * self.warm[i].cold as f64 * self.cold_ms(i, frustum, all),
            _ => 0.0,
        }
    }

    /// At a camera cut, while occlusion method `current` runs (the
    /// calibration over) and cuts are isolated ([`Params::isolated_cuts`](super::Params::isolated_cuts)):
    /// the occlusion method to take over, if not `current`. Whichever
    /// runs now starts from nothing, so a switch costs no warm-up of its
    /// own: the one whose cold frames and first steady frame cost least,
    /// by [`Chooser::cold_ms`], by more than the margin, takes over. Only
    /// from a candidate whose cold frames draw the whole frustum
    /// ([`WarmUp::cold_frustum`](super::WarmUp::cold_frustum)) to one whose do not: there the
    /// difference is known before either ran through a cut (radial-city's
    /// own path at 20k objects: `hzb` through the cut 50 and 43 ms, HROC,
    /// reseeded, 27 and 15, at equal steady cost); between others, estimates
    /// from another view would decide.
    pub(super) fn cut_takeover(&self, frame: u64, current: usize, predictions: &[(f64, bool)], frustum: f64, all: f64) -> Option<usize> {
        let occluding = |i: usize| self.loads[i] == Load::Occluded;
        if self.last_cut != Some(frame) || self.switched_at.is_none() || !occluding(current) || !self.warm[current].cold_frustum || self.cut_rate >= self.params.isolated_cuts {
            return None;
        }
        let cost = |i: usize| {
            let cold = self.warm[i].cold as f64;
            cold * (self.cold_ms(i, frustum, all) + predictions[i].0) + predictions[i].0
        };
        (0..predictions.len())
            .filter(|&i| occluding(i) && predictions[i].1 && !self.warm[i].cold_frustum)
            .min_by(|&a, &b| cost(a).total_cmp(&cost(b)))
            .filter(|&b| cost(current) - cost(b) > self.params.margin * cost(current))
    }

    /// What a frame of occlusion method `i` from nothing costs over its
    /// steady frame: as measured ([`Chooser::observe`]), else, where its
    /// cold frames draw the whole frustum, at least `vfc`'s frame over its
    /// steady one, else 0 (not known, so not held against it).
    pub(super) fn cold_ms(&self, i: usize, frustum: f64, all: f64) -> f64 {
        if let Some(ms) = self.switch_ms[i][0] {
            return ms;
        }
        let vfc = self.with_load(Load::Frustum).map(|v| self.steady(v, frustum, all)).filter(|p| p.1);
        match vfc {
            Some((vfc, _)) if self.warm[i].cold_frustum => (vfc - self.steady(i, frustum, all).0).max(0.0),
            _ => 0.0,
        }
    }

    /// [`Chooser::predict`] without the cuts: its steady frame, the
    /// model's, bounded by a warm-up frame measured since its last steady
    /// frame in the same view (no camera cut between), and an estimate
    /// from before a camera cut by a frame since that drew what it would
    /// ([`Chooser::bound`]: inside boxes every candidate draws the whole
    /// scene, and `vfc`'s one frame there cost 33 ms; out of them `hzb`,
    /// drawing the whole frustum, 5).
    pub(super) fn steady(&self, i: usize, frustum: f64, all: f64) -> (f64, bool) {
        let (ms, measured) = self.model(i, frustum, all);
        let ms = match (self.bound_ms[i], self.measured[i]) {
            (Some((f, b)), Some(m)) if self.in_view(f) && !self.in_view(m) => ms.min(b),
            _ => ms,
        };
        match self.warm_ms[i] {
            Some((f, warm)) if (!measured || warm < ms) && self.in_view(f) => (warm, true),
            _ => (ms, measured),
        }
    }

    /// The cost model's steady frame of candidate `i`, and whether it was
    /// measured.
    pub(super) fn model(&self, i: usize, frustum: f64, all: f64) -> (f64, bool) {
        let k = self.triangle_ms();
        let f = &self.fits[i];
        if f.n == 0.0 {
            if let Some((_, b)) = self.bound_ms[i] {
                return (b, true);
            }
            let frustum_cost = match self.loads[i] {
                Load::All => self.with_load(Load::Frustum).map(|v| self.predict(v, frustum, all)).filter(|p| p.1),
                _ => None,
            };
            return match frustum_cost {
                Some((vfc, _)) => (vfc + k * (all - frustum).max(0.0), false),
                None => (0.0, false),
            };
        }
        (self.intercept(i, k) + k * self.load(i, frustum, all), true)
    }

    /// Candidate `i`'s `a_i` at `k` ms per triangle: what its frames cost
    /// drawing nothing (its own passes and the frame's), 0 before it was
    /// measured.
    pub(super) fn intercept(&self, i: usize, k: f64) -> f64 {
        let f = &self.fits[i];
        if f.n == 0.0 {
            return 0.0;
        }
        ((f.c - k * f.t) / f.n).max(0.0)
    }
}

/// The least prediction of a measured candidate (infinite before any
/// was measured).
pub(super) fn measured_best(predictions: &[(f64, bool)]) -> f64 {
    predictions.iter().filter(|p| p.1).map(|p| p.0).fold(f64::INFINITY, f64::min)
}

impl Chooser {
    /// Candidate `i`'s prediction is within [`Params::plausible`](super::Params::plausible)
    /// times the best measured one (every candidate is, before any was measured).
    pub(super) fn plausible(&self, i: usize, predictions: &[(f64, bool)]) -> bool {
        let best = measured_best(predictions);
        !best.is_finite() || predictions[i].0 <= self.params.plausible * best
    }
}
