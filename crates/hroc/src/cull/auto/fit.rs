//! The decayed sums a candidate's cost model is fitted from (`chooser.rs`):
//! least squares of cost on triangles drawn, and the share of the
//! frustum drawn, with older frames weighing less.

use super::Observation;

/// Decayed sums of one candidate's observations (for `a_m` and `k`).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Fit {
    /// Weights (observations, decayed), and the weighted sums of
    /// triangles, cost, triangles², triangles × cost and cost².
    pub(super) n: f64,
    pub(super) t: f64,
    pub(super) c: f64,
    pub(super) tt: f64,
    pub(super) tc: f64,
    pub(super) cc: f64,
    /// Share of the frustum's triangles drawn (decayed mean).
    pub(super) share: f64,
    /// The frame of the last observation.
    pub(super) frame: u64,
}

impl Fit {
    /// Adds `o`, the older sums weighted by `decay` per frame between them.
    pub(super) fn add(&mut self, o: &Observation, decay: f64) {
        let d = if self.n == 0.0 { 0.0 } else { decay.powf(o.frame.saturating_sub(self.frame) as f64) };
        self.frame = self.frame.max(o.frame);
        let share = if o.frustum_triangles > 0.0 { (o.triangles / o.frustum_triangles).min(1.0) } else { 1.0 };
        self.share = (self.share * d * self.n + share) / (d * self.n + 1.0);
        self.n = self.n * d + 1.0;
        self.t = self.t * d + o.triangles;
        self.c = self.c * d + o.cost_ms;
        self.tt = self.tt * d + o.triangles * o.triangles;
        self.tc = self.tc * d + o.triangles * o.cost_ms;
        self.cc = self.cc * d + o.cost_ms * o.cost_ms;
    }
}
