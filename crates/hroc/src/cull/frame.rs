//! [`Frame`]: what a method records into, and the context it is built
//! from.

use super::marks::{BoxMarks, MarkTarget};
use super::*;
use crate::bvh::Bvh;
use crate::capabilities::DrawCount;
use crate::contract::{Draw, DrawHost, Phase, Targets};
use crate::error::{Error, Result};
use crate::flag_split::FlagSplit;
use crate::frustum::ViewGeometry;
use crate::gpu::shape::{EncoderShape, QueueShape};
use crate::gpu::{Gpu, GpuTimer, InvocationCounter, PassCount, Submission, Uploads};
use crate::id_marks::IdMarks;
use crate::layout::FrameUniform;
use crate::list_pass::ListPass;
use crate::objects::{ObjectFlags, SharedObjects};

/// Recorded in place of a method's frame (`View::cull_with`, for tests).
pub type FrameBody<'b> = &'b mut dyn FnMut(&mut Frame) -> Result<()>;

/// Everything a method sees while recording one frame of one view.
pub struct Frame<'a> {
    /// The device the culler was created on.
    pub gpu: &'a Gpu,
    /// The view as the host renders it this frame.
    pub geometry: ViewGeometry,
    /// The `Frame` uniform written for this view and frame.
    pub uniform: FrameUniform,
    /// Seconds on the host's clock, for methods whose statistics expire with
    /// time (`soq`).
    pub time: f32,
    pub(crate) objects: &'a SharedObjects,
    pub(crate) targets: &'a Targets,
    pub(crate) encoder: &'a mut wgpu::CommandEncoder,
    pub(crate) host: &'a mut dyn DrawHost,
    pub(crate) timer: Option<&'a mut GpuTimer>,
    pub(crate) counter: Option<&'a mut InvocationCounter>,
    /// The stage begun last ([`Frame::stage`]).
    pub(crate) current: Stage,
    pub(crate) split: Option<&'a mut FlagSplit>,
    pub(crate) sink: &'a wgpu::BindGroup,
    pub(crate) work: &'a mut WorkCounts,
    pub(crate) tally: &'a mut crate::tally::DrawTally,
    pub(crate) uploads: &'a mut Uploads,
    /// How lists are drawn up to their GPU count.
    pub(crate) draw_count: DrawCount,
    /// With an emulated draw count: the pass that empties a list's tail.
    pub(crate) tail: Option<&'a mut ListPass>,
    /// For methods that submit mid-frame: the encoder that holds the end of
    /// the view's previous frame, checked at the first submit.
    pub(crate) prior: Option<Submission>,
    /// A debug group named after the current stage is open on the encoder,
    /// so a GPU profiler groups the passes as the paper's steps.
    pub(crate) group_open: bool,
    /// The frame's number in its view (0 for the first).
    pub(crate) number: u64,
    /// The culler's BVH on the CPU, and its generation (bumped by every rebuild).
    pub(crate) tree: (&'a Bvh, u64),
    /// The method that culls this frame (what [`Method::Auto`] chose).
    pub(crate) culled_by: Method,
    /// CPU milliseconds since the view's previous frame began.
    pub(crate) period_ms: Option<f64>,
    /// The view's validation, when the culler validates.
    pub(crate) validation: Option<&'a mut crate::validation::Validation>,
    /// The check of the host's pipelines ([`Draw::record`]).
    pub(crate) pipelines: &'a crate::contract::PipelineCheck,
    /// The view's visibility as data, when it keeps it.
    pub(crate) visibility: Option<&'a mut crate::visibility::Visibility>,
    /// A stepwise frame's cuts ([`crate::View::steps`]).
    pub(crate) steps: Option<&'a mut super::steps::StepCuts>,
    /// With early-Z marks and CUTOUT objects: the box test that marks them.
    pub(crate) cutout_marks: Option<std::sync::Arc<BoxMarks>>,
    /// The view is culled in a set that packs its frustum list this frame
    /// ([`crate::Culler::cull_views`]); taken by [`Frame::set_frustum`].
    pub(crate) set_packed: bool,
}

/// Work of one frame that does not depend on how busy the machine is:
/// mid-frame submits, waits for the GPU, and bytes read back to the CPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkCounts {
    /// Mid-frame submits (each read-back's).
    pub submits: u64,
    /// Mid-frame waits for the GPU (read-backs that block).
    pub waits: u64,
    /// Bytes read back to the CPU, waited for or not.
    pub bytes_read: u64,
    /// Command slots of the lists handed to the host (`max_count` summed).
    pub command_slots: u64,
    /// Passes over the object-ID target that marked what a list drew.
    pub id_passes: u64,
}

impl<'a> Frame<'a> {
    /// The encoder to record into (the host's; replaced after a mid-frame
    /// submit, and in a stepwise frame after each pass of the engine's).
    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.take_cut();
        self.encoder
    }

    /// Begins GPU stage `stage` here (ends the previous one).
    pub fn stage(&mut self, stage: Stage) {
        self.take_cut();
        self.current = stage;
        self.end_group();
        self.encoder.push_debug_group(stage.name());
        self.group_open = true;
        if let Some(t) = self.timer.as_deref_mut() {
            t.mark(self.encoder, stage);
        }
    }

    /// The encoder, and a pipeline-statistics slot for the pass about to be
    /// recorded into it ([`Frame::pass_count`]).
    pub fn counted(&mut self) -> (&mut wgpu::CommandEncoder, PassCount) {
        self.take_cut();
        let count = self.pass_count();
        (self.encoder, count)
    }

    /// A pipeline-statistics slot for the next pass, counted under the
    /// current stage (nothing when the view does not count): the pass
    /// records its commands inside [`PassCount::around`].
    pub fn pass_count(&self) -> PassCount {
        match self.counter.as_deref() {
            Some(c) => c.pass(self.current),
            None => PassCount::NONE,
        }
    }

    /// Hands `list` to the host to draw in `phase`; with `marks`, the
    /// objects it drew visibly are marked there (by the host's fragments
    /// under early-Z, or from the ID target after the draw).
    pub fn draw(&mut self, phase: Phase, list: &DrawList, marks: Option<&MarkTarget>) {
        self.draw_all(phase, &[list], marks);
    }

    /// [`Frame::draw`] of several lists of one phase, one after the other:
    /// with ID marks, one pass over the ID target after the last marks
    /// them all.
    pub fn draw_all(&mut self, phase: Phase, lists: &[&DrawList], marks: Option<&MarkTarget>) {
        let mut cutouts = Vec::new();
        for list in lists {
            cutouts.extend(self.split_and_hand(phase, list, marks));
        }
        if let (Some(MarkTarget::Host(_, buffer)), Some(v)) = (marks, self.validation.as_deref_mut()) {
            v.after_marks(self.gpu, self.encoder, self.uploads, buffer);
        }
        // Cutouts cannot mark under early-Z: their boxes do.
        if let (Some(MarkTarget::Host(_, buffer)), Some(boxes), false) = (marks, self.cutout_marks.clone(), cutouts.is_empty()) {
            boxes.record(self, &cutouts.iter().collect::<Vec<_>>(), buffer);
        }
        if let Some(MarkTarget::Ids(ids)) = marks {
            if !lists.is_empty() {
                self.work.id_passes += 1;
                let (enc, q) = self.counted();
                let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc id marks"), timestamp_writes: None });
                q.around(&mut pass, |pass| ids.record(pass));
            }
        }
        if let Some(MarkTarget::Boxes(boxes, buffer)) = marks {
            boxes.record(self, lists, buffer);
        }
    }

    /// Hands `list` to the host after the flag split, if the view has one,
    /// and then its cutout list, if any object is CUTOUT; returns that.
    pub(crate) fn split_and_hand(&mut self, phase: Phase, list: &DrawList, marks: Option<&MarkTarget>) -> Option<DrawList> {
        let split;
        let split_count = if self.split.is_some() { self.pass_count() } else { PassCount::NONE };
        // The never-culled list holds neither NEVER_CULL's nor NOT_OCCLUDER's to take out.
        let empty = match phase {
            Phase::Always => ObjectFlags::CUTOUT,
            _ => ObjectFlags::NEVER_CULL | ObjectFlags::NOT_OCCLUDER | ObjectFlags::CUTOUT,
        };
        let (list, cutouts) = match self.split.as_deref_mut() {
            Some(s) => {
                split = s.split(self.gpu, self.encoder, self.uploads, &self.objects.bounds, list, &split_count, empty.bits());
                (&split.0, split.1.clone())
            }
            None => (list, None),
        };
        self.hand(phase, list, marks, false);
        if let Some(c) = &cutouts {
            self.hand(phase, c, None, true);
        }
        cutouts
    }

    /// Where the view's set packed its frustum list this frame
    /// ([`crate::Culler::cull_views`]): hands the host `list`, which the
    /// set's pass filled (packed, its tail emptied with an emulated draw
    /// count, and tallied), and returns true. False, recording nothing,
    /// where the view culls its frustum itself.
    pub(crate) fn set_frustum(&mut self, list: &DrawList) -> bool {
        if !std::mem::take(&mut self.set_packed) {
            return false;
        }
        self.stage(Stage::Draw);
        self.hand_list(Phase::Visible, list, None, false, true);
        true
    }

    /// True while the set's list is not yet handed ([`Frame::set_frustum`]).
    pub(crate) fn set_unused(&self) -> bool {
        self.set_packed
    }

    /// Hands `list` to the host as it is: with an emulated draw count, the
    /// commands past its GPU count are emptied first; what it draws is
    /// tallied after.
    pub(crate) fn hand(&mut self, phase: Phase, list: &DrawList, marks: Option<&MarkTarget>, cutout: bool) {
        self.hand_list(phase, list, marks, cutout, false);
    }

    /// [`Frame::hand`]; `packed`: a set's list, whose tail and tally its pass wrote.
    fn hand_list(&mut self, phase: Phase, list: &DrawList, marks: Option<&MarkTarget>, cutout: bool, packed: bool) {
        self.step_list(phase);
        self.work.command_slots += list.max_count as u64;
        crate::gpu::shape::count(|s| s.lists += 1);
        if let Some(tail) = self.tail.as_deref_mut().filter(|_| !packed) {
            tail.record(self.gpu, self.encoder, self.uploads, (&list.commands, &list.count, list.max_count), 0);
        }
        let statistics = self.pass_count();
        let host_marks = match marks {
            Some(MarkTarget::Host(_, buffer)) => Some(buffer),
            _ => None,
        };
        if let Some(v) = self.visibility.as_deref_mut() {
            v.record(self.gpu, self.encoder, self.uploads, phase, list);
        }
        if let Some(v) = self.validation.as_deref_mut() {
            v.before_draw(self.gpu, self.encoder, self.uploads, phase, host_marks);
        }
        let draw = Draw {
            phase,
            commands: &list.commands,
            count: &list.count,
            max_count: list.max_count,
            draw_count: self.draw_count,
            marks: match marks {
                Some(MarkTarget::Host(bind, _)) => bind,
                _ => self.sink,
            },
            mark: host_marks.is_some(),
            cutout,
            statistics,
            pipelines: self.pipelines,
        };
        self.host.draw(self.encoder, &draw);
        if let Some(v) = self.validation.as_deref_mut() {
            v.after_draw(phase, list, host_marks.is_some());
        }
        if !packed {
            self.tally.count(list);
        }
    }

    /// How lists are drawn up to their GPU count.
    pub fn draw_count(&self) -> DrawCount {
        self.draw_count
    }

    /// Submits what is recorded so far and continues in a fresh encoder (for
    /// methods that read back mid-frame). Fails, submitting nothing, when
    /// the view's previous frame ended in another encoder that is neither
    /// submitted nor dropped: this submit would run ahead of it.
    fn flush(&mut self) -> Result<()> {
        if let Some(prior) = self.prior.take() {
            if !prior.is(self.encoder) && prior.is_pending() {
                self.work.waits += 1;
                self.gpu.wait()?;
                if prior.is_pending() {
                    return Err(Error::SubmitOrder(
                        "this view submits the host's encoder mid-frame, and its previous frame ended in another encoder that is not yet submitted: submit that encoder first, or cull into it".into(),
                    ));
                }
            }
        }
        let enc = self.next_encoder("hroc frame");
        self.gpu.queue.counted_submit([enc.finish()]);
        self.work.submits += 1;
        Ok(())
    }

    /// Ends the encoder recorded so far (its stage's debug group closed,
    /// its uploads closed) and goes on in a fresh one labelled `label`
    /// (the stage's group opened again); returns the one ended.
    pub(crate) fn next_encoder(&mut self, label: &str) -> wgpu::CommandEncoder {
        let open = self.group_open;
        self.end_group();
        let enc = std::mem::replace(self.encoder, self.gpu.encoder(label));
        self.uploads.close(&enc);
        if open {
            self.encoder.push_debug_group(self.current.name());
            self.group_open = true;
        }
        enc
    }

    /// Records into the encoder a copy of `bytes` (a non-empty multiple of
    /// 4) to `target` at `offset`: per-frame data travels with the frame's
    /// commands, never through the queue, so frames may share an encoder.
    pub fn write(&mut self, target: &wgpu::Buffer, offset: u64, bytes: &[u8]) {
        self.take_cut();
        self.uploads.write(self.encoder, target, offset, bytes);
    }

    /// Closes the current stage's debug group, if one is open.
    pub(crate) fn end_group(&mut self) {
        if std::mem::take(&mut self.group_open) {
            self.encoder.pop_debug_group();
        }
    }

    /// Reads `count` u32s of `buf` mid-frame: submits and waits (a stall,
    /// which is what CR-style methods pay for).
    pub fn read_u32(&mut self, buf: &wgpu::Buffer, count: u64) -> Result<Vec<u32>> {
        self.flush()?;
        self.work.waits += 1;
        self.work.bytes_read += count * 4;
        self.gpu.read(buf, 0, count)
    }

    /// Submits, then maps and reads the first `bytes` of the `MAP_READ`
    /// buffer `staging` (a stall, as [`Frame::read_u32`]).
    pub fn map_read(&mut self, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>> {
        self.flush()?;
        self.work.waits += 1;
        self.work.bytes_read += bytes;
        self.gpu.map_read(staging, bytes)
    }

    /// Counts `bytes` read back without waiting (a staging buffer that
    /// arrived mapped).
    pub fn count_async_read(&mut self, bytes: u64) {
        self.work.bytes_read += bytes;
    }

    /// The host's depth attachment, for the method's own box passes.
    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.targets.depth_attachment
    }

    /// Width and height of the depth attachment.
    pub fn size(&self) -> (u32, u32) {
        self.targets.size
    }

    /// Registered objects.
    pub fn object_count(&self) -> u32 {
        self.objects.count
    }

    /// Every object in object order (`noc`'s list).
    pub fn all(&self) -> DrawList {
        self.objects.all()
    }
}

/// What a method may build from: the culler's shared buffers and the view's
/// own targets.
pub struct MethodContext<'a> {
    /// The host's device.
    pub gpu: &'a Gpu,
    /// The object BVH shared by every view.
    pub bvh: &'a Bvh,
    /// The BVH nodes on the GPU (`BvhNode`), shared by every view.
    pub bvh_nodes: &'a wgpu::Buffer,
    /// Leaf node of every object on the GPU, shared by every view.
    pub leaf_of_object: &'a wgpu::Buffer,
    /// Object boxes (`ObjectBounds`), shared by every view.
    pub bounds: &'a wgpu::Buffer,
    /// Object boxes in their own frames (`OrientedBounds`), shared by every view.
    pub oriented: &'a wgpu::Buffer,
    /// One command per object in object order, shared by every view.
    pub commands: &'a wgpu::Buffer,
    /// Object slots: every per-object buffer covers them.
    pub object_count: u32,
    /// Nodes the BVH can grow to over the slots (rebuilds keep the buffers).
    pub node_capacity: u32,
    /// This view's `Frame` uniform.
    pub frame: &'a wgpu::Buffer,
    /// This view's depth attachment (for box passes) and sampling views.
    pub targets: &'a Targets,
    /// Layout of a marks bind group (one `array<u32>` at binding 0).
    pub marks_layout: &'a wgpu::BindGroupLayout,
    /// Method parameters.
    pub options: &'a MethodOptions,
    /// What the culler runs with.
    pub capabilities: crate::capabilities::Capabilities,
    /// The ID-marks pass, with [`crate::capabilities::Marks::Ids`].
    pub(crate) id_marks: Option<&'a IdMarks>,
    /// `auto`'s candidates (empty for every other method).
    pub(crate) auto: &'a [Method],
}

impl MethodContext<'_> {
    /// Where a list's objects drawn visibly are marked in `marks` (u32 per
    /// object), for [`Frame::draw`]: by the host's fragments, or with ID
    /// marks from the ID target (the view has one: [`crate::Culler::view`]
    /// checks), of the objects `within` flags when given (the list's own
    /// objects, where a mark skips an object's test), else of any.
    pub fn mark_target(&self, marks: &wgpu::Buffer, within: Option<&wgpu::Buffer>) -> MarkTarget {
        match (self.capabilities.marks, self.id_marks, &self.targets.ids) {
            (crate::capabilities::Marks::EarlyZ, _, _) => MarkTarget::Host(self.gpu.bind_buffers(self.marks_layout, &[marks]), marks.clone()),
            (crate::capabilities::Marks::Ids, Some(pass), Some(ids)) => MarkTarget::Ids(pass.bind(self.gpu, ids, (self.targets.size, self.targets.samples), marks, within)),
            (crate::capabilities::Marks::Boxes, _, _) => MarkTarget::Boxes(std::sync::Arc::new(BoxMarks::new(self)), marks.clone()),
            (crate::capabilities::Marks::Ids, _, _) => unreachable!("Culler::view_with checks the ID target of methods that read marks, and ID marks build the pass"),
        }
    }
}
