//! Objects and triangles drawn per frame, counted on the GPU from every
//! list a view hands its host (`tally.wgsl`, one dispatch per list), and
//! read back without waiting: the totals are copied to a staging ring,
//! mapped once the frame's encoder is submitted and done, and tagged with
//! the frame they describe ([`crate::View::frame_stats`]).

use crate::contract::DrawList;
use crate::gpu::{Gpu, Readback, Uploads};
use crate::list_pass::ListPass;
use crate::reflect::Layout;

/// Staging buffers in flight: counts arrive one to three frames late.
const RING: usize = 3;

/// Statistics every method shares, of one frame of one view, read back
/// without waiting ([`crate::View::frame_stats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Which frame: the number of [`crate::View::cull`] calls on the view
    /// before it (0 for its first).
    pub frame: u64,
    /// Draws of objects in the lists handed to the host (an object in two
    /// lists counts twice).
    pub objects: u32,
    /// Triangles of those draws (`index_count / 3` each).
    pub triangles: u32,
    /// The view culled the frame as after a camera cut.
    pub cut: bool,
    /// Mid-frame submits of the method.
    pub submits: u64,
    /// Mid-frame waits for the GPU.
    pub waits: u64,
    /// Bytes read back to the CPU, waited for or not.
    pub bytes_read: u64,
    /// Command slots of the lists handed to the host (their `max_count`
    /// summed): what an emulated draw count walks.
    pub command_slots: u64,
    /// Passes over the object-ID target that marked what a list drew
    /// ([`crate::Marks::Ids`]).
    pub id_passes: u64,
}

/// Per-view counter of what its lists draw.
pub(crate) struct DrawTally {
    pass: ListPass,
    /// `[objects, triangles]` of the frame being recorded.
    totals: wgpu::Buffer,
    ring: Vec<(wgpu::Buffer, Readback<FrameStats>)>,
    latest: Option<FrameStats>,
}

impl DrawTally {
    pub(crate) fn new(gpu: &Gpu) -> Self {
        use wgpu::BufferUsages as U;
        let totals = gpu.buffer("hroc tally", 8, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        DrawTally {
            pass: ListPass::new(gpu, Layout::Tally, "tally.wgsl", "tally", Some(totals.clone())),
            totals,
            ring: (0..RING).map(|_| (gpu.buffer("hroc tally staging", 8, U::MAP_READ | U::COPY_DST), Readback::Free)).collect(),
            latest: None,
        }
    }

    /// Starts a frame: takes the totals of earlier frames that arrived and
    /// zeroes this frame's.
    pub(crate) fn begin(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder) {
        self.harvest(gpu);
        enc.clear_buffer(&self.totals, 0, None);
    }

    /// Counts what `list` draws, after the host recorded its draw.
    pub(crate) fn count(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, list: &DrawList) {
        self.pass.record(gpu, enc, uploads, &list.commands, &list.count, list.max_count);
    }

    /// Ends a frame: copies the totals, with `stats` (the frame's number
    /// and CPU-side counts), to a free staging buffer mapped when `enc` is
    /// submitted (skipped when all are in flight).
    pub(crate) fn end(&mut self, enc: &mut wgpu::CommandEncoder, stats: FrameStats) {
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| s.is_free()) {
            enc.copy_buffer_to_buffer(&self.totals, 0, buf, 0, Some(8));
            *slot = Readback::request(enc, buf, stats);
        }
    }

    /// The newest frame whose totals have arrived, polling the device
    /// without waiting; `None` before the first arrives. A frame's totals
    /// are mapped once its encoder is submitted and done.
    pub(crate) fn latest(&mut self, gpu: &Gpu) -> Option<FrameStats> {
        self.harvest(gpu);
        self.latest
    }

    /// Takes the totals that arrived, polling the device without waiting.
    fn harvest(&mut self, gpu: &Gpu) {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        for (buf, slot) in self.ring.iter_mut() {
            let words = |stats: FrameStats, v: &[u8]| FrameStats { objects: bytemuck::pod_read_unaligned(&v[0..4]), triangles: bytemuck::pod_read_unaligned(&v[4..8]), ..stats };
            if let Some(arrived) = slot.take(buf, words) {
                if self.latest.is_none_or(|l| l.frame < arrived.frame) {
                    self.latest = Some(arrived);
                }
            }
        }
    }
}
