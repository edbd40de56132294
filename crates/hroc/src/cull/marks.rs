//! Where a list's marks go ([`MarkTarget`]), and the culler's own marks
//! from boxes ([`BoxMarks`], [`Marks::Boxes`]): for hosts whose shaders
//! cannot mark (an engine's depth prepass has no fragment stage, and its
//! materials belong to its users) and that have no object-ID target.
//!
//! After an occluding list, the culler rasterizes the box of every object
//! the list drew against the depth the list left, as `roc`'s test does
//! (`roc_boxes.wgsl` with `COMMANDS`): under forced early-Z against the
//! attached depth where the device has it, else at a quarter of the size
//! each way ([`MARKS_SCALE`]), each fragment loading one pixel of its
//! block. A box fragment at or in front of the depth marks its object. A
//! box holds its object, so an object that owns a tested pixel has its
//! box's front face at or in front of that pixel's depth, and is marked;
//! a box may pass where its object does not. Marks are only ever the list's own
//! objects, and every method that reads marks stays conservative with
//! more marks than owners (a marked object of HROC's V was drawn, so it
//! needs no test; a marked object of `roc`'s or HROC's next V is only
//! drawn first) and with fewer (an unmarked object is tested like any
//! other: one seen only between the pixels tested, one whose box leaves
//! the frustum). Boxes that reach the near plane are marked without a
//! test. HROC without occluder filtering or rounds marks once a frame
//! instead, after its occludees: the boxes of all it drew against the
//! final depth, which alone make its next occluders (its walk takes all
//! of V as occluders: every one was drawn).
//!
//! [`Marks::Boxes`]: crate::capabilities::Marks::Boxes

use std::sync::{Arc, Mutex};

use super::roc::{BoxCount, BoxPass};
use super::{DrawList, Frame, MethodContext};
use crate::gpu::shape::EncoderShape;
use crate::id_marks::IdPass;

/// Where the host's draws of a list mark their objects, as the culler
/// runs: in the fragment shader ([`crate::capabilities::Marks::EarlyZ`]),
/// by the culler's pass over the ID target after the list
/// ([`crate::capabilities::Marks::Ids`]), or by the culler's box test
/// against the depth the list left ([`crate::capabilities::Marks::Boxes`]).
#[derive(Clone, Debug)]
pub enum MarkTarget {
    /// The marks bind group the host binds ([`crate::host::marks_wgsl`]),
    /// and the buffer it holds.
    Host(wgpu::BindGroup, wgpu::Buffer),
    /// The pass that marks from the ID target; the host binds a sink.
    Ids(IdPass),
    /// The box test that marks the list's objects into the buffer; the
    /// host binds a sink.
    Boxes(Arc<BoxMarks>, wgpu::Buffer),
}

/// Pixels per side of the blocks whose one pixel box marks test where
/// they load depth themselves (`roc_boxes.wgsl`): a sixteenth of the
/// fragments of a full-size test, each of which loads depth whether or not
/// it is hidden.
pub(crate) const MARKS_SCALE: u32 = 4;

/// Lists one box-marks pass marks at most (a phase hands one or two: a
/// list and its overflow); more are marked in further passes.
const LISTS_PER_PASS: usize = 4;

/// The box test that marks the objects of the lists it is handed in a
/// marks buffer ([`MarkTarget::Boxes`], and CUTOUT objects under early-Z).
pub struct BoxMarks {
    pass: BoxPass,
    frame: wgpu::Buffer,
    bounds: wgpu::Buffer,
    /// `DrawArgs` per list of a pass: 36 vertices, the list's count as instances.
    args: wgpu::Buffer,
    /// A bind group per list's command buffer and marks buffer, built when
    /// first marked.
    binds: Mutex<Vec<((wgpu::Buffer, wgpu::Buffer), wgpu::BindGroup)>>,
}

impl std::fmt::Debug for BoxMarks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BoxMarks").finish_non_exhaustive()
    }
}

impl BoxMarks {
    /// The box marks of a method's view.
    pub(crate) fn new(cx: &MethodContext) -> BoxMarks {
        let gpu = cx.gpu;
        let init: Vec<u32> = (0..LISTS_PER_PASS).flat_map(|_| [36, 0, 0, 0]).collect();
        use wgpu::BufferUsages as U;
        BoxMarks {
            pass: BoxPass::new(cx, true),
            frame: cx.frame.clone(),
            bounds: cx.bounds.clone(),
            args: gpu.buffer_init("hroc box marks args", bytemuck::cast_slice(&init), U::INDIRECT | U::COPY_DST),
            binds: Mutex::new(Vec::new()),
        }
    }

    /// Records the test of `lists`' objects against the depth they left,
    /// marking in `marks` (u32 per object) those whose boxes pass.
    pub(crate) fn record(&self, f: &mut Frame, lists: &[&DrawList], marks: &wgpu::Buffer) {
        for chunk in lists.chunks(LISTS_PER_PASS) {
            let binds: Vec<wgpu::BindGroup> = chunk.iter().map(|l| self.bind(f, &l.commands, marks)).collect();
            let enc = f.encoder();
            for (i, l) in chunk.iter().enumerate() {
                enc.counted_copy(&l.count, 0, &self.args, i as u64 * 16 + 4, Some(4));
            }
            let draws: Vec<(&wgpu::BindGroup, BoxCount)> = binds.iter().enumerate().map(|(i, b)| (b, BoxCount::IndirectAt(&self.args, i as u64 * 16))).collect();
            self.pass.record_all(f, "hroc box marks", &draws);
        }
    }

    fn bind(&self, f: &Frame, commands: &wgpu::Buffer, marks: &wgpu::Buffer) -> wgpu::BindGroup {
        let mut binds = self.binds.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, b)) = binds.iter().find(|((c, m), _)| c == commands && m == marks) {
            return b.clone();
        }
        let b = self.pass.bind(f.gpu, &self.frame, commands, &self.bounds, marks);
        binds.push(((commands.clone(), marks.clone()), b.clone()));
        b
    }
}
