//! [`Culler::cull_views`]: a frame's views culled as a set.

use super::*;
use crate::error::Result;
use crate::frustum::ViewGeometry;
use crate::set_frustum::{SetFrustum, SetJob, SET_OBJECTS};

/// A view's part in its set's frame.
#[derive(Default)]
pub(super) struct SetPart<'s> {
    /// The set's pass packs the view's frustum list this frame, and has
    /// written its uniform; the pass writes its tally too.
    pub(super) packed: bool,
    /// The set's pass, recorded at the start of this view's frame (the
    /// first view the pass packs): its shape and time are this view's.
    pub(super) pass: Option<(&'s SetFrustum, &'s [SetJob])>,
}

impl Culler {
    /// Culls one frame of several views as a set: a camera, its light's
    /// cascades, a point light's six faces. Each view is culled as
    /// [`View::cull`] culls it and hands its own host its lists, in the
    /// order given, all recorded into `encoder`; but every view that culls
    /// by its frustum alone this frame (`vfc`, and HROC where its probes
    /// found that occlusion culls little,
    /// [`crate::MethodOptions::hroc_frustum_below`]) is tested and packed in one
    /// compute pass the set shares, one dispatch per such view, in place
    /// of a pass, a compaction and a tally of its own (`hroc set frustum`,
    /// counted in the first such view's [`View::stats`]). A view that
    /// starts over (a cut, a rebuilt culler) culls alone in that frame.
    ///
    /// Views are packed only where every view of the set keeps to the
    /// host's encoder (no [`crate::Method::submits_mid_frame`]), no object has
    /// [`ObjectFlags`] that split lists, and the culler has at most
    /// 131,072 object slots (a set's view is packed by one workgroup).
    /// Otherwise each view culls alone, as [`View::cull`] does.
    ///
    /// Every view is recorded, whatever another's result; the first error
    /// comes back (as from [`View::cull`]: a finding of validation after a
    /// frame recorded in full, which the host submits as usual).
    pub fn cull_views(&self, encoder: &mut wgpu::CommandEncoder, views: &mut [(&mut View, FrameInput, &mut dyn DrawHost)]) -> Result<()> {
        let mut packed = vec![false; views.len()];
        let mut jobs = Vec::new();
        let keeps_encoder = views.iter().all(|(v, _, _)| !v.method.submits_mid_frame());
        if keeps_encoder && self.objects.count <= SET_OBJECTS {
            for ((view, input, _), packed) in views.iter_mut().zip(packed.iter_mut()) {
                let Some(g) = view.set_ready(self, input) else { continue };
                let Some(list) = view.imp.plan_set(&self.gpu) else { continue };
                let uniform = view.uniform(self, &g);
                view.uploads.write(encoder, &view.frame, 0, bytemuck::bytes_of(&uniform));
                jobs.push(self.set_frustum.job(&self.gpu, &view.frame, &self.objects.bounds, &self.objects.commands, &list, view.tally.totals()));
                *packed = true;
            }
        }
        let first = packed.iter().position(|&p| p);
        let mut result = Ok(());
        for (k, (view, input, host)) in views.iter_mut().enumerate() {
            let set = SetPart { packed: packed[k], pass: (first == Some(k)).then_some((&self.set_frustum, &jobs[..])) };
            let recorded = view.record(self, encoder, input, &mut **host, None, None, set);
            if result.is_ok() {
                result = recorded;
            }
        }
        result
    }
}

impl View {
    /// This frame's geometry, where the view's next frame can be packed by
    /// a set: it neither starts over (a cut, a rebuilt culler, a failed
    /// frame) nor fails before its method's frame (the checks of
    /// [`View::cull`]), and no object's flags split its lists.
    pub(super) fn set_ready(&self, culler: &Culler, input: &FrameInput) -> Option<ViewGeometry> {
        let regrown = self.slots != culler.objects.count;
        let rebuilt = self.generation != culler.generation && self.method.keeps_tree();
        let refused = (culler.moves > 0 && !self.method.takes_motion()) || (!self.method.takes_dynamic() && culler.objects.alone > 0);
        let split = ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER | ObjectFlags::CUTOUT;
        let flagged = self.split.is_some() || culler.objects.flags.iter().any(|f| f.bits() & split.bits() != 0);
        if regrown || rebuilt || refused || flagged || self.interrupted || input.cut {
            return None;
        }
        let g = input.view.geometry().ok().filter(|g| g.depth == self.targets.depth)?;
        (!self.turned(culler, &g)).then_some(g)
    }
}
