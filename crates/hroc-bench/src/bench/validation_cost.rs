//! What validation ([`hroc::CullerDesc::validation`]) costs, measured side
//! by side: two sessions of one scene on one device, one culler
//! validating and one not, each frame culled by every method in both, in
//! turn (the camera, then each of the light's shadow cascades), and the
//! camera checked against `noc`.

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

/// `methods` over `frames` of `scene`'s path at 640 × 360, with
/// `cascades` shadow cascades, without and with validation, frame by
/// frame in turn (the warm-up frames untimed): a frame's time is its
/// views' sum. Errors on a finding of validation, and on a camera frame
/// that misses what `noc` draws.
pub fn validation_cost(gpu: &Headless, scene: &Scene, frames: usize, methods: &[Method], cascades: u32) -> Result<Vec<ValidationCost>> {
    let session = |validate: bool| -> Result<Session> {
        let mut s = Session::with(gpu, scene.clone(), SessionDesc { validate, timestamps: false, ..SessionDesc::new(frames, (640, 360)) })?;
        s.set_shadow_cascades(cascades)?;
        Ok(s)
    };
    let (mut off, mut on) = (session(false)?, session(true)?);
    let mut views = Vec::with_capacity(methods.len());
    let mut shadow_views = Vec::with_capacity(methods.len());
    for &m in methods {
        views.push((off.create(m)?, on.create(m)?));
        shadow_views.push((0..cascades).map(|c| Ok((off.create_cascade(m, c)?, on.create_cascade(m, c)?))).collect::<Result<Vec<_>>>()?);
    }
    let warm = warmup_frames(frames);
    let mut sums = vec![(0.0, 0.0); methods.len()];
    for k in 0..frames {
        let (_, truth) = on.truth(k)?;
        let fitted = on.cascades(k);
        let time = on.times[k];
        for (((plain, checked), shadows), sum) in views.iter_mut().zip(shadow_views.iter_mut()).zip(sums.iter_mut()) {
            let mut a = off.run_frame(plain, k)?;
            let mut b = on.run_frame(checked, k)?;
            for (c, (plain, checked)) in shadows.iter_mut().enumerate() {
                a.wall_ms += off.run_cascade(plain, c as u32, &fitted[c], time)?.wall_ms;
                b.wall_ms += on.run_cascade(checked, c as u32, &fitted[c], time)?.wall_ms;
            }
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
    for ((_, checked), shadows) in views.iter_mut().zip(shadow_views.iter_mut()) {
        checked.validation(&on.culler)?;
        for (_, checked) in shadows.iter_mut() {
            checked.validation(&on.culler)?;
        }
    }
    let timed = (frames - warm).max(1) as f64;
    Ok(methods.iter().zip(sums).map(|(&method, (a, b))| ValidationCost { method, off_ms: a / timed, on_ms: b / timed }).collect())
}
