//! The checker every method's frame goes through: `noc`'s picture is the
//! truth ([`Truth`]); a frame's false negatives, missing pixels and the
//! rasterizer's stray fragments ([`Check`]).

use super::session::{FrameResult, Projection, Session};
use crate::error::Result;
use crate::render::DrawList;
use crate::scene::Camera;

/// `noc`'s picture of one frame: the ground truth every method is checked against.
pub struct Truth {
    /// Objects that own at least one pixel of the ID target, sorted.
    pub visible: Vec<u32>,
    pub depth: Vec<f32>,
    /// Object id + 1 per pixel (0: background).
    pub ids: Vec<u32>,
}

impl Truth {
    /// The truth of an ID image (`ids`) and its depth: the objects that
    /// own a texel of it, of `objects`. An ID past them (a wrong decode) is
    /// an error: it would hide the object it stands for.
    pub fn of(ids: Vec<u32>, depth: Vec<f32>, objects: u32) -> Result<Truth> {
        let mut seen = vec![false; objects as usize];
        for &id in &ids {
            if let Some(o) = id.checked_sub(1) {
                *seen.get_mut(o as usize).ok_or_else(|| crate::Error::Device(format!("object ID {id} in noc's picture, of {objects} objects")))? = true;
            }
        }
        let visible = (0..objects).filter(|&o| seen[o as usize]).collect();
        Ok(Truth { visible, depth, ids })
    }
}

impl std::ops::AddAssign for Check {
    fn add_assign(&mut self, o: Check) {
        self.drawn += o.drawn;
        self.triangles += o.triangles;
        self.false_negatives += o.false_negatives;
        self.missing_pixels += o.missing_pixels;
        self.stray_pixels += o.stray_pixels;
    }
}

/// Correctness of one frame against the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Check {
    pub drawn: usize,
    /// Triangles of the drawn objects.
    pub triangles: u64,
    pub false_negatives: usize,
    pub missing_pixels: usize,
    /// `noc` fragments the method did not reproduce that lie in front of
    /// their own object's box: the rasterizer's, not the geometry's (lavapipe
    /// extrapolates the depth of some silhouette pixels of sub-pixel
    /// triangles). No box test can keep them, so they are counted here, not
    /// as missing pixels or false negatives.
    pub stray_pixels: usize,
}

impl Session<'_> {
    /// Checks cascade `c`'s frame just rendered against `truth` (every
    /// differing texel counts: the stray-fragment test is the camera's).
    pub fn check_cascade(&self, c: u32, r: &FrameResult, truth: &Truth) -> Result<Check> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
        let (texture, layer) = s.cascades.depth_of(c);
        let depth = self.gpu.read_depth_layer(texture, layer)?;
        self.check_with(r, truth, &depth, None)
    }

    /// Which objects the lists drew (non-empty commands within the GPU count).
    pub fn drawn(&self, lists: &[DrawList]) -> Result<Vec<bool>> {
        let mut drawn = vec![false; self.renderer.object_count as usize];
        for l in lists {
            for c in self.gpu.read_list(&l.commands, &l.count, l.max_count)? {
                if c.instance_count > 0 && c.index_count > 0 {
                    if let Some(d) = drawn.get_mut(c.first_instance as usize) {
                        *d = true;
                    }
                }
            }
        }
        Ok(drawn)
    }

    /// Checks the frame just rendered against `truth`: false negatives
    /// (visible in `noc`, not drawn) and missing pixels (depth farther than
    /// `noc`'s; samples, with MSAA), leaving out `noc`'s stray fragments
    /// (`Check::stray_pixels`).
    pub fn check(&self, r: &FrameResult, truth: &Truth) -> Result<Check> {
        let depth = self.read_depth()?;
        let t = &self.renderer.targets;
        // The stray test is the perspective camera's; orthographic views count every differing texel.
        let stray = r.camera.filter(|_| self.projection == Projection::Perspective).map(|c| Stray::new(&c, self.renderer.aspect(), (t.width, t.height), t.samples));
        self.check_with(r, truth, &depth, stray.as_ref())
    }

    /// [`Session::check`] against `depth`, the frame's, telling stray
    /// fragments by `stray` where given.
    fn check_with(&self, r: &FrameResult, truth: &Truth, depth: &[f32], stray: Option<&Stray>) -> Result<Check> {
        let drawn = self.drawn(&r.lists)?;
        let is_stray = |i: usize| truth.ids[i] > 0 && stray.is_some_and(|s| s.is_stray(i, truth.depth[i], &self.scene.objects[(truth.ids[i] - 1) as usize].bounds));
        // The stray test runs only where the method differs from noc (rare).
        let (mut missing, mut strays) = (0, 0);
        for i in (0..depth.len()).filter(|&i| depth[i] > truth.depth[i]) {
            if is_stray(i) {
                strays += 1;
            } else {
                missing += 1;
            }
        }
        let undrawn: Vec<u32> = truth.visible.iter().copied().filter(|&o| !drawn[o as usize]).collect();
        let mut real = vec![false; drawn.len()];
        if !undrawn.is_empty() {
            for i in (0..truth.ids.len()).filter(|&i| truth.ids[i] > 0 && !drawn[(truth.ids[i] - 1) as usize]) {
                if !is_stray(i) {
                    real[(truth.ids[i] - 1) as usize] = true;
                }
            }
        }
        Ok(Check {
            drawn: drawn.iter().filter(|&&d| d).count(),
            triangles: self.scene.objects.iter().zip(&drawn).filter(|(_, &d)| d).map(|(o, _)| self.scene.triangles(o) as u64).sum(),
            false_negatives: undrawn.iter().filter(|&&o| real[o as usize]).count(),
            missing_pixels: missing,
            stray_pixels: strays,
        })
    }
}

/// Tells a rasterizer's stray fragment from geometry: the fragment's depth
/// is in front of where the pixel's ray enters the object's box (padded as
/// the shaders pad it, with their depth tolerance), or the ray misses the box.
struct Stray {
    camera: Camera,
    view_proj: glam::Mat4,
    ray_dirs: glam::Mat4,
    pixel: glam::Vec2,
    size: (u32, u32),
    /// Samples per pixel of the checked values (each pixel's in turn).
    samples: u32,
}

impl Stray {
    fn new(camera: &Camera, aspect: f32, size: (u32, u32), samples: u32) -> Self {
        let ray_dirs = camera.ray_dirs(aspect);
        // A perspective camera: a pixel is `b d` high at distance d.
        let pixel = glam::Vec2::new(0.0, 2.0 * ray_dirs.y_axis.truncate().length() / camera.near / size.1 as f32);
        Stray { camera: *camera, view_proj: camera.view_proj(aspect), ray_dirs, pixel, size, samples }
    }

    /// Sample `i` (of each pixel's [`Stray::samples`], tested at the
    /// pixel's centre with a pixel more of padding when there are several).
    fn is_stray(&self, i: usize, depth: f32, bounds: &crate::scene::Aabb) -> bool {
        use glam::{Vec2, Vec4};
        let i = i / self.samples as usize;
        let (w, h) = (self.size.0 as f32, self.size.1 as f32);
        let (x, y) = ((i as u32 % self.size.0) as f32 + 0.5, (i as u32 / self.size.0) as f32 + 0.5);
        let ndc = Vec2::new(x / w * 2.0 - 1.0, 1.0 - y / h * 2.0);
        let dir = (self.ray_dirs * Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
        let eye = self.camera.eye;
        let b = hroc::geometry::tested_box(*bounds, eye, self.pixel, self.samples);
        let (t0, t1) = ((b.min - eye) / dir, (b.max - eye) / dir);
        let (enter, exit) = (t0.min(t1).max_element().max(1.0), t0.max(t1).min_element());
        if exit.is_nan() || enter.is_nan() || exit < enter {
            return true;
        }
        let (c0, c1) = (self.view_proj * eye.extend(1.0), self.view_proj * dir.extend(0.0));
        let entry = (c0.z + enter * c1.z) / (c0.w + enter * c1.w);
        depth < entry - STRAY_TOLERANCE
    }
}

/// Depth-buffer units: 7 float steps near 1.0, the box test's own tolerance.
const STRAY_TOLERANCE: f32 = 4e-7;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Aabb;
    use glam::Vec3;

    fn depth_at(cam: &Camera, aspect: f32, p: Vec3) -> f32 {
        let c = cam.view_proj(aspect) * p.extend(1.0);
        c.z / c.w
    }

    /// A box 40 m ahead, seen through the centre pixel of a 64x36 target.
    #[test]
    fn stray_fragments_are_told_from_geometry() {
        let cam = Camera { eye: Vec3::ZERO, target: Vec3::new(0.0, 0.0, -1.0), up: Vec3::Y, fov_y_deg: 60.0, near: 0.01, far: 500.0 };
        let (size, aspect) = ((64, 36), 64.0 / 36.0);
        let s = Stray::new(&cam, aspect, size, 1);
        let b = Aabb { min: Vec3::new(-2.0, -2.0, -42.0), max: Vec3::new(2.0, 2.0, -38.0) };
        let centre = 18 * 64 + 32;
        // On the box's front face, or behind it: geometry.
        assert!(!s.is_stray(centre, depth_at(&cam, aspect, Vec3::new(0.0, 0.0, -38.0)), &b));
        assert!(!s.is_stray(centre, depth_at(&cam, aspect, Vec3::new(0.0, 0.0, -41.0)), &b));
        // 20 m in front of the box: no geometry inside it makes that fragment.
        assert!(s.is_stray(centre, depth_at(&cam, aspect, Vec3::new(0.0, 0.0, -18.0)), &b));
        // A pixel whose ray misses the box by far.
        assert!(s.is_stray(0, depth_at(&cam, aspect, Vec3::new(0.0, 0.0, -40.0)), &b));
    }
}
