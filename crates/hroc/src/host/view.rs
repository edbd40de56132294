//! [`View`]: one method's temporal state over a culler's objects, and its
//! frame.

use super::set::SetPart;
use super::*;
use crate::cull::steps::StepCuts;
use crate::cull::{CullMethod, Frame, FrameBody, Method, MethodContext, MethodOptions, Stage, Stat, WorkCounts};
use crate::error::{Error, Result};
use crate::frustum::ViewDesc;
use crate::gpu::shape::EncoderShape;
use crate::gpu::{GpuTimer, InvocationCounter, Invocations, Submission, Uploads};
use crate::list_pass::ListPass;
use crate::tally::{DrawTally, FrameStats};
use crate::visibility::Visibility;

/// What the host hands in per frame of a view. The view draws into the
/// targets it was created with ([`View::resize`] changes them).
#[derive(Clone, Copy, Debug)]
pub struct FrameInput {
    /// The view and projection of this frame.
    pub view: ViewDesc,
    /// A camera cut: last frame's visibility says nothing about this one.
    pub cut: bool,
    /// Seconds on the host's clock (`soq` expires statistics with it).
    pub time: f32,
}

/// One view of a [`Culler`]'s objects: a method and its temporal state.
pub struct View {
    pub(super) method: Method,
    pub(super) options: MethodOptions,
    pub(super) imp: Box<dyn CullMethod>,
    pub(super) frame: wgpu::Buffer,
    pub(super) targets: Targets,
    pub(super) sink: wgpu::BindGroup,
    pub(super) split: Option<FlagSplit>,
    pub(super) timer: Option<GpuTimer>,
    pub(super) counter: Option<InvocationCounter>,
    pub(super) last_stages: Vec<(Stage, f64)>,
    /// The culler's BVH generation and slots when this view was built.
    pub(super) generation: u64,
    pub(super) slots: u32,
    /// Last frame's eye and view direction, for cut detection.
    pub(super) last_pose: Option<(glam::Vec3, glam::Vec3)>,
    /// The last frame was culled as after a cut.
    pub(super) last_cut: bool,
    /// The last frame's submits, waits and bytes read back.
    pub(super) work: WorkCounts,
    /// The last frame's shape and CPU nanoseconds of recording.
    pub(super) shape: (crate::gpu::FrameShape, u64),
    /// Objects and triangles drawn, per frame, read back without waiting.
    pub(super) tally: DrawTally,
    /// Frames culled so far.
    pub(super) frames: u64,
    /// The frame's writes, recorded in the host's encoder.
    pub(super) uploads: Uploads,
    /// Methods that submit mid-frame: the encoder the last frame ended in.
    pub(super) tail: Option<Submission>,
    /// With an emulated draw count: empties the lists' tails.
    pub(super) tail_pass: Option<ListPass>,
    /// The last frame failed part-way: the next starts over as after a cut.
    pub(super) interrupted: bool,
    /// When the last frame began, on the CPU clock.
    pub(super) last_start: Option<std::time::Instant>,
    /// The method that culled the last frame.
    pub(super) culled_by: Method,
    /// The view's validation, when the culler validates.
    pub(super) validation: Option<crate::validation::Validation>,
    /// Visibility as data, once asked for ([`View::visibility`]).
    pub(super) visibility: Option<crate::visibility::Visibility>,
    /// With early-Z marks, once some object is CUTOUT: its box marks.
    pub(super) cutout_marks: Option<std::sync::Arc<crate::cull::BoxMarks>>,
    /// The next stepwise frame, as planned ([`View::plans_late`]), needs
    /// recording ([`View::wants_steps`]).
    pub(super) wants_steps: bool,
}

impl View {
    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The method that culled the last frame: the view's own, or the one
    /// [`Method::Auto`] chose for it.
    pub fn culled_by(&self) -> Method {
        self.culled_by
    }

    /// Draws into `targets` from the next frame on: a new size, or
    /// another texture in the same role (a host that alternates two depth
    /// textures). The method's state is rebuilt for them; where the new
    /// targets have the old ones' size, format and samples, the view keeps
    /// its visible set (the next frame culls as the last one did, one small
    /// submit on the culler's queue carries it over) and what HROC measured
    /// of it, else it starts over
    /// as after a camera cut. Fails, leaving the view as it was, on targets
    /// no method can draw into (as [`Culler::view`]).
    pub fn resize(&mut self, culler: &Culler, targets: &ViewTargets) -> Result<()> {
        let mut fresh = culler.view_with(self.method, targets, &self.options)?;
        let old = &self.targets;
        let same_shape = (old.size, old.depth_format, old.samples, old.depth, old.ids.is_some())
            == (fresh.targets.size, fresh.targets.depth_format, fresh.targets.samples, fresh.targets.depth, fresh.targets.ids.is_some());
        if same_shape && !self.interrupted {
            let mut enc = culler.gpu.encoder("hroc resize");
            fresh.imp.take_over(&mut enc, self.imp.visible_set());
            crate::cull::hroc::gate::carry_gate(&mut *fresh.imp, &mut *self.imp);
            culler.gpu.queue.submit([enc.finish()]);
            fresh.last_pose = self.last_pose;
        } else {
            fresh.interrupted = true;
        }
        *self = View { frames: self.frames, visibility: self.visibility.take(), ..fresh };
        Ok(())
    }

    /// Culls one frame: records the view's uniform and the method's passes
    /// into `encoder` and hands `host` every list to draw, in phase order.
    /// The host has cleared its targets before (the crate docs' clearing
    /// rule) and submits `encoder` after, now or later (the crate docs'
    /// encoder rule). Methods with counter read-back
    /// ([`Method::submits_mid_frame`]) submit `encoder` mid-frame and
    /// continue in a new one, which this call leaves in `*encoder`; the
    /// default `hroc` never submits or waits.
    ///
    /// Fails on a host's mistake (targets, view, a scene the method cannot
    /// take, [`Error::SubmitOrder`]). The view stays usable (after a
    /// failure part-way, its next frame starts over as after a cut), and
    /// `encoder` stays balanced and submittable.
    ///
    /// With validation ([`CullerDesc::validation`]), an earlier frame's
    /// findings come back as [`Error::Validation`] after this frame is
    /// recorded in full, exactly as without validation: its lists were
    /// handed and drawn, and the host submits `encoder` as usual (a host
    /// that logs the finding and goes on loses no frame).
    pub fn cull(&mut self, culler: &Culler, encoder: &mut wgpu::CommandEncoder, input: &FrameInput, host: &mut dyn DrawHost) -> Result<()> {
        self.record(culler, encoder, input, host, None, None, SetPart::default())
    }

    /// [`View::cull`] with `body` recorded in place of the method's frame:
    /// for tests of a method's building blocks (`cull::queries::QueryRenderer`).
    #[doc(hidden)]
    pub fn cull_with(&mut self, culler: &Culler, encoder: &mut wgpu::CommandEncoder, input: &FrameInput, host: &mut dyn DrawHost, body: FrameBody) -> Result<()> {
        self.record(culler, encoder, input, host, Some(body), None, SetPart::default())
    }

    /// What this view's methods are built from (with [`View::cull_with`]).
    #[doc(hidden)]
    pub fn method_context<'a>(&'a self, culler: &'a Culler) -> MethodContext<'a> {
        let mut cx = culler.context(&self.frame, &self.targets);
        cx.options = &self.options;
        cx
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn record(
        &mut self,
        culler: &Culler,
        encoder: &mut wgpu::CommandEncoder,
        input: &FrameInput,
        host: &mut dyn DrawHost,
        body: Option<FrameBody>,
        steps: Option<&mut StepCuts>,
        set: SetPart<'_>,
    ) -> Result<()> {
        let (started, shape_before) = (std::time::Instant::now(), crate::gpu::shape::recorded());
        let regrown = self.slots != culler.objects.count;
        let rebuilt = self.generation != culler.generation && self.method.keeps_tree();
        if regrown || rebuilt {
            let fresh = culler.view_with(self.method, &self.targets.desc(), &self.options)?;
            // Frames keep their numbers across the rebuild, and a view that
            // keeps its visibility as data keeps it (for the new slots).
            let visibility = self.visibility.is_some().then(|| Visibility::new(&culler.gpu, culler.objects.count));
            *self = View { frames: self.frames, visibility, ..fresh };
        }
        if culler.moves > 0 && !self.method.takes_motion() {
            return Err(Error::InvalidScene(format!("{} keeps its own copy of the BVH and takes static scenes only; objects have moved", self.method)));
        }
        if !self.method.takes_dynamic() && culler.objects.alone > 0 {
            let outside = (0..culler.objects.count as usize).find(|&i| culler.live[i] && (culler.is_dynamic(i) || culler.bvh_leaf(i).is_none()));
            if let Some(i) = outside {
                return Err(Error::InvalidScene(format!(
                    "{} culls through the BVH alone, and object {i} is outside it (DYNAMIC, or added since the last build): call Culler::rebuild, or use hroc",
                    self.method
                )));
            }
        }
        let g = input.view.geometry()?;
        if g.depth != self.targets.depth {
            return Err(Error::InvalidView(format!(
                "the projection maps near to {:?} depth, and the view's targets were given {:?} (ViewTargets::depth_range)",
                g.depth, self.targets.depth
            )));
        }
        // Findings of earlier frames come back after this one is recorded;
        // a stepwise frame's, through View::validation.
        let stepwise = steps.is_some();
        let arrived = self.validation.as_mut().filter(|_| !stepwise).and_then(|v| v.harvest(&culler.gpu));
        culler.flush_oriented();
        let uniform = self.uniform(culler, &g);
        // (A set that packs the view's list wrote it before its pass.)
        if !set.packed {
            self.uploads.write(encoder, &self.frame, 0, bytemuck::bytes_of(&uniform));
        }
        // An engine clears its targets in its early pass, after this point.
        if let Some(v) = self.validation.as_mut() {
            v.begin(encoder, &mut self.uploads, self.frames, stepwise);
        }
        if let Some(v) = self.visibility.as_mut() {
            v.begin(encoder, &mut self.uploads, self.frames);
        }
        let cut = self.detect_cut(culler, &g) || input.cut || std::mem::take(&mut self.interrupted);
        if cut {
            self.imp.reset(encoder);
        }
        self.last_cut = cut;
        if let Some(t) = self.timer.as_mut() {
            t.begin_frame();
        }
        if let Some(c) = self.counter.as_mut() {
            c.begin_frame();
        }
        // Flags cost nothing until some object has one.
        let split_flags = ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER | ObjectFlags::CUTOUT;
        if self.split.is_none() && culler.objects.flags.iter().any(|f| f.bits() & split_flags.bits() != 0) {
            self.split = Some(FlagSplit::new(&culler.gpu, &culler.objects));
        }
        let cutouts = culler.objects.flags.iter().any(|f| f.contains(ObjectFlags::CUTOUT));
        if let Some(s) = self.split.as_mut() {
            s.begin(encoder, &culler.objects, cutouts);
        }
        if cutouts && culler.caps.marks == crate::capabilities::Marks::EarlyZ && self.cutout_marks.is_none() {
            self.cutout_marks = Some(std::sync::Arc::new(crate::cull::BoxMarks::new(&culler.context(&self.frame, &self.targets))));
        }
        self.work = WorkCounts::default();
        // A set that packs the view's list writes its tally.
        self.tally.begin(&culler.gpu, encoder, !set.packed);
        let mut f = Frame {
            tally: &mut self.tally,
            uploads: &mut self.uploads,
            draw_count: culler.caps.draw_count,
            tail: self.tail_pass.as_mut(),
            prior: if self.method.submits_mid_frame() { self.tail.take() } else { None },
            group_open: false,
            work: &mut self.work,
            gpu: &culler.gpu,
            geometry: g,
            uniform,
            time: input.time,
            objects: &culler.objects,
            targets: &self.targets,
            encoder,
            host,
            timer: self.timer.as_mut(),
            counter: self.counter.as_mut(),
            current: Stage::Draw,
            split: self.split.as_mut(),
            sink: &self.sink,
            number: self.frames,
            tree: (&culler.bvh, culler.generation),
            culled_by: self.method,
            period_ms: period_ms(&mut self.last_start),
            validation: self.validation.as_mut(),
            pipelines: &culler.pipelines,
            visibility: self.visibility.as_mut(),
            steps,
            cutout_marks: self.cutout_marks.clone(),
            set_packed: set.packed,
        };
        if let Some((pass, jobs)) = set.pass {
            f.stage(Stage::FrustumCull);
            let (enc, q) = f.counted();
            let mut p = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc set frustum"), timestamp_writes: None });
            q.around(&mut p, |p| pass.record(p, jobs));
        }
        if let Some(always) = culler.objects.always.as_ref() {
            f.stage(Stage::FlaggedObjects);
            f.split_and_hand(Phase::Always, always, None);
        }
        let recorded = match body {
            Some(body) => body(&mut f),
            None => self.imp.frame(&mut f),
        };
        if let Err(e) = recorded {
            // Leave the host's encoder balanced and submittable, and start
            // the next frame over.
            f.end_group();
            f.uploads.close(f.encoder);
            if self.method.submits_mid_frame() {
                self.tail = Some(Submission::mark(f.encoder));
            }
            self.interrupted = true;
            return Err(e);
        }
        if let Some(s) = f.split.take() {
            f.stage(Stage::FlaggedObjects);
            let (enc, q) = f.counted();
            let list = s.finish(enc, &q);
            f.hand(Phase::NonOccluders, &list, None, false);
        }
        if f.validation.is_some() {
            // A stepwise frame's last read comes after the engine's late pass.
            f.take_cut();
        }
        if let Some(v) = f.validation.as_deref_mut() {
            v.end(f.gpu, f.encoder, f.uploads);
        }
        if f.set_unused() {
            // The set tallied a list the frame did not hand.
            f.tally.clear(f.encoder);
        }
        f.tally.record(f.gpu, f.encoder, f.uploads, &crate::gpu::PassCount::NONE);
        if let Some(t) = f.timer.take() {
            t.end(f.encoder);
        }
        if let Some(c) = f.counter.take() {
            c.end(f.encoder);
        }
        f.end_group();
        let w = *f.work;
        let stats = FrameStats {
            frame: self.frames,
            cut,
            submits: w.submits,
            waits: w.waits,
            bytes_read: w.bytes_read,
            command_slots: w.command_slots,
            id_passes: w.id_passes,
            ..Default::default()
        };
        self.culled_by = f.culled_by;
        let shape = crate::gpu::shape::recorded() - shape_before;
        self.shape = (shape, started.elapsed().as_nanos() as u64);
        let stats = FrameStats { shape, record_ns: self.shape.1, ..stats };
        f.tally.end(f.encoder, stats);
        f.uploads.close(f.encoder);
        if self.method.submits_mid_frame() {
            self.tail = Some(Submission::mark(f.encoder));
        }
        self.frames += 1;
        match (culler.pipelines.take_refusal(), arrived) {
            (Some(reason), _) => Err(Error::InvalidPipeline(reason)),
            (None, Some(finding)) => Err(Error::Validation(finding)),
            (None, None) => Ok(()),
        }
    }

    /// The view's `Frame` uniform for `g` this frame.
    pub(super) fn uniform(&self, culler: &Culler, g: &crate::frustum::ViewGeometry) -> crate::layout::FrameUniform {
        g.uniform(self.targets.size, culler.objects.count, culler.bvh.nodes.len() as u32)
    }

    /// The statistics every method shares ([`FrameStats`]: objects and
    /// triangles drawn, cut, submits, waits, bytes read back) of the
    /// newest frame whose counts have come back, without waiting: a
    /// frame's arrive once its encoder was submitted and its work is done
    /// (on a busy GPU, a frame or more later), tagged with its number.
    /// `None` before the first arrives.
    pub fn frame_stats(&mut self, culler: &Culler) -> Option<FrameStats> {
        self.tally.latest(&culler.gpu)
    }

    /// The findings of validation ([`CullerDesc::validation`]) that
    /// arrived since the last [`View::cull`], without waiting: an
    /// [`Error::Validation`] for the earliest frame that had any. An
    /// engine culling with [`View::steps`] calls it each frame (its
    /// frames' findings come only from here); a host that stops culling
    /// calls it once the GPU is done, for the last frames' findings. `Ok`
    /// without validation.
    pub fn validation(&mut self, culler: &Culler) -> Result<()> {
        match self.validation.as_mut() {
            Some(v) => v.arrived(&culler.gpu),
            None => Ok(()),
        }
    }

    /// True when the view turned or moved past the options' cut thresholds
    /// ([`MethodOptions::cut_turn_deg`], [`MethodOptions::cut_move`]) since
    /// the last frame: last frame's visibility says little about this one.
    /// The view's pose is its central ray: the eye of a perspective, and
    /// of an orthographic view (a shadow cascade, whose box follows the
    /// camera while the light's direction stays put) the ray's origin.
    pub(super) fn detect_cut(&mut self, culler: &Culler, g: &crate::frustum::ViewGeometry) -> bool {
        let cut = self.turned(culler, g);
        self.last_pose = Some(pose_of(g));
        cut
    }

    /// [`View::detect_cut`] without taking the pose.
    pub(super) fn turned(&self, culler: &Culler, g: &crate::frustum::ViewGeometry) -> bool {
        let pose = pose_of(g);
        let Some((eye, dir)) = self.last_pose else { return false };
        let turn = dir.dot(pose.1).clamp(-1.0, 1.0).acos().to_degrees();
        let diagonal = if culler.bvh.nodes.is_empty() { f32::INFINITY } else { culler.bvh.aabb(0).extent().length() };
        let limit = self.options.cut_move * diagonal;
        let moved = match g.orthographic {
            // Across the view (its near plane moves along it as its box is
            // refitted), past half its smaller side too.
            true => {
                let side = g.ray_origins.x_axis.truncate().length().min(g.ray_origins.y_axis.truncate().length());
                (pose.0 - eye).reject_from_normalized(pose.1).length() > limit.max(side)
            }
            false => eye.distance(pose.0) > limit,
        };
        turn > self.options.cut_turn_deg || moved
    }

    /// Per-stage GPU ms of the last frame, in stage order; empty without
    /// timestamps. Reads back: call after the frame's work was submitted.
    pub fn stage_ms(&mut self, culler: &Culler) -> Result<&[(Stage, f64)]> {
        self.last_stages = match self.timer.as_ref() {
            Some(t) => t.read(&culler.gpu)?,
            None => Vec::new(),
        };
        Ok(&self.last_stages)
    }

    /// Shader invocations per stage of the last frame, in stage order; empty
    /// without [`CullerDesc::pipeline_statistics`]. Reads back: call after
    /// the frame's work was submitted.
    pub fn stage_invocations(&self, culler: &Culler) -> Result<Vec<(Stage, Invocations)>> {
        let mut v = match self.counter.as_ref() {
            Some(c) => c.read(&culler.gpu)?,
            None => Vec::new(),
        };
        v.sort_by_key(|(s, _)| *s);
        Ok(v)
    }

    /// The method's own statistics of the last frame (set sizes, rays,
    /// ...), for benchmarks and debugging: reads back with a wait, so call
    /// it after the frame's work was submitted. What every method shares
    /// comes without a wait from [`View::frame_stats`].
    pub fn stats(&mut self, culler: &Culler) -> Result<Vec<(Stat, f64)>> {
        let mut s = self.imp.stats(&culler.gpu)?;
        s.push((Stat::Cut, self.last_cut as u32 as f64));
        let w = self.work;
        s.extend([
            (Stat::Submits, w.submits as f64),
            (Stat::Waits, w.waits as f64),
            (Stat::BytesRead, w.bytes_read as f64),
            (Stat::CommandSlots, w.command_slots as f64),
            (Stat::IdPasses, w.id_passes as f64),
        ]);
        s.extend(self.shape_stats());
        Ok(s)
    }

    /// The last frame's shape ([`crate::gpu::FrameShape`]: what the culler
    /// recorded, the host's draws counted as lists) and CPU ms of
    /// recording, as statistics, without a wait: what [`View::stats`]
    /// reports of it. A host sums them over a frame's views.
    pub fn shape_stats(&self) -> [(Stat, f64); 12] {
        let (f, record_ns) = self.shape;
        [
            (Stat::ComputePasses, f.compute_passes as f64),
            (Stat::RenderPasses, f.render_passes as f64),
            (Stat::Dispatches, (f.dispatches + f.indirect_dispatches) as f64),
            (Stat::IndirectDispatches, f.indirect_dispatches as f64),
            (Stat::OwnDraws, f.draws as f64),
            (Stat::Lists, f.lists as f64),
            (Stat::Clears, f.clears as f64),
            (Stat::Copies, f.copies as f64),
            (Stat::QueryOps, (f.query_writes + f.query_resolves) as f64),
            (Stat::Created, (f.bind_groups + f.buffers) as f64),
            (Stat::Maps, f.map_requests as f64),
            (Stat::RecordMs, record_ns as f64 / 1e6),
        ]
    }

    /// BVH nodes whose boxes the method tested last frame, if it tests boxes.
    pub fn tested_nodes(&self, culler: &Culler) -> Result<Option<Vec<u32>>> {
        self.imp.tested_nodes(&culler.gpu)
    }

    /// `ref` only (benchmark): the objects visible in `noc`'s ID target this frame.
    pub fn set_oracle(&mut self, culler: &Culler, visible: &[u32]) -> Result<()> {
        self.imp.set_oracle(&culler.gpu, visible)
    }

    /// The method's own state, for its debug read-backs (e.g.
    /// `view.method_state::<hroc::cull::hroc::Hroc>()`).
    #[doc(hidden)]
    pub fn method_state<T: 'static>(&self) -> Option<&T> {
        (&*self.imp as &dyn std::any::Any).downcast_ref::<T>()
    }

    /// True for `ref`, which needs [`View::set_oracle`] before each frame.
    pub fn wants_oracle(&self) -> bool {
        self.method.is_benchmark_only()
    }

    /// [`View::method_state`], mutable (debug switches of a method).
    #[doc(hidden)]
    pub fn method_state_mut<T: 'static>(&mut self) -> Option<&mut T> {
        (&mut *self.imp as &mut dyn std::any::Any).downcast_mut::<T>()
    }
}

/// A view's pose: its central ray's origin and direction.
fn pose_of(g: &crate::frustum::ViewGeometry) -> (glam::Vec3, glam::Vec3) {
    (g.ray_origins.w_axis.truncate(), g.ray_dirs.z_axis.truncate().normalize_or_zero())
}

/// Milliseconds since `*last` (none for a view's first frame); sets it to now.
fn period_ms(last: &mut Option<std::time::Instant>) -> Option<f64> {
    let now = std::time::Instant::now();
    last.replace(now).map(|t| now.duration_since(t).as_secs_f64() * 1e3)
}
