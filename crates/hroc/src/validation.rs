//! Validation ([`crate::CullerDesc::validation`]): every host mistake that
//! would make a view cull what it must draw, found on the GPU without
//! waiting, and reported a frame or two later as a [`Finding`] (by
//! [`crate::View::cull`] once it has recorded its frame, or by
//! [`crate::View::validation`]), naming the object, view, phase and
//! frame, and the fix.
//!
//! A frame's draws come in groups: consecutive lists of one phase, which
//! the host marks into one buffer or not at all. `validate.wgsl` stamps
//! each list's objects with the frame, group and list; after a list the
//! host marks, stamps the objects marked; and after every group reads the
//! host's depth and IDs, comparing them with the last read (the first
//! group's with the cleared targets): drawing only brings depth nearer and
//! never writes ID 0, and an object that owns a sample after a group the
//! host marks must be marked. It then looks for marks no passing fragment
//! made (an object marked, owning no sample, whose every sample is empty
//! or owned by an object drawn before it: no forced early-Z). The frame's
//! last read checks every sample's ID: in range, naming an object an
//! occluding list drew, and not in front of that object's box along the
//! pixel's ray (boxes too small, wrong transforms, depth bias toward the
//! viewer). A view without IDs checks, at the frame's end, every drawn
//! sample against the boxes of all the objects the frame drew: not in
//! front of where its ray enters the nearest (depth bias toward a light
//! in a shadow cascade, boxes too small, stale transforms), and names the
//! drawn box nearest the sample as the likeliest culprit. Where the host
//! clears before the frame ([`crate::View::cull`]), the frame's first pass
//! checks that it did. What it finds is counted, with a first example, and
//! read back through a staging ring like the draw tally's. All that is due
//! at one point of the frame is one compute pass.
//!
//! The checks are exact, so they raise no alarm on a host that keeps the
//! contract: each compares what drawing can do with what was drawn,
//! padded as the culler's own tests pad boxes and by the depth's and the
//! projection's rounding.

use crate::gpu::shape::{EncoderShape, PassShape};
use std::collections::HashMap;

use crate::contract::{DrawList, Phase, Targets};
use crate::error::{Error, Finding};
use crate::gpu::{Gpu, Readback, Uploads};
use crate::reflect::{pipeline_layout, Layout};

/// Groups of draws a frame tells apart (`GROUPS` in `validate.wgsl`).
const GROUPS: usize = 32;

/// Kinds of finding, in `validate.wgsl`'s order.
const KINDS: usize = 11;

/// `Check::mode` bits (`validate.wgsl`).
const FIRST: u32 = 1;
const CHECK_IDS: u32 = 2;
const HOST_MARKS: u32 = 4;
const FINAL: u32 = 8;
const BEGIN: u32 = 16;
const BOXES: u32 = 32;

/// Bytes of `Results`: a count, object, pixel and group per kind, then
/// per group whether it changed a pixel, and the objects it marked, then
/// the suspect's key (and padding).
const RESULT_BYTES: u64 = (KINDS * 16 + GROUPS * 8 + 16) as u64;

/// Most pixels a pass over the host's targets reads: beyond, it reads
/// one in `s` × `s` (the least power of two that fits), a different one
/// each frame, every pixel in `s²` frames. A CPU rasterizer pays for each
/// pixel read (lavapipe on 2 cores: a pass reading all of 640 × 360 costs
/// about 13 ms, most of a 15 ms frame).
const PIXELS_READ: u32 = 1024;

/// The check that the host cleared its targets before the frame runs
/// one frame in this many (a pass of its own; a target left uncleared is
/// so every frame).
const CLEARED_EVERY: u64 = 8;

/// Without IDs, the check of drawn samples against the drawn boxes runs
/// one frame in this many (it costs hzb about 13 % of a frame on the
/// default scene on lavapipe where it runs; BENCHMARKS.md, "Validation").
const BOXES_EVERY: u64 = 2;

/// Most objects a frame's check of hidden marks reads around (the
/// pixels their boxes cover, up to 32 × 32 each): beyond, one in
/// `slots / OBJECTS_READ`, a different one each frame.
const OBJECTS_READ: u32 = 1024;

/// Workgroups of 64 threads for `n` items, at most [`THREADS`] threads,
/// which stride over the rest: a CPU rasterizer pays per thread.
fn groups(n: u32) -> u32 {
    n.min(THREADS).div_ceil(64).max(1)
}

/// Most threads a pass over objects or a list launches.
const THREADS: u32 = 1024;

/// The stride of the pixels read in a view of `size`.
fn stride(size: (u32, u32)) -> u32 {
    let mut s = 1;
    while size.0.div_ceil(s) * size.1.div_ceil(s) > PIXELS_READ {
        s *= 2;
    }
    s
}

/// Bind groups kept for the lists and marks buffers seen lately.
const BINDS: usize = 256;

/// `Check` in `validate.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CheckUniform {
    /// The frame's tag (bits 8.. of a stamp).
    pub tag: u32,
    /// The group checked or marked.
    pub group: u32,
    /// `FIRST`, `CHECK_IDS`, `HOST_MARKS`, `FINAL`, `BEGIN`, `BOXES` bits.
    pub mode: u32,
    /// Bits of an object index in the suspect's key.
    pub object_bits: u32,
    /// Which pixel of each `stride` × `stride` square the frame reads.
    pub offset: [u32; 2],
    /// The pixels the frame reads: one in `stride` × `stride`, from `offset`.
    pub stride: u32,
    /// The objects the check of hidden marks reads around: one in this
    /// many, a different one each frame.
    pub object_stride: u32,
}

/// The validation passes of a culler's device, per sample count of the
/// host's targets, built when a view first needs them.
#[derive(Default)]
pub(crate) struct Validator {
    built: std::sync::Mutex<Vec<(u32, Passes)>>,
}

/// The passes and their layouts.
#[derive(Clone)]
struct Passes {
    pixels: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    /// Without IDs: the drawn boxes' entries, then the suspect, in the
    /// pixels' layout.
    box_entries: wgpu::ComputePipeline,
    suspect: wgpu::ComputePipeline,
    stamp: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    marks: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    late: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
}

impl Validator {
    fn passes(&self, gpu: &Gpu, samples: u32) -> Passes {
        let mut built = self.built.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, p)) = built.iter().find(|(n, _)| *n == samples) {
            return p.clone();
        }
        let module = gpu.shader("validate.wgsl", &crate::shaders::source_for("validate.wgsl", samples));
        let make = |layout: Layout, entry: &str| {
            let bgl = layout.create_for(gpu, samples);
            (gpu.compute_pipeline(&module, entry, Some(&pipeline_layout(gpu, layout.label(), &bgl)), &[]), bgl)
        };
        let pixels = make(Layout::Validate, "check_pixels");
        let same = |entry: &str| gpu.compute_pipeline(&module, entry, Some(&pipeline_layout(gpu, Layout::Validate.label(), &pixels.1)), &[]);
        let p = Passes {
            box_entries: same("box_entries"),
            suspect: same("suspect"),
            pixels,
            stamp: make(Layout::ValidateStamp, "stamp"),
            marks: make(Layout::ValidateMarks, "marks_of_group"),
            late: make(Layout::ValidateLate, "late_marks"),
        };
        built.push((samples, p.clone()));
        p
    }
}

/// What a frame's findings are tagged with: its number, and its groups.
#[derive(Clone, Copy)]
struct Tag {
    frame: u64,
    groups: [Option<Group>; GROUPS],
}

/// A group of draws: its phase, whether the host marked some of its
/// lists, and whether it marked them all (then any pixel it drew comes
/// with a mark).
#[derive(Clone, Copy)]
struct Group {
    phase: Phase,
    marked: bool,
    all_marked: bool,
}

/// One view's validation: its buffers, and the frame being recorded.
pub(crate) struct Validation {
    passes: Passes,
    check: wgpu::Buffer,
    results: wgpu::Buffer,
    stamps: wgpu::Buffer,
    marked: wgpu::Buffer,
    order: wgpu::Buffer,
    pixels_bind: wgpu::BindGroup,
    late_bind: wgpu::BindGroup,
    /// Each list's stamp bind group, and its uniform (group and number).
    stamp_binds: HashMap<(wgpu::Buffer, wgpu::Buffer), (wgpu::BindGroup, wgpu::Buffer)>,
    marks_binds: HashMap<wgpu::Buffer, wgpu::BindGroup>,
    /// The view checks IDs (its method has the host write them).
    ids: bool,
    size: (u32, u32),
    slots: u32,
    /// The view, as errors name it.
    name: String,
    uniform: CheckUniform,
    tag: Tag,
    /// The frame's draws so far: none yet, or the group being drawn (its
    /// phase and marks buffer).
    group: Option<(usize, Phase, Option<wgpu::Buffer>)>,
    /// Lists handed to the host so far in the frame.
    lists: u32,
    /// The frame is stepwise ([`crate::View::steps`]): the engine draws
    /// its lists in two passes.
    stepwise: bool,
    /// Lists drawn and not yet stamped: each with its `Stamping` (group,
    /// number, marked by the host).
    pending: Vec<(DrawList, [u32; 4])>,
    ring: Vec<(wgpu::Buffer, Readback<Tag>)>,
}

/// What a view's validation binds.
pub(crate) struct ValidationDesc<'a> {
    pub frame: &'a wgpu::Buffer,
    pub bounds: &'a wgpu::Buffer,
    pub oriented: &'a wgpu::Buffer,
    pub slots: u32,
    pub targets: &'a Targets,
    /// The host writes the ID target (the view's method reads it).
    pub ids: bool,
    pub name: String,
}

impl Validation {
    pub(crate) fn new(gpu: &Gpu, validator: &Validator, d: ValidationDesc) -> Validation {
        use wgpu::BufferUsages as U;
        let t = d.targets;
        let passes = validator.passes(gpu, t.samples);
        let per_object = |label| gpu.buffer(label, d.slots.max(1) as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let check = gpu.buffer("hroc validation check", std::mem::size_of::<CheckUniform>() as u64, U::UNIFORM | U::COPY_DST);
        let results = gpu.buffer("hroc validation results", RESULT_BYTES, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let s = stride(t.size);
        // Created zeroed: no box entry yet.
        let shadow = gpu.buffer("hroc validation shadow", (t.size.0.div_ceil(s) * t.size.1.div_ceil(s)).max(1) as u64 * 8, U::STORAGE);
        let (stamps, marked) = (per_object("hroc validation stamps"), per_object("hroc validation marked"));
        let (order, owned) = (per_object("hroc validation order"), per_object("hroc validation owned"));
        let ids_format = if t.samples > 1 { wgpu::TextureFormat::Rg16Uint } else { wgpu::TextureFormat::R32Uint };
        let stand_in;
        let ids = match (&t.ids, d.ids) {
            (Some(v), true) => v,
            _ => {
                stand_in = gpu.stand_in("hroc validation no ids", ids_format, t.samples);
                &stand_in
            }
        };
        let resources = [
            (0, d.frame.as_entire_binding()),
            (1, check.as_entire_binding()),
            (2, results.as_entire_binding()),
            (3, stamps.as_entire_binding()),
            (4, marked.as_entire_binding()),
            (5, shadow.as_entire_binding()),
            (6, d.bounds.as_entire_binding()),
            (7, d.oriented.as_entire_binding()),
            (8, wgpu::BindingResource::TextureView(&t.depth_sampled)),
            (9, wgpu::BindingResource::TextureView(ids)),
            (14, order.as_entire_binding()),
            (15, owned.as_entire_binding()),
        ];
        let pixels_bind = Layout::Validate.bind(gpu, &passes.pixels.1, &resources);
        let late_bind = Layout::ValidateLate.bind(gpu, &passes.late.1, &resources);
        Validation {
            passes,
            check,
            results,
            stamps,
            marked,
            order,
            pixels_bind,
            late_bind,
            stamp_binds: HashMap::new(),
            marks_binds: HashMap::new(),
            ids: d.ids && t.ids.is_some(),
            size: t.size,
            slots: d.slots,
            name: d.name,
            uniform: CheckUniform {
                stride: s,
                object_stride: d.slots.div_ceil(OBJECTS_READ).max(1),
                object_bits: u32::BITS - (d.slots.max(2) - 1).leading_zeros(),
                ..Default::default()
            },
            tag: Tag { frame: 0, groups: [None; GROUPS] },
            group: None,
            lists: 0,
            stepwise: false,
            pending: Vec::new(),
            ring: Vec::new(),
        }
    }

    /// Starts frame `number` of the view, after its uniform's upload:
    /// zeroes this frame's findings. Unless the frame is `stepwise` (an
    /// engine clears in its early pass), the host has cleared its targets
    /// before this point (the clearing rule of [`crate::View::cull`]),
    /// which a first read checks one frame in [`CLEARED_EVERY`].
    pub(crate) fn begin(&mut self, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, number: u64, stepwise: bool) {
        enc.counted_clear(&self.results, 0, None);
        let (tag, s) = ((number % 0xff_ffff) as u32 + 1, self.uniform.stride);
        // Each frame another pixel of each square, all in s² frames.
        let k = number.wrapping_mul(0x9e37_79b9) as u32 % (s * s);
        self.uniform =
            CheckUniform { tag, stride: s, offset: [k % s, k / s], object_stride: self.uniform.object_stride, object_bits: self.uniform.object_bits, ..Default::default() };
        self.tag = Tag { frame: number, groups: [None; GROUPS] };
        self.group = None;
        self.lists = 0;
        self.stepwise = stepwise;
        self.pending.clear();
        if !stepwise && number.is_multiple_of(CLEARED_EVERY) {
            self.uniform.mode = BEGIN | if self.ids { CHECK_IDS } else { 0 };
            uploads.write(enc, &self.check, 0, bytemuck::bytes_of(&self.uniform));
            let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc validation cleared"), timestamp_writes: None });
            self.dispatch_pixels(&mut pass);
        }
    }

    /// The pass over the pixels read, in the uniform's mode.
    fn dispatch_pixels(&self, pass: &mut wgpu::ComputePass<'_>) {
        let s = self.uniform.stride;
        pass.set_pipeline(&self.passes.pixels.0);
        pass.set_bind_group(0, &self.pixels_bind, &[]);
        pass.counted_dispatch(self.size.0.div_ceil(s).div_ceil(8), self.size.1.div_ceil(s).div_ceil(8), 1);
    }

    /// Before the host draws a list of `phase` (marking into `marks`, the
    /// host's marks buffer, where it marks): at the first list of a new
    /// group, checks the group before it.
    pub(crate) fn before_draw(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, phase: Phase, marks: Option<&wgpu::Buffer>) {
        if !phase.occludes() {
            return;
        }
        // An engine draws a stepwise frame's early lists in one pass.
        let phase = match phase {
            Phase::Always | Phase::Visible if self.stepwise => Phase::Occluders,
            p => p,
        };
        // Unmarked lists join the group of their phase; lists marking into
        // another buffer start one.
        let index = match &self.group {
            None => 0,
            Some((g, p, m)) if *p == phase && (marks.is_none() || m.is_none() || m.as_ref() == marks) => {
                let g = *g;
                if let Some(group) = self.tag.groups[g].as_mut() {
                    group.marked |= marks.is_some();
                    group.all_marked &= marks.is_some();
                }
                if let (Some(m), Some(group)) = (marks, self.group.as_mut()) {
                    group.2 = Some(m.clone());
                }
                return;
            }
            Some((g, ..)) => {
                let g = *g;
                self.flush(gpu, enc, uploads, None, Some(self.group_mode(g)));
                (g + 1).min(GROUPS - 1)
            }
        };
        self.group = Some((index, phase, marks.cloned()));
        self.tag.groups[index] = Some(Group { phase, marked: marks.is_some(), all_marked: marks.is_some() });
    }

    /// After the host drew `list` (with the host's marks or not): its
    /// objects are stamped with the group at the next flush, before
    /// anything reads the stamps.
    pub(crate) fn after_draw(&mut self, phase: Phase, list: &DrawList, marking: bool) {
        if let Some((g, ..)) = self.group.as_ref().filter(|_| phase.occludes() && list.max_count > 0) {
            self.pending.push((list.clone(), [*g as u32, self.lists, marking as u32, 0]));
            self.lists += 1;
        }
    }

    /// After the lists of one call drew with the host's `marks`: stamps
    /// them, and the objects they marked (before the culler's next pass
    /// reads or changes the marks).
    pub(crate) fn after_marks(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, marks: &wgpu::Buffer) {
        self.flush(gpu, enc, uploads, Some(marks), None);
    }

    /// Ends the frame: checks the last group and every sample's ID, and
    /// copies the findings to a staging buffer mapped when `enc` is
    /// submitted.
    pub(crate) fn end(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads) {
        let Some((g, ..)) = self.group.as_ref() else { return };
        let mode = self.group_mode(*g) | FINAL;
        self.flush(gpu, enc, uploads, None, Some(mode));
        self.group = None;
        let slot = match self.ring.iter().position(|(_, s)| s.is_free()) {
            Some(i) => i,
            None => {
                self.ring.push((gpu.buffer("hroc validation staging", RESULT_BYTES, wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST), Readback::Free));
                self.ring.len() - 1
            }
        };
        let (buf, state) = &mut self.ring[slot];
        enc.counted_copy(&self.results, 0, buf, 0, Some(RESULT_BYTES));
        *state = Readback::request(enc, buf, self.tag);
    }

    fn group_mode(&self, g: usize) -> u32 {
        let marks = self.tag.groups[g].is_some_and(|group| group.marked);
        let first = g == 0;
        (if self.ids { CHECK_IDS } else { 0 }) | (if marks { HOST_MARKS } else { 0 }) | (if first { FIRST } else { 0 })
    }

    /// One compute pass of what is due (a CPU rasterizer pays per pass):
    /// the stamps of the lists drawn since the last; the objects `marks`
    /// marked; and with `pixels`, the pass over the host's depth and IDs
    /// in that mode, checking the current group, then its marked objects
    /// that own no sample.
    fn flush(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, marks: Option<&wgpu::Buffer>, pixels: Option<u32>) {
        let g = self.group.as_ref().map_or(0, |(g, ..)| *g);
        self.uniform.group = g as u32;
        // Without IDs, the frame's last read compares with the drawn boxes.
        let pixels = pixels.map(|m| if m & (FINAL | CHECK_IDS) == FINAL && self.tag.frame.is_multiple_of(BOXES_EVERY) { m | BOXES } else { m });
        self.uniform.mode = pixels.unwrap_or(0);
        uploads.write(enc, &self.check, 0, bytemuck::bytes_of(&self.uniform));
        if self.stamp_binds.len() > BINDS {
            self.stamp_binds.clear();
        }
        if self.marks_binds.len() > BINDS {
            self.marks_binds.clear();
        }
        let mut stamps = Vec::with_capacity(self.pending.len());
        for (list, stamping) in std::mem::take(&mut self.pending) {
            let (bind, which) = self.stamp_binds.entry((list.commands.clone(), list.count.clone())).or_insert_with(|| {
                let which = gpu.buffer("hroc validation list", 16, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
                let resources = [
                    (1, self.check.as_entire_binding()),
                    (3, self.stamps.as_entire_binding()),
                    (12, list.commands.as_entire_binding()),
                    (13, list.count.as_entire_binding()),
                    (14, self.order.as_entire_binding()),
                    (16, which.as_entire_binding()),
                ];
                (Layout::ValidateStamp.bind(gpu, &self.passes.stamp.1, &resources), which)
            });
            uploads.write(enc, which, 0, bytemuck::cast_slice(&stamping));
            stamps.push((bind.clone(), list.max_count));
        }
        let marks_bind = marks.map(|m| {
            self.marks_binds
                .entry(m.clone())
                .or_insert_with(|| {
                    let resources = [
                        (1, self.check.as_entire_binding()),
                        (2, self.results.as_entire_binding()),
                        (3, self.stamps.as_entire_binding()),
                        (4, self.marked.as_entire_binding()),
                        (10, m.as_entire_binding()),
                    ];
                    Layout::ValidateMarks.bind(gpu, &self.passes.marks.1, &resources)
                })
                .clone()
        });
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc validation"), timestamp_writes: None });
        pass.set_pipeline(&self.passes.stamp.0);
        for (bind, max_count) in &stamps {
            pass.set_bind_group(0, bind, &[]);
            pass.counted_dispatch(groups(*max_count), 1, 1);
        }
        if let Some(bind) = marks_bind {
            pass.set_pipeline(&self.passes.marks.0);
            pass.set_bind_group(0, &bind, &[]);
            pass.counted_dispatch(groups(self.slots), 1, 1);
        }
        let Some(mode) = pixels else { return };
        let boxes = mode & BOXES != 0;
        if boxes {
            pass.set_pipeline(&self.passes.box_entries);
            pass.set_bind_group(0, &self.pixels_bind, &[]);
            pass.counted_dispatch(groups(self.slots), 1, 1);
        }
        self.dispatch_pixels(&mut pass);
        if boxes {
            pass.set_pipeline(&self.passes.suspect);
            pass.counted_dispatch(groups(self.slots), 1, 1);
        }
        // The group's marked objects that own no sample now.
        if mode & (HOST_MARKS | CHECK_IDS) == HOST_MARKS | CHECK_IDS {
            pass.set_pipeline(&self.passes.late.0);
            pass.set_bind_group(0, &self.late_bind, &[]);
            pass.counted_dispatch(groups(self.slots.div_ceil(self.uniform.object_stride)), 1, 1);
        }
    }

    /// The findings that arrived ([`Validation::harvest`]).
    pub(crate) fn arrived(&mut self, gpu: &Gpu) -> Result<(), Error> {
        match self.harvest(gpu) {
            Some(f) => Err(Error::Validation(f)),
            None => Ok(()),
        }
    }

    /// Takes the findings that arrived, polling the device without
    /// waiting: those of the earliest frame that had any.
    pub(crate) fn harvest(&mut self, gpu: &Gpu) -> Option<Finding> {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let mut first: Option<Finding> = None;
        for (buf, slot) in self.ring.iter_mut() {
            let (name, bits) = (&self.name, self.uniform.object_bits);
            if let Some(Some(found)) = slot.take(buf, |tag, bytes| describe(name, bits, tag, bytes)) {
                if first.as_ref().is_none_or(|f| found.frame < f.frame) {
                    first = Some(found);
                }
            }
        }
        first
    }
}

/// What validation finds: the mistake and its fix, by kind.
const FINDINGS: [&str; KINDS] = [
    "the depth became farther between the culler's draws: the depth target was cleared or overwritten inside the frame (a LoadOp::Clear in a draw's pass, or a pass of the host's own). Clear it once, before View::cull, and load it (LoadOp::Load) in the pass of every Draw",
    "an object's ID was erased between the culler's draws: the ID target was cleared inside the frame. Clear it once, before View::cull, and load it in the pass of every Draw",
    "the ID target holds a value past the culler's object slots: write the draw's instance_index + 1 (the object index + 1), and clear the target to 0",
    "the ID target names an object that no occluding list drew this frame: write instance_index + 1 in the occluding draws only (not in the non-occluders' pass nor in passes of the host's own), and clear the target to 0 each frame",
    "an object drew a fragment in front of its box along the pixel's ray: its box does not bound what it draws (a box too small, a stale or wrong transform, skinning or morphing past the box), or its pass biases depth toward the viewer. Give boxes that hold every vertex of the frame drawn (Culler::set_bounds before the frame), flag deforming objects ObjectFlags::NEVER_CULL, and bias depth only away from the viewer",
    "depth was drawn where the ID target holds 0: every occluding draw writes the object index + 1 (object 0 writes 1) wherever it writes depth, and nothing else writes depth in the frame",
    "an object owns a sample after a phase the host marks, and was not marked: the fragment shaders of the phase must be declared @early_depth_test(force) and call hroc_mark(instance_index) (hroc::device::marks_wgsl), with Draw::marks bound at the group the pipeline's layout has it (Draw::record)",
    "an object was marked although its box lay behind the depth already drawn at every pixel it covers: a fragment that failed the depth test ran the fragment shader, so it is not declared @early_depth_test(force). Declare it on every fragment entry point that calls hroc_mark",
    "the ID values look like the object index itself: write the index + 1 (instance_index + 1), since 0 means nothing was drawn",
    "the targets were not cleared before the frame: depth nearer than far (or an ID other than 0) was there before the culler's first draw. Clear the depth target to its far value (1 standard, 0 reversed) and the ID target to 0 once per frame, before View::cull (a pass of its own, or LoadOp::Clear in a pass recorded before the call)",
    "depth was drawn in front of every box drawn this frame along the pixel's ray: some object's box does not bound what it draws (a box too small, a stale or wrong transform, a vertex shader that moves geometry past its box: wind, skinning, morphing), or a pass biases depth toward the viewer or light. Give boxes that hold every vertex of the frame drawn (Culler::set_bounds before the frame), flag deforming objects ObjectFlags::NEVER_CULL, and bias depth only away from the viewer or light (wgpu::DepthBiasState's constant and slope_scale >= 0 with standard depth, <= 0 with reversed)",
];

/// The findings of one frame (`None`: it had none): the first, in an
/// order where a cause comes before what it brings (a target never
/// cleared, IDs written as the index), and the rest as follow-on. The
/// suspect's key holds an object index in its low `object_bits`.
fn describe(view: &str, object_bits: u32, tag: Tag, bytes: &[u8]) -> Option<Finding> {
    let word = |i: usize| bytemuck::pod_read_unaligned::<u32>(&bytes[i * 4..i * 4 + 4]);
    let suspect = match word(KINDS * 4 + 2 * GROUPS) {
        0 => u32::MAX,
        w => !w & (((1u64 << object_bits) - 1) as u32),
    };
    let phase = |g: u32| match tag.groups.get(g as usize).copied().flatten() {
        Some(group) => format!(", in the {:?} phase", group.phase),
        None => String::new(),
    };
    let mut lines = Vec::new();
    let (mut object, mut pixel, mut mistake) = (None, None, "");
    for kind in [9, 8, 0, 1, 2, 3, 5, 4, 10, 6, 7] {
        let count = word(kind * 4);
        if count == 0 {
            continue;
        }
        let (o, px, group) = (if kind == 10 { suspect } else { word(kind * 4 + 1) }, word(kind * 4 + 2), word(kind * 4 + 3));
        let o = (o != u32::MAX).then_some(o);
        let px = (px != u32::MAX).then_some((px & 0xffff, px >> 16));
        let mut what = match (kind, o) {
            (2, Some(id)) => vec![format!("ID {id}")],
            (10, Some(o)) => vec![format!("object {o} (the drawn box nearest the sample)")],
            (_, Some(o)) => vec![format!("object {o}")],
            _ => Vec::new(),
        };
        if let Some((x, y)) = px {
            what.push(format!("at pixel ({x}, {y})"));
        }
        // BEFORE_BOXES keeps the sample's depth where others keep a group.
        let phase = if kind == 10 { String::new() } else { phase(group) };
        if lines.is_empty() {
            (object, pixel, mistake) = (if kind == 2 { None } else { o }, px, FINDINGS[kind]);
        }
        lines.push(format!("{}{phase} ({count} found): {}", what.join(" "), FINDINGS[kind]).trim_start().to_string());
    }
    let changed = KINDS * 4;
    let marked = changed + GROUPS;
    for (g, group) in tag.groups.iter().enumerate() {
        if let Some(Group { phase, all_marked: true, .. }) = group {
            if word(changed + g) > 0 && word(marked + g) == 0 {
                let fix = FINDINGS[6].split_once(": ").map_or(FINDINGS[6], |(_, fix)| fix);
                lines.push(format!("the {phase:?} phase drew and marked no object: {fix}"));
            }
        }
    }
    let mut lines = lines.into_iter();
    let cause = lines.next()?;
    if mistake.is_empty() {
        // A phase that marked nothing is the first finding.
        mistake = FINDINGS[6];
    }
    Some(Finding { view: view.to_string(), frame: tag.frame, object, pixel, cause, mistake, follow_on: lines.collect() })
}
