//! Visibility as data ([`crate::View::visibility`]): for engines that
//! build their own draws (per material, from their own indirect
//! parameters), one `u32` per object slot says in which phase of this
//! frame the culler draws the object, after a header of this frame's
//! stamp of every phase. A host's shader reads it with the WGSL of
//! [`visibility_wgsl`]. The stamps are written by a pass after each list
//! the culler hands (`visibility.wgsl`), in the host's encoder, so a
//! phase's stamps are there when the host draws that phase.

use crate::contract::{DrawList, Phase};
use crate::gpu::{Gpu, Uploads};
use crate::list_pass::ListPass;
use crate::reflect::Layout;

/// `u32`s before the first object's slot: this frame's stamp of each
/// phase: always, visible, occluders, occludees, interleaved,
/// non-occluders (the order of [`Phase`]), 2 unused.
pub const HEADER: u32 = 8;

/// The index of `phase`'s stamp in the header.
pub const fn phase_index(phase: Phase) -> u32 {
    match phase {
        Phase::Always => 0,
        Phase::Visible => 1,
        Phase::Occluders => 2,
        Phase::Occludees => 3,
        Phase::Interleaved => 4,
        Phase::NonOccluders => 5,
    }
}

/// The stamp of `phase` in frame `frame` of a view: never 0 (a slot never
/// stamped), distinct for every phase and for 2^29 frames in a row.
pub fn stamp(frame: u64, phase: Phase) -> u32 {
    (frame as u32).wrapping_add(1).wrapping_mul(HEADER) | phase_index(phase)
}

/// A view's visibility buffer and the pass that stamps it.
pub(crate) struct Visibility {
    /// [`HEADER`] stamps, then one per object slot.
    pub buffer: wgpu::Buffer,
    pass: ListPass,
    /// The frame being stamped.
    frame: u64,
}

impl Visibility {
    /// The buffer for `slots` objects, and its pass.
    pub fn new(gpu: &Gpu, slots: u32) -> Visibility {
        use wgpu::BufferUsages as U;
        let buffer = gpu.buffer("hroc visibility", (HEADER + slots) as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let pass = ListPass::new(gpu, Layout::Visibility, ("visibility.wgsl", "stamp"), Some(buffer.clone()), &[("HEADER", HEADER as f64)]);
        Visibility { buffer, pass, frame: 0 }
    }

    /// Writes frame `frame`'s header (the first thing the frame records).
    pub fn begin(&mut self, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, frame: u64) {
        self.frame = frame;
        let phases = [Phase::Always, Phase::Visible, Phase::Occluders, Phase::Occludees, Phase::Interleaved, Phase::NonOccluders];
        let mut header = [0u32; HEADER as usize];
        for p in phases {
            header[phase_index(p) as usize] = stamp(frame, p);
        }
        uploads.write(enc, &self.buffer, 0, bytemuck::cast_slice(&header));
    }

    /// Stamps the objects `list` draws with `phase`.
    pub fn record(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, phase: Phase, list: &DrawList) {
        self.pass.record(gpu, enc, uploads, (&list.commands, &list.count, list.max_count), stamp(self.frame, phase));
    }
}

/// The WGSL a host's shader includes to read a view's visibility
/// ([`crate::View::visibility`]) bound at `@group(group) @binding(binding)`
/// as a read-only storage buffer:
///
/// ```wgsl
/// @group(G) @binding(B) var<storage, read> hroc_visibility: array<u32>;
/// const HROC_ALWAYS: u32 = 0u;         // never-culled objects, first
/// const HROC_VISIBLE: u32 = 1u;        // a single-list method's list (noc, vfc)
/// const HROC_OCCLUDERS: u32 = 2u;      // the early pass
/// const HROC_OCCLUDEES: u32 = 3u;      // the late pass
/// const HROC_NON_OCCLUDERS: u32 = 5u;  // NOT_OCCLUDER objects, last
/// // True when this frame draws `object` in `phase`.
/// fn hroc_drawn_in(object: u32, phase: u32) -> bool;
/// // True when this frame draws `object` in its early pass (never culled,
/// // a single list's, or an occluder) or its late pass (an occludee).
/// fn hroc_early(object: u32) -> bool;
/// fn hroc_late(object: u32) -> bool;
/// ```
///
/// `object` is the object's index (its slot). A phase's answers hold once
/// the culler has handed that phase's lists: in a stepwise frame
/// ([`crate::View::steps`]) the early pass's after [`crate::Steps::begin`],
/// the late pass's after [`crate::Steps::occluders_drawn`], the
/// non-occluders' after [`crate::Steps::occludees_drawn`].
pub fn visibility_wgsl(group: u32, binding: u32) -> String {
    format!(
        "// hroc: in which phase this frame draws each object (hroc::View::visibility).\n\
         @group({group}) @binding({binding}) var<storage, read> hroc_visibility: array<u32>;\n\
         const HROC_ALWAYS: u32 = {always}u;\n\
         const HROC_VISIBLE: u32 = {visible}u;\n\
         const HROC_OCCLUDERS: u32 = {occluders}u;\n\
         const HROC_OCCLUDEES: u32 = {occludees}u;\n\
         const HROC_NON_OCCLUDERS: u32 = {non}u;\n\
         fn hroc_drawn_in(object: u32, phase: u32) -> bool {{\n    return hroc_visibility[{HEADER}u + object] == hroc_visibility[phase];\n}}\n\
         fn hroc_early(object: u32) -> bool {{\n    let s = hroc_visibility[{HEADER}u + object];\n    return s == hroc_visibility[HROC_ALWAYS] || s == hroc_visibility[HROC_VISIBLE] || s == hroc_visibility[HROC_OCCLUDERS];\n}}\n\
         fn hroc_late(object: u32) -> bool {{\n    return hroc_drawn_in(object, HROC_OCCLUDEES);\n}}\n",
        always = phase_index(Phase::Always),
        visible = phase_index(Phase::Visible),
        occluders = phase_index(Phase::Occluders),
        occludees = phase_index(Phase::Occludees),
        non = phase_index(Phase::NonOccluders),
    )
}
