//! HROC's frame sized to what it saves in each view, measured in the view
//! without a stall. One frame in [`PROBE_EVERY`] is a probe: a full HROC
//! frame that also counts, on the GPU, what two of its parts change, read
//! back without waiting; until the next probe's counts arrive, the view
//! runs only the parts the last counts found paying.
//!
//! - **Occlusion where it culls.** The probe counts the objects in the
//!   view's frustum and those of them the frame culls by occlusion (in
//!   neither V nor U, and their triangles; `measure` in
//!   `hroc_yield.wgsl`). Where occlusion culled less than
//!   [`MethodOptions::hroc_frustum_below`](crate::MethodOptions) of the
//!   frustum's objects, or fewer triangles than
//!   [`MethodOptions::hroc_frustum_triangles`](crate::MethodOptions) per
//!   pixel of the view while less than half of the frustum's objects (a
//!   light looking down on roofs: a few per cent, 50 objects in 512²),
//!   or, in a view drawn depth only (with that bar), where the objects it
//!   culled hold no more triangles than the boxes its test drew (12 for
//!   each object of the frustum not in V: on `houses`, whose objects are
//!   all boxes, occlusion culls most of a far cascade and saves nothing
//!   the test did not cost), the view's frames cull by the frustum alone: one
//!   compute pass, one list (`frustum`; in a set of views, one dispatch
//!   of the set's pass, `crate::Culler::cull_views`). Frustum culling is
//!   conservative, and the next probe runs HROC from the last V it had
//!   (V only orders a frame). A view drawn depth only over objects that
//!   hold no more triangles than their boxes culls by the frustum without
//!   probing: there the rule above cannot hold (`Gate::objects`).
//! - **Occluder filtering where it changes the result.** OF (step 5 with
//!   the ID target, Lee et al. 2021 §4.2) makes the next V the objects
//!   that own a pixel, where the merge makes it O ∪ D: it pays where many
//!   drawn objects own no pixel, and costs a pass over every pixel where
//!   nearly all of them own one. The probe's filter also counts the
//!   objects it keeps and those O ∪ D holds (`filter_occluders` with
//!   `MEASURE`, `hroc_next.wgsl`); the view filters only if the last probe
//!   kept at most [`FILTER_PAYS_BELOW`] of O ∪ D, else merges. Either next
//!   V is conservative. Only where D is marked (early-Z marks), which the
//!   merge needs.
//!
//! - **Probes where they can change the plan.** A view whose probe found
//!   occlusion not paying probes next [`PROBE_LEAST`] frames later (a view
//!   drawn depth only, twice as late after each further such probe, up
//!   to [`PROBE_MOST`]): a light over roofs measures little and the same
//!   from frame to frame, and each probe is HROC's whole frame. A probe
//!   that finds occlusion paying brings back one in [`PROBE_EVERY`].
//!   Probes only size the frame, so any rate is conservative.
//! - **Probes from a fresh V.** With marks from boxes, the frame of the
//!   frustum before a probe marks the boxes of its list against the depth
//!   it left, and they are the probe's V (`Hroc::refresh_occluders`):
//!   the probe then tests what V leaves, as a steady frame does, not the
//!   whole view from a V up to [`PROBE_LEAST`] frames old.
//!
//! A camera cut runs the whole frame and probes at once: the last counts
//! describe another view. In a view where occlusion did not pay, the cut
//! frame culls by the frustum and refreshes V, and the next frame probes;
//! in such a view drawn depth only, frames cull by the frustum until its
//! next probe.

use super::{Hroc, Launch, MarkTarget, Seed, Step};
use crate::contract::{DrawList, Phase};
use crate::cull::{CullMethod, Frame, Stage};
use crate::gpu::shape::EncoderShape;
use crate::gpu::{dispatch_size, Gpu, Readback};
use crate::layout::DrawCommand;
use std::any::Any;

/// A probe every this many frames of the view, where occlusion pays.
pub const PROBE_EVERY: u32 = 8;

/// A probe every this many frames of a view where it does not.
pub const PROBE_LEAST: u32 = 32;

/// ... and in a view drawn depth only (a light's, with a triangle bar),
/// twice as many after each further probe that finds it not paying, up to
/// this many: whether occlusion pays there is a property of the light and
/// the scene, which a camera's moves change little, and on lavapipe a
/// probe of a 1024² shadow map costs several steady frames.
pub const PROBE_MOST: u32 = 128;

/// Filtering pays when it keeps at most this share of O ∪ D.
pub const FILTER_PAYS_BELOW: f64 = 0.9;

/// Staging buffers in flight.
const RING: usize = 2;

/// Bytes of the tally (u32 each): objects the filter keeps, objects of
/// O ∪ D, objects in the frustum, of those culled by occlusion, their
/// triangles (at least 64 each, for their draws), the frustum's objects
/// the batch test takes (not in V), and the culled objects' own triangles.
pub(super) const TALLY: u64 = 28;

/// Counts in the tally.
const COUNTS: usize = (TALLY / 4) as usize;

/// Triangles of the box the batch test draws for an object.
const BOX_TRIANGLES: f64 = 12.0;

/// Where occlusion pays: it culls at least this share of the frustum's
/// objects, and at least this many triangles.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pays {
    pub(super) share: f32,
    pub(super) triangles: f64,
}

/// What step 5 runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Next {
    /// The filter, counting what it changes.
    Probe,
    /// The filter.
    Filter,
    /// The merge: next V = O ∪ D.
    Merge,
}

/// What a frame of the view runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Plan {
    /// The frame counts what occlusion culls (and with the filter gate,
    /// what the filter changes), read back without a stall.
    pub(super) probe: bool,
    /// The frame culls by occlusion; else by the frustum alone.
    pub(super) occlusion: bool,
    /// Step 5.
    pub(super) next: Next,
    /// A frame of the frustum alone before a probe: V becomes the
    /// frustum's objects the frame's depth shows ([`Hroc::refresh_occluders`]).
    pub(super) refresh: bool,
}

impl Plan {
    /// The whole frame, as without a gate: `of` filters.
    pub(super) fn whole(of: bool) -> Plan {
        Plan { probe: false, occlusion: true, next: if of { Next::Filter } else { Next::Merge }, refresh: false }
    }
}

/// One view's measurements of what its frame's parts change.
pub(super) struct Gate {
    /// `[kept, merged, inside, culled, triangles, tested, own]`, counted by the probes.
    pub(super) tally: wgpu::Buffer,
    ring: Vec<(wgpu::Buffer, Readback<()>)>,
    /// The view filters with OF where it pays (else `of` alone decides).
    filter: bool,
    /// The variant filters (OF).
    of: bool,
    /// Where occlusion pays.
    pays: Pays,
    filter_pays: bool,
    occlusion_pays: bool,
    /// Frames since the last probe, this one counted.
    since_probe: u32,
    /// Frames from one probe to the next: [`PROBE_EVERY`], or
    /// [`PROBE_LEAST`] after a probe that found occlusion not paying.
    interval: u32,
    /// The last counts that arrived.
    pub(super) last: Option<[u32; COUNTS]>,
    /// No object holds more triangles than the box the test draws for it,
    /// as of the objects' commands of this version ([`Gate::objects`]).
    boxes_only: Option<(u64, bool)>,
}

impl Gate {
    /// A gate for a view of variant `of`: `filter` where D is marked,
    /// occlusion culling where it `pays` (a share of 0: always).
    pub(super) fn new(gpu: &Gpu, of: bool, filter: bool, pays: Pays) -> Self {
        use wgpu::BufferUsages as U;
        Gate {
            tally: gpu.buffer("hroc gate tally", TALLY, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            ring: (0..RING).map(|_| (gpu.buffer("hroc gate tally staging", TALLY, U::MAP_READ | U::COPY_DST), Readback::Free)).collect(),
            filter: of && filter,
            of,
            pays: Pays { share: pays.share.max(0.0), triangles: pays.triangles.max(0.0) },
            filter_pays: true,
            occlusion_pays: true,
            since_probe: PROBE_LEAST,
            interval: PROBE_EVERY,
            last: None,
            boxes_only: None,
        }
    }

    /// Learns the objects' triangles from their commands (of `version`,
    /// read again only when it changes). In a view drawn depth only where
    /// no object holds more triangles than the box the test draws for it,
    /// occlusion cannot pay by the measurement's own rule (the culled
    /// objects' triangles are then at most 12 for each object tested), so
    /// the view culls by the frustum and never probes, until an object
    /// with more triangles comes.
    pub(super) fn objects(&mut self, version: u64, commands: &[DrawCommand]) {
        if self.boxes_only.is_none_or(|(v, _)| v != version) {
            let boxes = commands.iter().all(|c| f64::from(c.index_count / 3) <= BOX_TRIANGLES);
            self.boxes_only = Some((version, boxes));
        }
    }

    /// Occlusion cannot pay in this view: drawn depth only, over objects
    /// no richer than their boxes ([`Gate::objects`]).
    fn cannot_pay(&self) -> bool {
        self.depth_only() && self.boxes_only.is_some_and(|(_, b)| b)
    }

    /// Takes the counts that arrived (polling, never waiting) and plans
    /// this frame; returns the bytes read back too.
    pub(super) fn plan(&mut self, gpu: &Gpu) -> (Plan, u64) {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let mut bytes = 0;
        let depth_only = self.depth_only();
        for (buf, slot) in self.ring.iter_mut() {
            let Some(c) = slot.take(buf, |(), v| std::array::from_fn::<u32, COUNTS, _>(|k| bytemuck::pod_read_unaligned(&v[k * 4..k * 4 + 4]))) else { continue };
            bytes += TALLY;
            self.last = Some(c);
            let [kept, merged, inside, culled, triangles, tested, own] = c.map(f64::from);
            if self.filter {
                self.filter_pays = merged == 0.0 || kept <= FILTER_PAYS_BELOW * merged;
            }
            let share = self.pays.share as f64;
            // (Culling most of the frustum's objects pays whatever they
            // cost; but in a view drawn depth only, not where the test's
            // boxes hold as many triangles as the objects it culls.)
            let saves = (triangles >= self.pays.triangles || culled >= 0.5 * inside) && (!depth_only || own > BOX_TRIANGLES * tested);
            self.occlusion_pays = inside == 0.0 || share == 0.0 || (culled >= share * inside && saves);
            self.interval = match (self.occlusion_pays, depth_only) {
                (true, _) => PROBE_EVERY,
                (false, true) if self.interval >= PROBE_LEAST => (2 * self.interval).min(PROBE_MOST),
                (false, _) => PROBE_LEAST,
            };
        }
        let cannot_pay = self.cannot_pay();
        if cannot_pay {
            self.occlusion_pays = false;
        }
        let probe = !cannot_pay && self.since_probe >= self.interval && self.ring.iter().any(|(_, s)| s.is_free());
        // (Counting this frame: the next probe `interval` frames after it.)
        self.since_probe = if probe { 1 } else { self.since_probe + 1 };
        let next = match (self.of, self.filter) {
            (false, _) => Next::Merge,
            (true, false) => Next::Filter,
            (true, true) if probe => Next::Probe,
            (true, true) if self.filter_pays => Next::Filter,
            (true, true) => Next::Merge,
        };
        let occlusion = probe || self.occlusion_pays;
        // The next frame probes, by the counts known now.
        let refresh = !occlusion && !cannot_pay && self.since_probe >= self.interval;
        (Plan { probe, occlusion, next, refresh }, bytes)
    }

    /// The view is drawn depth only: it has a triangle bar
    /// ([`MethodOptions::hroc_frustum_triangles`](crate::MethodOptions)).
    fn depth_only(&self) -> bool {
        self.pays.triangles > 0.0
    }

    /// Before a probe's counts: the tally starts at zero.
    pub(super) fn begin_probe(&self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.tally, 0, None);
    }

    /// After a probe's last count: the tally goes to a free staging
    /// buffer, mapped once `enc` is submitted ([`Gate::plan`] probes only
    /// with one free).
    pub(super) fn end_probe(&mut self, enc: &mut wgpu::CommandEncoder) {
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| s.is_free()) {
            enc.counted_copy(&self.tally, 0, buf, 0, Some(TALLY));
            *slot = Readback::request(enc, buf, ());
        }
    }

    /// A camera cut: the whole frame, and a probe at once; but in a view
    /// that `refreshes` V ([`Hroc::refresh_occluders`]) and where
    /// occlusion did not pay, a frame of the frustum that refreshes V, and
    /// a probe the next frame (a cut frame seeds V and tests the whole
    /// view, the dearest of HROC's frames); and in a view drawn depth only
    /// where it did not pay, the frustum until its next probe: a light's
    /// cascade refitted to a camera that cuts is cut too, and whether
    /// occlusion pays there is the light's and the scene's ([`PROBE_MOST`]).
    pub(super) fn reset(&mut self, refreshes: bool) {
        self.filter_pays = true;
        if self.depth_only() && !self.occlusion_pays {
            return;
        }
        if self.occlusion_pays || !refreshes {
            self.occlusion_pays = true;
            // (Past any interval: counts of an earlier probe, arriving at
            // this frame's plan, may lengthen it.)
            self.since_probe = PROBE_MOST;
            self.interval = PROBE_EVERY;
        } else {
            self.since_probe = self.interval - 1;
        }
    }
}

/// After [`crate::View::resize`] to targets of the same shape: `fresh`
/// takes `old`'s measurements and the plan made ahead for this frame,
/// where both are HROC views with a gate. They describe the view (its
/// camera and the scene), not its texture: a point light's faces, which
/// an engine moves to other layers or textures as its lights come and
/// go, keep culling by the frustum where occlusion did not pay, rather
/// than measuring anew, and keep to the plan the engine was told
/// (`View::plans_late`).
pub(crate) fn carry_gate(fresh: &mut dyn CullMethod, old: &mut dyn CullMethod) {
    let (Some(fresh), Some(old)) = ((fresh as &mut dyn Any).downcast_mut::<Hroc>(), (old as &mut dyn Any).downcast_mut::<Hroc>()) else { return };
    // (The fresh view's passes write its own tally: only what was
    // learned moves, and the old view's counts in flight are dropped.)
    if let (Some(g), Some(o)) = (fresh.gate.as_mut(), old.gate.as_ref()) {
        (g.filter_pays, g.occlusion_pays, g.since_probe, g.interval, g.last, g.boxes_only) = (o.filter_pays, o.occlusion_pays, o.since_probe, o.interval, o.last, o.boxes_only);
        (fresh.plan, fresh.planned) = (old.plan, old.planned.take());
    }
}

impl Hroc {
    /// A frame of frustum culling alone, where the view's gate found that
    /// occlusion culls little ([`Gate`]): every object whose box meets the
    /// frustum (`frustum`, the gate's pass), packed in object order into
    /// U's list, drawn as one list. V stays as the last HROC frame left it,
    /// for the next probe.
    pub(super) fn frustum_frame(&self, f: &mut Frame, frustum: &Step) {
        f.stage(Stage::FrustumCull);
        let (x, y) = dispatch_size(self.n, 256);
        self.compute(f, "hroc frustum", &[(frustum, Launch::Grid(x, y))], Some(&self.u_job), None);
        f.stage(Stage::Draw);
        f.draw(Phase::Visible, &self.frustum_list(), None);
    }

    /// Where the plan says ([`Plan::refresh`]), in the frame before a
    /// probe of a view that culls by its frustum: V becomes the objects of
    /// the frustum's list whose boxes are at or in front of the depth the
    /// frame left (box marks against it, then step 5's merge). The probe
    /// is then an HROC frame from a fresh V, not from the V of the view's
    /// last HROC frame, up to [`PROBE_LEAST`] frames old, which leaves
    /// most of the view to the test: on lavapipe, a probe of a light's
    /// 1024² cascade cost 4 × its steady HROC frame.
    /// Any V is conservative (V only orders a frame). Only where the view
    /// marks from boxes ([`crate::capabilities::Marks::Boxes`], with the
    /// marks at the end of the frame); elsewhere the probe starts from the
    /// last V.
    pub(super) fn refresh_occluders(&mut self, f: &mut Frame) {
        let Some((boxes, drawn)) = self.refreshes().filter(|_| self.plan.refresh).map(|(b, d)| (b.clone(), d.clone())) else { return };
        // (A cut's seed would replace the V this writes.)
        self.seed_next = false;
        f.stage(Stage::Filtering);
        f.encoder().counted_clear(&drawn, 0, None);
        boxes.record(f, &[&self.frustum_list()], &drawn);
        self.compute(f, "hroc next occluders", &[(&self.merge, self.merge_launch())], None, None);
    }

    /// Cells of the seed's grid whose coverage step 5 records (for the
    /// refill; 1 without it).
    pub(super) fn covered_cells(&self) -> u32 {
        if self.seed_mode == Seed::Cuts {
            self.grid.0 * self.grid.1
        } else {
            1
        }
    }

    /// Step 5's merge: a thread per object, and per covered cell.
    pub(super) fn merge_launch(&self) -> Launch<'_> {
        let (x, y) = dispatch_size(self.n.max(self.covered_cells()), 256);
        Launch::Grid(x, y)
    }

    /// The box marks and their buffer, where frames of the frustum can
    /// refresh V: marks from boxes at the end of the frame.
    pub(super) fn refreshes(&self) -> Option<(&std::sync::Arc<crate::cull::BoxMarks>, &wgpu::Buffer)> {
        match (&self.marks_d, self.marks_at_end) {
            (MarkTarget::Boxes(boxes, drawn), true) => Some((boxes, drawn)),
            _ => None,
        }
    }

    /// Plans the frame: the plan made before it for a set of views, or now.
    pub(super) fn plan_frame(&mut self, f: &mut Frame) {
        // (A plan made before the frame knew the objects of the last.)
        if let Some(g) = self.gate.as_mut() {
            g.objects(f.objects.commands_version, &f.objects.cpu_commands);
        }
        self.plan = match (self.planned.take(), self.gate.as_mut()) {
            (Some(bytes), _) => {
                f.count_async_read(bytes);
                self.plan
            }
            (None, Some(g)) => {
                let (plan, bytes) = g.plan(f.gpu);
                f.count_async_read(bytes);
                plan
            }
            (None, None) => Plan::whole(self.variant.of),
        };
    }

    /// Plans the next frame before it is recorded, for a set of views
    /// (`CullMethod::plan_set`): U's list where it culls by the frustum alone.
    pub(super) fn plan_early(&mut self, gpu: &Gpu) -> Option<DrawList> {
        let g = self.gate.as_mut().filter(|_| self.frustum.is_some())?;
        let (plan, bytes) = g.plan(gpu);
        (self.plan, self.planned) = (plan, Some(bytes));
        (!plan.occlusion).then(|| self.frustum_list())
    }

    /// U's list, as a frame of frustum culling alone fills it.
    pub(super) fn frustum_list(&self) -> DrawList {
        DrawList { max_count: self.n, ..self.u_list.clone() }
    }
}
