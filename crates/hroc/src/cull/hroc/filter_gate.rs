//! Occluder filtering where it changes the result. OF (step 5 with the
//! ID target, Lee et al. 2021 §4.2) makes the next V the objects that own
//! a pixel, where the merge makes it O ∪ D: it pays where many drawn
//! objects own no pixel (a camera in a city: V shrinks by half), and costs
//! a pass over every pixel where nearly all of them own one (a light
//! looking down on roofs). The gate measures that, in the view, without a
//! stall: one frame in [`PROBE_EVERY`] the filter also counts the objects
//! it keeps and those O ∪ D holds (`filter_occluders` with `MEASURE`,
//! `hroc_next.wgsl`), read back without waiting; until the next
//! measurement arrives, the view filters only if the last one kept at most
//! [`PAYS_BELOW`] of O ∪ D, and merges otherwise.
//!
//! Either next V is conservative: V only orders the frame (its objects
//! are drawn first, the rest tested against them), so the gate changes
//! what a frame costs and culls, never what it shows. It runs where D is
//! marked (early-Z marks), which the merge needs.

use crate::gpu::shape::EncoderShape;
use crate::gpu::{Gpu, Readback};

/// A measurement every this many frames of the view.
pub const PROBE_EVERY: u32 = 8;

/// Filtering pays when it keeps at most this share of O ∪ D.
pub const PAYS_BELOW: f64 = 0.9;

/// Staging buffers in flight.
const RING: usize = 2;

/// Bytes of the tally: objects kept, objects of O ∪ D (u32 each).
const TALLY: u64 = 8;

/// One view's measurement of what its filter changes.
pub(super) struct FilterGate {
    /// `[kept, merged]`, counted by the measuring filter.
    pub(super) tally: wgpu::Buffer,
    ring: Vec<(wgpu::Buffer, Readback<()>)>,
    /// The last measurement said filtering pays (so before any).
    pays: bool,
    /// Frames since the last measurement was recorded.
    since_probe: u32,
    /// The last measurement, `(kept, merged)`.
    pub(super) last: Option<(u32, u32)>,
}

/// What step 5 runs this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Next {
    /// The filter, measuring what it changes.
    Probe,
    /// The filter.
    Filter,
    /// The merge: next V = O ∪ D.
    Merge,
}

impl FilterGate {
    pub(super) fn new(gpu: &Gpu) -> Self {
        use wgpu::BufferUsages as U;
        FilterGate {
            tally: gpu.buffer("hroc filter tally", TALLY, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            ring: (0..RING).map(|_| (gpu.buffer("hroc filter tally staging", TALLY, U::MAP_READ | U::COPY_DST), Readback::Free)).collect(),
            pays: true,
            since_probe: PROBE_EVERY,
            last: None,
        }
    }

    /// Takes the measurements that arrived (polling, never waiting) and
    /// says what step 5 runs; returns the bytes read back too.
    pub(super) fn choose(&mut self, gpu: &Gpu) -> (Next, u64) {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let mut bytes = 0;
        for (buf, slot) in self.ring.iter_mut() {
            if let Some((kept, merged)) = slot.take(buf, |(), v| (bytemuck::pod_read_unaligned::<u32>(&v[0..4]), bytemuck::pod_read_unaligned::<u32>(&v[4..8]))) {
                bytes += TALLY;
                self.last = Some((kept, merged));
                self.pays = merged == 0 || kept as f64 <= PAYS_BELOW * merged as f64;
            }
        }
        let free = self.ring.iter().any(|(_, s)| s.is_free());
        let next = if self.since_probe >= PROBE_EVERY && free {
            Next::Probe
        } else if self.pays {
            Next::Filter
        } else {
            Next::Merge
        };
        self.since_probe = if next == Next::Probe { 0 } else { self.since_probe + 1 };
        (next, bytes)
    }

    /// Before a probe's pass: its tally starts at zero.
    pub(super) fn begin_probe(&self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.tally, 0, None);
    }

    /// After a probe's pass: the tally goes to a free staging buffer,
    /// mapped once `enc` is submitted ([`FilterGate::choose`] found one).
    pub(super) fn end_probe(&mut self, enc: &mut wgpu::CommandEncoder) {
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| s.is_free()) {
            enc.counted_copy(&self.tally, 0, buf, 0, Some(TALLY));
            *slot = Readback::request(enc, buf, ());
        }
    }

    /// A camera cut: filter, and measure again at once.
    pub(super) fn reset(&mut self) {
        self.pays = true;
        self.since_probe = PROBE_EVERY;
    }
}
