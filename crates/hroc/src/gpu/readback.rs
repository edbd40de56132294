//! What becomes of the host's encoders once a frame is recorded:
//! [`Readback`], a staging buffer mapped when the encoder that fills it is
//! submitted and read later without waiting, and [`Submission`], whether
//! an encoder was submitted.
//!
//! Both travel with the host's encoder
//! (`CommandEncoder::map_buffer_on_submit`, `on_submitted_work_done`), so
//! they never meet an encoder that is still recording: frames may share an
//! encoder or be submitted late, and an encoder dropped unsubmitted frees
//! its staging buffer.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

const PENDING: u8 = 0;
/// Mapped (a read-back), or submitted and done (a submission).
const MAPPED: u8 = 1;
const FAILED: u8 = 2;
/// The encoder was dropped before it was submitted: nothing was copied.
const DROPPED: u8 = 3;

/// Marks a map request dropped if wgpu drops its callback uncalled (the
/// encoder was never submitted).
struct DropGuard(Arc<AtomicU8>);

impl Drop for DropGuard {
    fn drop(&mut self) {
        let _ = self.0.compare_exchange(PENDING, DROPPED, Ordering::AcqRel, Ordering::Acquire);
    }
}

/// Where a staging buffer stands.
pub enum Readback<T> {
    /// Free to be copied into.
    Free,
    /// Copied into by an encoder, with `T` (what the copy describes):
    /// mapped once that encoder's work is done.
    Pending(T, Arc<AtomicU8>),
}

impl<T: Copy> Readback<T> {
    /// Records into `enc` the request to map `buf` (which `enc` has just
    /// copied into) once `enc` is submitted and done.
    pub fn request(enc: &wgpu::CommandEncoder, buf: &wgpu::Buffer, tag: T) -> Self {
        let state = Arc::new(AtomicU8::new(PENDING));
        let guard = DropGuard(state.clone());
        super::shape::count(|s| s.map_requests += 1);
        enc.map_buffer_on_submit(buf, wgpu::MapMode::Read, .., move |r| {
            guard.0.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
        });
        Readback::Pending(tag, state)
    }

    /// True when `buf` can be copied into.
    pub fn is_free(&self) -> bool {
        matches!(self, Readback::Free)
    }

    /// Takes the contents of `buf` if they arrived (the caller polled the
    /// device): `f` reads the mapped bytes, then `buf` is unmapped and the
    /// slot freed. A failed map, or an encoder dropped unsubmitted, frees
    /// the slot with nothing read.
    pub fn take<R>(&mut self, buf: &wgpu::Buffer, f: impl FnOnce(T, &[u8]) -> R) -> Option<R> {
        let Readback::Pending(tag, state) = self else { return None };
        match state.load(Ordering::Acquire) {
            PENDING => None,
            MAPPED => {
                let tag = *tag;
                let out = buf.slice(..).get_mapped_range().ok().map(|v| f(tag, &v));
                buf.unmap();
                *self = Readback::Free;
                out
            }
            _ => {
                *self = Readback::Free;
                None
            }
        }
    }
}

/// Whether an encoder was submitted: its work done, it was dropped
/// unsubmitted, or neither yet.
pub struct Submission {
    state: Arc<AtomicU8>,
    /// The encoder's identity (wgpu's ids are not reused).
    encoder: u64,
}

impl Submission {
    /// Records into `enc` a marker set when its work is done, or when it is
    /// dropped unsubmitted.
    pub fn mark(enc: &wgpu::CommandEncoder) -> Self {
        let state = Arc::new(AtomicU8::new(PENDING));
        let guard = DropGuard(state.clone());
        enc.on_submitted_work_done(move || guard.0.store(MAPPED, Ordering::Release));
        Submission { state, encoder: identity(enc) }
    }

    /// True when `enc` is the marked encoder.
    pub fn is(&self, enc: &wgpu::CommandEncoder) -> bool {
        identity(enc) == self.encoder
    }

    /// True while the marked encoder is neither done nor dropped: after the
    /// device has waited for all submitted work, it was not submitted.
    pub fn is_pending(&self) -> bool {
        self.state.load(Ordering::Acquire) == PENDING
    }
}

fn identity(enc: &wgpu::CommandEncoder) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    enc.hash(&mut h);
    h.finish()
}
