//! What `auto`'s probes cost (`chooser.rs`): each probe frame's measured
//! cost over the prediction of the candidate it left, against the time of
//! every frame measured since the calibration. Probes after camera cuts
//! are allowed while that excess stays within a share of the time, so
//! they are frequent where they are cheap (a cold `hzb` frame costs what
//! `vfc`'s does and its pyramid) and rare where they are dear.

/// Frames a probe's measurement is awaited before it is given up.
const KEPT: u64 = 16;

/// The probes' excess cost and the time measured.
#[derive(Clone, Debug, Default)]
pub(super) struct Spend {
    /// Probe frames awaiting their measurement: the frame, and what the
    /// candidate left was predicted to cost then, ms.
    awaited: Vec<(u64, f64)>,
    /// Measured cost of probe frames over those predictions, ms.
    excess_ms: f64,
    /// Cost of every frame, ms: each measured frame stands for the
    /// frames since the last measured (steady frames are measured one in
    /// a few).
    total_ms: f64,
    last: Option<u64>,
}

impl Spend {
    /// Frame `frame` probes, where the candidate it left would cost `left_ms`.
    pub(super) fn probe(&mut self, frame: u64, left_ms: f64) {
        self.awaited.retain(|&(f, _)| frame <= f.saturating_add(KEPT));
        self.awaited.push((frame, left_ms));
    }

    /// Frame `frame` was measured at `cost_ms`.
    pub(super) fn measured(&mut self, frame: u64, cost_ms: f64) {
        let frames = self.last.map_or(1, |l| frame.saturating_sub(l).clamp(1, KEPT));
        self.last = Some(self.last.map_or(frame, |l| l.max(frame)));
        self.total_ms += cost_ms * frames as f64;
        if let Some(k) = self.awaited.iter().position(|&(f, _)| f == frame) {
            let (_, left_ms) = self.awaited.swap_remove(k);
            self.excess_ms += (cost_ms - left_ms).max(0.0);
        }
    }

    /// The probes' excess, and `next_ms` more, is within `share` of the
    /// time measured.
    pub(super) fn within(&self, share: f64, next_ms: f64) -> bool {
        self.excess_ms + next_ms <= share * self.total_ms
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_probe_costs_its_excess_over_the_candidate_left() {
        let mut s = Spend::default();
        for f in 0..10 {
            s.measured(f, 10.0);
        }
        // Frame 10 probes at 14 ms where the candidate left costs 10: 4 ms
        // of 122 (3.3 %); a cheaper probe frame costs nothing.
        s.probe(10, 10.0);
        s.probe(11, 10.0);
        s.measured(10, 14.0);
        s.measured(11, 8.0);
        assert!(s.within(0.04, 0.0) && !s.within(0.03, 0.0));
        // A probe expected to cost 2 ms more does not fit 4 %.
        assert!(!s.within(0.04, 2.0));
        // A frame measured after three unmeasured stands for four.
        let before = s.total_ms;
        s.measured(15, 10.0);
        assert_eq!(s.total_ms - before, 40.0);
        // A measurement lost is given up, not awaited for ever.
        s.probe(12, 10.0);
        s.probe(12 + KEPT + 1, 10.0);
        assert_eq!(s.awaited.len(), 1);
    }
}
