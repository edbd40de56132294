//! CPU references of the Hi-Z passes: the pyramid (MAX reduction with
//! whole footprints on non-power-of-two sizes) and the per-object test.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::cull::hroc::cpu::{crosses_near, padded};
use crate::layout::FrameUniform;
use crate::{frustum::aabb_in_frustum, Aabb};

/// One level of the pyramid buffer (`Mip` in `hzb_pyramid.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Mip {
    /// First texel of the level in the concatenated pyramid buffer.
    pub offset: u32,
    /// Level width in texels.
    pub width: u32,
    /// Level height in texels.
    pub height: u32,
    /// Padding to 16 bytes; always 0.
    pub _pad: u32,
}

/// Levels for a `w` x `h` depth buffer: level 0 is full size, each next
/// side is half the last, rounded down, at least 1, down to 1x1.
pub fn mip_chain(w: u32, h: u32) -> Vec<Mip> {
    let (mut w, mut h, mut offset) = (w.max(1), h.max(1), 0);
    let mut mips = Vec::new();
    loop {
        mips.push(Mip { offset, width: w, height: h, _pad: 0 });
        offset += w * h;
        if w == 1 && h == 1 {
            return mips;
        }
        (w, h) = ((w / 2).max(1), (h / 2).max(1));
    }
}

/// Texels of level `i + 1` covering texel range of level `i`: texel `t`
/// takes `2t`, `2t + 1`, and the rest of the row/column when it is last.
fn footprint(t: u32, dst: u32, src: u32) -> (u32, u32) {
    let lo = (2 * t).min(src - 1);
    let hi = if t == dst - 1 { src - 1 } else { (2 * t + 1).min(src - 1) };
    (lo, hi)
}

/// The whole pyramid of `depth` (`w` x `h`, row-major), levels concatenated
/// as [`mip_chain`] lays them out.
pub fn build(depth: &[f32], w: u32, h: u32) -> Vec<f32> {
    let mips = mip_chain(w, h);
    let total = mips.last().map_or(0, |m| m.offset + 1) as usize;
    let mut out = vec![0.0f32; total];
    out[..depth.len()].copy_from_slice(depth);
    for l in 1..mips.len() {
        let (src, dst) = (mips[l - 1], mips[l]);
        for y in 0..dst.height {
            let (y0, y1) = footprint(y, dst.height, src.height);
            for x in 0..dst.width {
                let (x0, x1) = footprint(x, dst.width, src.width);
                let mut far = 0.0f32;
                for sy in y0..=y1 {
                    for sx in x0..=x1 {
                        far = far.max(out[(src.offset + sy * src.width + sx) as usize]);
                    }
                }
                out[(dst.offset + y * dst.width + x) as usize] = far;
            }
        }
    }
    out
}

/// Outcome of the per-object test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The padded box is outside the view frustum: culled.
    OutsideFrustum,
    /// Reaches the near plane: visible without a test.
    Near,
    /// Tested against the pyramid: may be visible?
    Tested(bool),
}

impl Outcome {
    /// True for [`Outcome::Near`] and a passing test: the object is drawn.
    pub fn visible(self) -> bool {
        matches!(self, Outcome::Near | Outcome::Tested(true))
    }
}

/// `hzb_test.wgsl` for one object box. `slack` grows the pixel rect by that
/// many pixels on every side and `tolerance` lets the box's depth be that
/// much behind the pyramid: negative values give what the GPU must find
/// visible, positive ones all it may.
pub fn test(mips: &[Mip], hiz: &[f32], u: &FrameUniform, b: Aabb, slack: f32, tolerance: f32) -> Outcome {
    let vp = Mat4::from_cols_array_2d(&u.view_proj);
    let eye = Vec3::from_slice(&u.eye[..3]);
    let pixel = Vec2::new(u.footprint[0], u.footprint[1]);
    let planes = u.planes.map(Vec4::from);
    let b = padded(b, eye, pixel);
    if !aabb_in_frustum(&planes, b.min, b.max) {
        return Outcome::OutsideFrustum;
    }
    if crosses_near(Vec4::from(u.near_plane), u.near, &b) {
        return Outcome::Near;
    }
    let (mut lo, mut hi) = (Vec3::splat(1e30), Vec2::splat(-1e30));
    for c in 0..8 {
        let p = Vec3::new(if c & 1 != 0 { b.max.x } else { b.min.x }, if c & 2 != 0 { b.max.y } else { b.min.y }, if c & 4 != 0 { b.max.z } else { b.min.z });
        let clip = vp * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc.truncate());
    }
    let size = Vec2::new(u.viewport[0], u.viewport[1]);
    let r0 = Vec2::new(lo.x * 0.5 + 0.5, 0.5 - hi.y * 0.5) * size - slack;
    let r1 = Vec2::new(hi.x * 0.5 + 0.5, 0.5 - lo.y * 0.5) * size + slack;
    if r1.x < r0.x || r1.y < r0.y {
        return Outcome::Tested(false);
    }
    let p0 = r0.floor().clamp(Vec2::ZERO, size - 1.0);
    let p1 = r1.floor().clamp(Vec2::ZERO, size - 1.0);
    let (p0, p1) = ((p0.x as u32, p0.y as u32), (p1.x as u32, p1.y as u32));
    let mut l = 0;
    let (t0, t1) = loop {
        let m = mips[l];
        let t0 = ((p0.0 >> l).min(m.width - 1), (p0.1 >> l).min(m.height - 1));
        let t1 = ((p1.0 >> l).min(m.width - 1), (p1.1 >> l).min(m.height - 1));
        if (t1.0 - t0.0 <= 1 && t1.1 - t0.1 <= 1) || l + 1 >= mips.len() {
            break (t0, t1);
        }
        l += 1;
    };
    let m = mips[l];
    let mut far = 0.0f32;
    for y in t0.1..=t1.1 {
        for x in t0.0..=t1.0 {
            far = far.max(hiz[(m.offset + y * m.width + x) as usize]);
        }
    }
    Outcome::Tested(lo.z - tolerance <= far)
}
