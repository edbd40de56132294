//! [`Uploads`]: data a view writes per frame, recorded in the host's
//! encoder.
//!
//! `Queue::write_buffer` lands at the next submit, whichever encoder that
//! submits: two frames recorded before a submit would both see the second
//! frame's data. Copies recorded in the encoder keep each frame's data
//! with its own commands, so frames may share an encoder or be submitted
//! late.

use wgpu::util::StagingBelt;

/// Chunks of the per-view staging belt: a frame writes a few hundred bytes.
const CHUNK: u64 = 16 * 1024;

/// A staging belt whose chunks are recalled when the encoder that copies
/// from them is submitted (and simply dropped with an encoder that never
/// is).
pub struct Uploads {
    belt: StagingBelt,
}

impl Uploads {
    /// A belt on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        Uploads { belt: StagingBelt::new(device.clone(), CHUNK) }
    }

    /// Records into `enc` a copy of `bytes` (a non-empty multiple of 4) to
    /// `target` at `offset` (a multiple of 4).
    pub fn write(&mut self, enc: &mut wgpu::CommandEncoder, target: &wgpu::Buffer, offset: u64, bytes: &[u8]) {
        let Some(size) = wgpu::BufferSize::new(bytes.len() as u64) else { return };
        super::shape::count(|s| s.copies += 1);
        self.belt.write_buffer(enc, target, offset, size).copy_from_slice(bytes);
    }

    /// Closes the chunks `enc` copies from, to be recalled once it is
    /// submitted: call before `enc` is finished.
    pub fn close(&mut self, enc: &wgpu::CommandEncoder) {
        self.belt.finish_and_recall_on_submit(enc);
    }
}
