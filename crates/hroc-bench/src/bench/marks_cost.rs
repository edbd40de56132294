//! What marks from boxes ([`hroc::device::Marks::Boxes`], for hosts whose
//! shaders cannot mark) cost against the host's own marks (early-Z marks
//! from its fragment shaders), measured side by side: two sessions of one
//! scene on one device, each frame culled by every method in both, in
//! turn, checked against `noc`. C/R (culled over what `noc`'s pictures
//! leave out) counts objects, not time, so it does not depend on noise.

use super::{warmup_frames, Session, SessionDesc};
use crate::error::Result;
use crate::gpu::Headless;
use crate::scene::Scene;
use hroc::device::{Capabilities, Marks};
use hroc::Method;

/// One method's C/R and mean wall ms per frame with the host's marks and
/// with marks from boxes.
#[derive(Clone, Copy, Debug)]
pub struct MarksCost {
    pub method: Method,
    pub host_cr: f64,
    pub boxes_cr: f64,
    pub host_ms: f64,
    pub boxes_ms: f64,
}

/// `methods` over `frames` of `scene`'s path at 640 × 360, on the full
/// tier (early-Z marks) and with marks from boxes, frame by frame in turn
/// (the warm-up frames untimed). Errors on a frame that misses what `noc`
/// draws.
pub fn marks_cost(gpu: &Headless, scene: &Scene, frames: usize, methods: &[Method]) -> Result<Vec<MarksCost>> {
    let session = |marks: Marks| {
        let capabilities = Some(Capabilities { marks, ..Capabilities::FULL });
        Session::with(gpu, scene.clone(), SessionDesc { validate: false, timestamps: false, capabilities, ..SessionDesc::new(frames, (640, 360)) })
    };
    let (mut host, mut boxes) = (session(Marks::EarlyZ)?, session(Marks::Boxes)?);
    let mut views = Vec::with_capacity(methods.len());
    for &m in methods {
        views.push((host.create(m)?, boxes.create(m)?));
    }
    let warm = warmup_frames(frames);
    let n = scene.objects.len() as f64;
    // Per method: culled with host marks, with box marks, ms of each; and what noc leaves out.
    let mut sums = vec![[0.0f64; 4]; methods.len()];
    let mut hidden = 0.0;
    for k in 0..frames {
        let (_, truth) = boxes.truth(k)?;
        hidden += n - truth.visible.len() as f64;
        for ((a, b), sum) in views.iter_mut().zip(sums.iter_mut()) {
            let ra = host.run_frame(a, k)?;
            let ca = host.check(&ra, &truth)?;
            let rb = boxes.run_frame(b, k)?;
            let cb = boxes.check(&rb, &truth)?;
            for c in [&ca, &cb] {
                if (c.false_negatives, c.missing_pixels) != (0, 0) {
                    return Err(crate::Error::Options(format!("{} frame {k}: {} false negatives, {} missing pixels", b.method(), c.false_negatives, c.missing_pixels)));
                }
            }
            sum[0] += n - ca.drawn as f64;
            sum[1] += n - cb.drawn as f64;
            if k >= warm {
                sum[2] += ra.wall_ms;
                sum[3] += rb.wall_ms;
            }
        }
    }
    let timed = (frames - warm).max(1) as f64;
    let hidden = hidden.max(1.0);
    Ok(methods.iter().zip(sums).map(|(&method, s)| MarksCost { method, host_cr: s[0] / hidden, boxes_cr: s[1] / hidden, host_ms: s[2] / timed, boxes_ms: s[3] / timed }).collect())
}
