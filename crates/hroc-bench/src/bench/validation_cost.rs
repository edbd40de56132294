//! What validation ([`hroc::CullerDesc::validation`]) costs, measured side
//! by side: two sessions of one scene on one device, one culler
//! validating and one not, each frame culled by every method in both, in
//! turn, and checked against `noc`.

use super::{warmup_frames, Session, SessionDesc};
use crate::error::Result;
use crate::gpu::Headless;
use crate::scene::Scene;
use hroc::Method;

/// One method's mean wall ms per frame without validation and with it.
#[derive(Clone, Copy, Debug)]
pub struct ValidationCost {
    pub method: Method,
    pub off_ms: f64,
    pub on_ms: f64,
}

/// `methods` over `frames` of `scene`'s path at 640 × 360, without and
/// with validation, frame by frame in turn (the warm-up frames untimed).
/// Errors on a finding of validation, and on a frame that misses what
/// `noc` draws.
pub fn validation_cost(gpu: &Headless, scene: &Scene, frames: usize, methods: &[Method]) -> Result<Vec<ValidationCost>> {
    let session = |validate: bool| Session::with(gpu, scene.clone(), SessionDesc { validate, timestamps: false, ..SessionDesc::new(frames, (640, 360)) });
    let (mut off, mut on) = (session(false)?, session(true)?);
    let mut views = Vec::with_capacity(methods.len());
    for &m in methods {
        views.push((off.create(m)?, on.create(m)?));
    }
    let warm = warmup_frames(frames);
    let mut sums = vec![(0.0, 0.0); methods.len()];
    for k in 0..frames {
        let (_, truth) = on.truth(k)?;
        for ((plain, checked), sum) in views.iter_mut().zip(sums.iter_mut()) {
            let a = off.run_frame(plain, k)?;
            let b = on.run_frame(checked, k)?;
            let c = on.check(&b, &truth)?;
            if (c.false_negatives, c.missing_pixels) != (0, 0) {
                return Err(crate::Error::Options(format!("{} frame {k}: {} false negatives, {} missing pixels", checked.method(), c.false_negatives, c.missing_pixels)));
            }
            if k >= warm {
                sum.0 += a.wall_ms;
                sum.1 += b.wall_ms;
            }
        }
    }
    // The last frames' findings.
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    for (_, checked) in views.iter_mut() {
        checked.validation(&on.culler)?;
    }
    let timed = (frames - warm).max(1) as f64;
    Ok(methods.iter().zip(sums).map(|(&method, (a, b))| ValidationCost { method, off_ms: a / timed, on_ms: b / timed }).collect())
}
