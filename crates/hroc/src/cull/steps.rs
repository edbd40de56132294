//! The stepwise frame's cuts ([`StepCuts`]): a method records its frame
//! as always, and where it would hand the host a list, the frame ends the
//! command buffer the engine submits before that pass and goes on in the
//! next one, which the engine submits after it.
//!
//! A list of the early pass (occluders, or a single list's) or of the late
//! pass (occludees) leaves a cut pending; the next command the method
//! records (its next stage, a pass that reads the depth the list left)
//! takes it. The lists of one pass may so come one after another (a list
//! and its stall-free overflow, the flag split's), and what a pass's lists
//! need before they are drawn (the emulated count's tail, the split) stays
//! before the cut. Never-culled objects come first and non-occluders last,
//! and cut nothing.

use super::Frame;
use crate::contract::Phase;
use crate::error::{Error, Result};

/// The two points of a stepwise frame where the engine draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cut {
    /// The engine's early pass (occluders).
    Early,
    /// The engine's late pass (occludees).
    Late,
}

/// A stepwise frame's command buffers so far, and its pending cut.
#[derive(Default)]
pub(crate) struct StepCuts {
    /// The command buffers before each cut taken, in order.
    pub done: Vec<(Cut, wgpu::CommandBuffer)>,
    pending: Option<Cut>,
    /// A list of the late pass was handed.
    pub late: bool,
    /// The first list that does not fit two passes.
    pub error: Option<Error>,
}

impl StepCuts {
    fn taken(&self, cut: Cut) -> bool {
        self.done.iter().any(|(c, _)| *c == cut)
    }
}

impl Frame<'_> {
    /// True when the frame is recorded for an engine that draws it itself
    /// ([`crate::View::steps`]): methods then leave out what would need
    /// a third pass of the engine's (HROC's refill of V).
    pub fn stepwise(&self) -> bool {
        self.steps.is_some()
    }

    /// A list of `phase` is handed: in a stepwise frame, cuts before it
    /// when another pass's cut is pending, and leaves its own pending.
    pub(crate) fn step_list(&mut self, phase: Phase) {
        let Some(steps) = self.steps.as_deref_mut() else { return };
        let cut = match phase {
            Phase::Always | Phase::NonOccluders => return,
            Phase::Visible | Phase::Occluders => Cut::Early,
            Phase::Occludees => Cut::Late,
            Phase::Interleaved => {
                steps.error.get_or_insert(Error::InvalidScene(format!("{} draws between its queries and cannot run stepwise", self.culled_by)));
                return;
            }
        };
        let late = matches!(steps.pending, Some(Cut::Late)) || steps.taken(Cut::Late);
        let again = steps.taken(cut);
        if (cut == Cut::Early && late) || again {
            let what = match cut {
                Cut::Early => "its occluders after the occlusion test, or in rounds (HROC's occluder rounds)",
                Cut::Late => "its occludees in rounds (MethodOptions::hroc_rounds above 1)",
            };
            steps.error.get_or_insert(Error::InvalidScene(format!("{} draws {what}: a stepwise frame has one early and one late pass", self.culled_by)));
            return;
        }
        steps.late |= cut == Cut::Late;
        if steps.pending.is_some_and(|p| p != cut) {
            self.take_cut();
        }
        if let Some(steps) = self.steps.as_deref_mut() {
            steps.pending = Some(cut);
        }
    }

    /// Takes the pending cut, if any: the commands so far become the
    /// command buffer the engine submits before that pass.
    pub(crate) fn take_cut(&mut self) {
        let Some(cut) = self.steps.as_deref_mut().and_then(|s| s.pending.take()) else { return };
        let enc = self.next_encoder("hroc step");
        if let Some(steps) = self.steps.as_deref_mut() {
            steps.done.push((cut, enc.finish()));
        }
    }
}

/// Checks that `method`, culled with marks of `marks`, can run stepwise.
pub(crate) fn check(method: super::Method, marks: crate::capabilities::Marks) -> Result<()> {
    if method.submits_mid_frame() {
        return Err(Error::InvalidScene(format!("{method} submits mid-frame (counter read-back) and cannot run stepwise: use hroc, hroc-sf, hzb or vfc")));
    }
    if method.reads_marks() && marks == crate::capabilities::Marks::EarlyZ {
        return Err(Error::InvalidScene(format!(
            "{method} reads which objects the host drew, and in a stepwise frame the host's shaders cannot mark them: create the culler with Marks::Boxes (or Marks::Ids and an ID target) in CullerDesc::capabilities"
        )));
    }
    Ok(())
}
