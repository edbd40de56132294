//! The chooser's constants (`chooser.rs`).

/// The chooser's constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// A switch needs the best prediction below `1 - margin` times the current's.
    pub margin: f64,
    /// ... in this many decisions in a row.
    pub confirm: u32,
    /// Frames after a switch before the next.
    pub dwell: u64,
    /// Probes take at most one frame in this many (the calibration aside).
    pub probe_every: u64,
    /// A candidate is probed once its last measurement is this old.
    pub stale: u64,
    /// ... and its prediction within this factor of the best ...
    pub plausible: f64,
    /// ... or, where the estimate is of one frame (a spike, maybe), this one.
    pub plausible_once: f64,
    /// Any candidate not measured for this many frames is probed.
    pub forced: u64,
    /// Weight of an observation in a candidate's fit, per frame of its age.
    pub decay: f64,
    /// The frustum's triangles changing by this factor since an occlusion
    /// method was measured changes the view as a camera cut does.
    pub view_change: f64,
    /// Probes after changes of view take at most one frame in this many ...
    pub cut_probe_every: u64,
    /// ... and cost over the candidates they left at most this share of the time.
    pub probe_share: f64,
    /// A camera cut while the recent rate of cuts (decayed as the fits
    /// are) is below this starts each candidate's estimate anew.
    pub isolated_cuts: f64,
    /// Steady frames are measured one in this many ([`Chooser::times`](super::Chooser::times)).
    pub time_every: u64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            margin: 0.065,
            confirm: 3,
            dwell: 8,
            probe_every: 30,
            stale: 90,
            plausible: 1.3,
            plausible_once: 1.6,
            forced: 600,
            decay: 0.93,
            view_change: 3.0,
            cut_probe_every: 5,
            probe_share: 0.04,
            isolated_cuts: 0.2,
            time_every: 4,
        }
    }
}
