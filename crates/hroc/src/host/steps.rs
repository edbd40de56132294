//! The frame of an engine that draws it itself: [`View::steps`] and
//! [`View::visibility`].

use super::*;
use crate::cull::steps::{check, Cut, StepCuts};
use crate::error::Result;
use crate::visibility::Visibility;

/// One frame of a view culled for an engine that runs its own passes and
/// builds its own draws ([`View::steps`]): three command buffers, which
/// the engine submits in this order around its two depth passes (or adds
/// to its own list of command buffers, as Bevy's `RenderContext` does).
/// Between them the engine draws what [`View::visibility`] says.
pub struct Steps {
    /// Before the engine's early pass: what decides it (the frame's
    /// stamps, last frame's visible set packed, a seed after a cut).
    pub begin: wgpu::CommandBuffer,
    /// After the early pass, before the late pass: the occlusion test
    /// against the depth the early pass left (marks, Hi-Z or HROC's test).
    pub occluders_drawn: wgpu::CommandBuffer,
    /// After the late pass: what the next frame starts from (HROC's next
    /// occluders), and the non-occluders' stamps, which the engine's
    /// blended pass reads.
    pub occludees_drawn: wgpu::CommandBuffer,
    /// This frame's late pass draws objects: false where the method
    /// handed no occludees (a frame culled by the frustum alone, `vfc`,
    /// HROC's frames of the frustum where occlusion does not pay), and no
    /// object is stamped for that pass; the engine may then leave it out.
    pub late: bool,
}

/// Takes the host's draws of a stepwise frame: it has none.
struct EngineDraws;

impl DrawHost for EngineDraws {
    fn draw(&mut self, _: &mut wgpu::CommandEncoder, _: &Draw) {}
}

impl View {
    /// The view's visibility as data: [`crate::device::VISIBILITY_HEADER`] `u32`s of
    /// this frame's stamp of each phase, then one `u32` per object slot, the
    /// stamp of the phase this frame draws it in (any other value: not
    /// drawn). Read it in a shader with [`device::visibility_wgsl`], to
    /// build per-material indirect draws in the host's own compute pass.
    /// From the first call on, every frame stamps the objects of every list
    /// it hands, in the host's encoder, right before the list: a phase's
    /// stamps are final when it is the host's turn to draw it. The buffer
    /// changes when the culler's slots grow: take it each frame.
    ///
    /// [`device::visibility_wgsl`]: crate::device::visibility_wgsl
    pub fn visibility(&mut self, culler: &Culler) -> &wgpu::Buffer {
        &self.visibility.get_or_insert_with(|| Visibility::new(&culler.gpu, culler.objects.count)).buffer
    }

    /// Plans the view's next stepwise frame before the engine prepares
    /// its passes, and says whether that frame's late pass draws: false
    /// where it culls by the frustum alone (`vfc`; HROC where its
    /// measurements found occlusion not paying in the view), and the
    /// engine may then prepare and draw the view that frame as one without
    /// occlusion culling (every object its own frustum culling keeps, in
    /// its early pass), while [`View::steps`] still records the frame,
    /// which keeps the view's measurements and next occluders. True where
    /// it cannot tell: a cut, a culler regrown or rebuilt, a method that
    /// tests after the early pass. The next [`View::steps`] keeps to the
    /// plan unless the view starts over first, and says what it drew in
    /// [`Steps::late`]. Any plan is conservative: a frame of the frustum
    /// draws every object the view shows.
    pub fn plans_late(&mut self, culler: &Culler, input: &FrameInput) -> bool {
        let frustum = self.set_ready(culler, input).is_some() && self.imp.plan_set(&culler.gpu).is_some();
        self.wants_steps = !frustum || self.imp.planned_frame_needed();
        !frustum
    }

    /// After [`View::plans_late`] said false: whether the view needs that
    /// frame recorded at all. Where not, an engine that culls the frame by
    /// its own frustum culling, and reads nothing of hroc's for it, may
    /// leave out [`View::steps`]: the view only counts the frame toward its
    /// next measurement (HROC records the frame before one, whose depth
    /// makes the measurement's occluders; `vfc` needs none). True until
    /// the next plan.
    pub fn wants_steps(&self) -> bool {
        self.wants_steps
    }

    /// Culls one frame for an engine that draws it itself: it records the
    /// view's culling as [`View::cull`] does, and in place of handing draw
    /// lists, stamps [`View::visibility`] and ends a command buffer at each
    /// point where the engine draws ([`Steps`]). The engine clears its
    /// targets before its early pass (the crate docs' clearing rule), then:
    ///
    /// 1. submits [`Steps::begin`], and draws its **early pass**: the
    ///    objects `hroc_early` says (never culled, a single list's, the
    ///    occluders), writing depth (and IDs where the view has an ID
    ///    target) as the contract's occluding phases do;
    /// 2. submits [`Steps::occluders_drawn`], and draws its **late pass**:
    ///    the objects `hroc_late` says, the same way;
    /// 3. submits [`Steps::occludees_drawn`]; its blended objects are then
    ///    those stamped `HROC_NON_OCCLUDERS`.
    ///
    /// Which steps each method fills: `noc`, `vfc`, `woc` and `ref` decide
    /// everything in `begin` (the other two hold only bookkeeping); `hzb`
    /// tests in `occluders_drawn`; `roc`, `roc-all` and HROC (`hroc`,
    /// `hroc-sf`, `hroc-na`, `hroc-of`) mark and test in `occluders_drawn`
    /// and find the next frame's occluders in `occludees_drawn`; `auto`
    /// runs its choice's steps. Methods that submit mid-frame (`hroc-cr`,
    /// `ioc`, the query methods) cannot run stepwise, nor HROC with
    /// occludee or occluder rounds (a third pass); HROC leaves out its
    /// refill of V's holes, which would need one. The engine's shaders
    /// cannot mark: methods that read marks need a culler with
    /// [`device::Marks::Boxes`], or [`device::Marks::Ids`] and an ID
    /// target. Validation ([`CullerDesc::validation`]) checks the
    /// engine's passes against what [`View::visibility`] let them draw
    /// (their depth after each pass; without IDs, every drawn sample
    /// against the boxes of the objects stamped visible); its findings
    /// come from [`View::validation`], never from this call.
    ///
    /// Errors as [`View::cull`] does, and when the method cannot run
    /// stepwise; the view's next frame then starts over as after a cut.
    ///
    /// [`device::Marks::Boxes`]: crate::device::Marks::Boxes
    /// [`device::Marks::Ids`]: crate::device::Marks::Ids
    pub fn steps(&mut self, culler: &Culler, input: &FrameInput) -> Result<Steps> {
        check(self.method, culler.caps.marks)?;
        self.wants_steps = true;
        self.visibility(culler);
        let mut cuts = StepCuts::default();
        let mut encoder = culler.gpu.encoder("hroc steps");
        let recorded = self.record(culler, &mut encoder, input, &mut EngineDraws, None, Some(&mut cuts), super::set::SetPart::default());
        if let Some(e) = cuts.error.take() {
            self.interrupted = true;
            return Err(e);
        }
        recorded?;
        let mut early = None;
        let mut late = None;
        for (cut, buffer) in cuts.done {
            match cut {
                Cut::Early => early = Some(buffer),
                Cut::Late => late = Some(buffer),
            }
        }
        let empty = || culler.gpu.encoder("hroc step").finish();
        let last = encoder.finish();
        // (A late list that ends the frame leaves its cut pending.)
        let draws_late = cuts.late;
        // The buffers in order; a pass that had no cut gets an empty one.
        let (begin, occluders_drawn, occludees_drawn) = match (early, late) {
            (Some(e), Some(l)) => (e, l, last),
            (Some(e), None) => (e, last, empty()),
            (None, Some(l)) => (l, empty(), last),
            (None, None) => (last, empty(), empty()),
        };
        Ok(Steps { begin, occluders_drawn, occludees_drawn, late: draws_late })
    }
}
