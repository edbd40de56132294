//! What the chooser takes (each candidate's load and warm-up, measured
//! frames) and what it gives (the decision for a frame).

/// What a candidate draws, for predicting frames it does not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Load {
    /// Every object (`noc`).
    All,
    /// The objects in the frustum (`vfc`).
    Frustum,
    /// A share of the frustum's objects, learnt when it runs (`hzb`, `hroc`).
    Occluded,
}

/// Frames a candidate takes after taking over to reach its steady cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WarmUp {
    /// Starting from nothing (as after a cut).
    pub cold: u32,
    /// Starting from the visible set the candidate before it handed over.
    pub handed: u32,
    /// Its frames from nothing draw the whole frustum (an empty visible
    /// set and depth pyramid), so each costs at least `vfc`'s frame.
    pub cold_frustum: bool,
}

impl WarmUp {
    /// A candidate without state between frames (`noc`, `vfc`).
    pub const NONE: WarmUp = WarmUp { cold: 0, handed: 0, cold_frustum: false };

    pub(super) fn frames(self, handed: bool) -> u32 {
        if handed {
            self.handed
        } else {
            self.cold
        }
    }
}

/// One measured frame of a candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// Which candidate ran.
    pub candidate: usize,
    /// The frame's number.
    pub frame: u64,
    /// Its cost, ms: the GPU time between its first and last pass and the
    /// CPU time of recording it (or the CPU clock's frame period).
    pub cost_ms: f64,
    /// Triangles it drew.
    pub triangles: f64,
    /// Triangles in the frustum that frame.
    pub frustum_triangles: f64,
    /// A warm-up frame after the candidate took over: it prices a switch,
    /// not the candidate's steady cost.
    pub warm_up: bool,
    /// ... a warm-up that started from a visible set handed over.
    pub handed: bool,
}

/// What to run this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decision {
    /// The candidate.
    pub candidate: usize,
    /// It takes over this frame from another candidate (or starts).
    pub fresh: bool,
    /// ... from the visible set of this candidate's last frame (itself:
    /// its own set, kept while another ran), else as after a cut.
    pub from: Option<usize>,
    /// A probe, not the choice.
    pub probe: bool,
    /// The frame counts in the candidate's estimate: false in its warm-up
    /// frames after taking over.
    pub measured: bool,
    /// The candidate's first frame ever (lazy set-up in drivers).
    pub first: bool,
}
