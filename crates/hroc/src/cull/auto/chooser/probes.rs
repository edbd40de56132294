//! Which candidate `chooser.rs` probes after its calibration, if any: the
//! candidate measured longest ago, once its estimate is stale, and an
//! estimate from another view (a camera cut, a frustum `view_change`
//! times fuller or emptier), as the probes' spend allows.

use super::predict::measured_best;
use super::{Chooser, Load};

impl Chooser {
    /// The candidate whose stale estimate frame `frame` probes, if one is
    /// due: at most one frame in `probe_every` since the first decision,
    /// the candidate measured longest ago, once that is `stale` frames
    /// (`probe_every` where its estimate is of one frame) and it is
    /// plausible (an estimate of one frame, a spike maybe, within
    /// `plausible_once` times the best), or once it is `forced` frames
    /// whatever it is predicted to cost. Candidates that never ran (not
    /// plausible) are not forced.
    pub(super) fn stale_probe(&self, frame: u64, current: usize, predictions: &[(f64, bool)]) -> Option<usize> {
        let p = self.params;
        if frame < self.last_probe.saturating_add(p.probe_every) {
            return None;
        }
        let since = frame - self.first_frame.unwrap_or(frame);
        let best = measured_best(predictions);
        let handed = |i: usize| self.source(frame, i).is_some();
        let budget = |i: usize| (self.probe_frames - self.calibration_frames + 1 + self.warm[i].frames(handed(i)) as u64).saturating_mul(p.probe_every) <= since;
        let age = |i: usize| self.measured[i].or(self.ran[i]).map(|m| frame.saturating_sub(m));
        let stale_at = |i: usize| if self.fits[i].n < 1.5 { p.probe_every } else { p.stale };
        let one_frame_plausible = |i: usize| self.fits[i].n < 1.5 && predictions[i].0 <= p.plausible_once * best;
        let due = |i: usize| age(i).is_some_and(|a| (a >= stale_at(i) && (self.plausible(i, predictions) || one_frame_plausible(i))) || a >= p.forced);
        (0..predictions.len()).filter(|&i| i != current && budget(i) && due(i)).max_by_key(|&i| age(i))
    }

    /// The candidate whose estimate from another view frame `frame`
    /// probes, if one is due. An occlusion method's share of the frustum
    /// was learnt on another view when it was measured before a camera
    /// cut, or with `view_change` times fewer or more triangles in the
    /// frustum (and a cut left any occlusion method cold). So while a
    /// stateless candidate runs, the occlusion method predicted cheapest
    /// whose estimate is from another view is probed, at most one frame in
    /// `cut_probe_every` and while the probes' excess stays within
    /// `probe_share` of the time (`spend.rs`).
    pub(super) fn view_probe(&self, frame: u64, current: usize, predictions: &[(f64, bool)], frustum: f64) -> Option<usize> {
        let p = self.params;
        if !self.spend.within(p.probe_share, 0.0) {
            return None;
        }
        let since = frame - self.first_frame.unwrap_or(frame);
        let occluding = |i: usize| self.loads[i] == Load::Occluded;
        let paced = |i: usize| (self.probe_frames - self.calibration_frames + 1 + self.warm[i].cold as u64).saturating_mul(p.cut_probe_every) <= since;
        let cut = |i: usize| self.measured[i].is_some_and(|m| !self.in_view(m));
        // Within a view (no cut since), a method whose frame drawing
        // nothing costs what the current one's whole frame does is not
        // cheaper with a fuller or emptier frustum.
        let k = self.triangle_ms();
        let reframed = |i: usize| {
            let (a, b) = (frustum.max(1.0), self.measured_frustum[i].max(1.0));
            a.max(b) > p.view_change * a.min(b) && self.intercept(i, k) < predictions[current].0
        };
        // After a change of the frustum, the probe's warm-up from nothing
        // (at what one cost before, else at twice its steady frame) fits
        // the probes' share too.
        let affordable = |i: usize| {
            let warm_ms = self.switch_ms[i][0].unwrap_or(predictions[i].0);
            self.spend.within(p.probe_share, self.warm[i].cold as f64 * warm_ms)
        };
        let due = (0..predictions.len()).filter(|&i| {
            let after = match (occluding(current), occluding(i)) {
                (false, true) => cut(i) || (reframed(i) && affordable(i)),
                // While an occlusion method runs, `vfc` or `noc` measured
                // before a cut: their estimates hold that view's own cost.
                (true, false) => cut(i) && self.plausible(i, predictions),
                // While `noc` runs, `vfc` measured before a cut: its frame
                // draws no more than `noc`'s (the eye inside boxes, where
                // `noc` was cheapest, draws the whole scene either way; out
                // of them `vfc` draws a part).
                (false, false) => cut(i) && self.loads[current] == Load::All && self.loads[i] == Load::Frustum,
                _ => false,
            };
            after && self.measured[i].is_some() && paced(i)
        });
        due.min_by(|&a, &b| predictions[a].0.total_cmp(&predictions[b].0))
    }
}
