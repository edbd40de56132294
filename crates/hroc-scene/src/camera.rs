//! Cameras and 10 s camera paths: keyframes, piecewise-linear interpolation,
//! camera cuts (two keys at the same time), JSON files (`--camera-path`).

use glam::{Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};
use std::path::Path;

use crate::error::{Error, Result};

/// A perspective pinhole camera. Depth is standard [0, 1] (near → 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }
    pub fn proj(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, self.near, self.far)
    }
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.proj(aspect) * self.view()
    }

    /// Columns x, y, z: world offsets such that the ray through NDC (x, y)
    /// is `eye + t * (x * X + y * Y + Z)`, reaching the near plane at t = 1.
    pub fn ray_dirs(&self, aspect: f32) -> Mat4 {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let ty = (self.fov_y_deg.to_radians() * 0.5).tan();
        let n = self.near;
        Mat4::from_cols((right * ty * aspect * n).extend(0.0), (up * ty * n).extend(0.0), (forward * n).extend(0.0), Vec4::W)
    }
}

pub use hroc::geometry::{aabb_in_frustum, frustum_planes};

/// One cascade of a directional light's shadow map: a view looking along
/// the light and the light-space box its orthographic projection spans
/// (light space looks down -z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    pub view: Mat4,
    pub min: Vec3,
    pub max: Vec3,
}

impl Cascade {
    /// The right-handed orthographic projection of the box: standard depth
    /// (near 0), or `reversed` (near 1).
    pub fn proj(&self, reversed: bool) -> Mat4 {
        let (near, far) = (-self.max.z, -self.min.z);
        let (n, f) = if reversed { (far, near) } else { (near, far) };
        Mat4::orthographic_rh(self.min.x, self.max.x, self.min.y, self.max.y, n, f)
    }
}

/// `count` cascades of a light shining along `-toward_light` onto the
/// scene in `scene`, for `camera` (aspect `aspect`): the camera's depth
/// range (up to the scene's farthest corner) split
/// half logarithmically, half uniformly (the practical split scheme), each
/// slice's corners bounded in light space, and the depth range stretched
/// over the whole scene so that every caster lies between the planes.
pub fn cascades(camera: &Camera, aspect: f32, toward_light: Vec3, scene: &crate::Aabb, count: u32) -> Vec<Cascade> {
    let corner = |i: u32| {
        let (a, b) = (scene.min, scene.max);
        Vec3::new(if i & 1 != 0 { b.x } else { a.x }, if i & 2 != 0 { b.y } else { a.y }, if i & 4 != 0 { b.z } else { a.z })
    };
    let reach = (0..8).map(|i| corner(i).distance(camera.eye)).fold(0.0f32, f32::max);
    let (near, far) = (camera.near, camera.far.min(reach).max(camera.near * 2.0));
    let split = |i: u32| {
        let f = i as f32 / count.max(1) as f32;
        0.5 * (near * (far / near).powf(f)) + 0.5 * (near + (far - near) * f)
    };
    let dir = toward_light.normalize();
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let light = Mat4::look_at_rh(Vec3::ZERO, -dir, up);
    let inv_view = camera.view().inverse();
    let ty = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let tx = ty * aspect;
    let depth = (0..8).map(|i| light.transform_point3(corner(i)).z).fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), z| (lo.min(z), hi.max(z)));
    (0..count)
        .map(|i| {
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for d in [split(i), split(i + 1)] {
                for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                    let p = light.transform_point3(inv_view.transform_point3(Vec3::new(sx * tx * d, sy * ty * d, -d)));
                    (lo, hi) = (lo.min(p), hi.max(p));
                }
            }
            Cascade { view: light, min: lo.truncate().extend(depth.0 - 1.0), max: hi.truncate().extend(depth.1 + 1.0) }
        })
        .collect()
}

/// One key of a camera path file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraKey {
    pub t: f32,
    pub eye: [f32; 3],
    pub target: [f32; 3],
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    60.0
}

/// Keyframed path; keys sorted by `t`. Equal consecutive `t` is a camera cut:
/// the path jumps to the later key.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CameraPath {
    pub keys: Vec<CameraKey>,
    /// Clip planes; `None` lets the scene's bounds choose.
    #[serde(default)]
    pub near: Option<f32>,
    #[serde(default)]
    pub far: Option<f32>,
}

impl CameraPath {
    pub fn new(keys: Vec<CameraKey>) -> Self {
        CameraPath { keys, near: None, far: None }
    }

    pub fn duration(&self) -> f32 {
        self.keys.last().map_or(0.0, |k| k.t)
    }

    /// Reads and checks a JSON path file.
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => Error::NotFound(path.to_path_buf()),
            _ => Error::Io { path: path.to_path_buf(), source: e },
        })?;
        Self::from_json(&text, path)
    }

    /// Parses and checks a JSON path read from `path` (named in errors).
    pub fn from_json(text: &str, path: &Path) -> Result<Self> {
        let p: CameraPath = serde_json::from_str(text).map_err(|e| Error::CameraPath { path: path.to_path_buf(), msg: e.to_string() })?;
        p.validate().map_err(|msg| Error::CameraPath { path: path.to_path_buf(), msg })?;
        Ok(p)
    }

    /// Checks keys are present, finite, ordered and non-degenerate.
    pub fn validate(&self) -> std::result::Result<(), String> {
        if self.keys.is_empty() {
            return Err("no keys".into());
        }
        for (i, k) in self.keys.iter().enumerate() {
            let finite = k.t.is_finite() && k.fov_y_deg.is_finite() && k.eye.iter().chain(&k.target).chain(&k.up).all(|c| c.is_finite());
            if !finite {
                return Err(format!("key {i}: non-finite value"));
            }
            if !(k.fov_y_deg > 0.0 && k.fov_y_deg < 180.0) {
                return Err(format!("key {i}: fov_y_deg {} outside (0, 180)", k.fov_y_deg));
            }
            let dir = Vec3::from(k.target) - Vec3::from(k.eye);
            if dir.length_squared() == 0.0 {
                return Err(format!("key {i}: eye equals target"));
            }
            if dir.cross(Vec3::from(k.up)).length_squared() <= 1e-12 * dir.length_squared() * Vec3::from(k.up).length_squared() {
                return Err(format!("key {i}: up is parallel to the view direction"));
            }
            if i > 0 && k.t < self.keys[i - 1].t {
                return Err(format!("key {i}: t {} before previous key's {}", k.t, self.keys[i - 1].t));
            }
        }
        match (self.near, self.far) {
            (Some(n), _) if !(n > 0.0 && n.is_finite()) => Err(format!("near {n} must be positive")),
            (Some(n), Some(f)) if !(f > n && f.is_finite()) => Err(format!("far {f} must exceed near {n}")),
            _ => Ok(()),
        }
    }

    /// The path at time `t` (clamped). At a cut, `t` equal to the cut time
    /// gives the later key.
    pub fn sample(&self, t: f32, near: f32, far: f32) -> Camera {
        let keys = &self.keys;
        let i = keys.partition_point(|k| k.t <= t); // first key strictly after t
        let k = if i == 0 {
            keys[0]
        } else if i == keys.len() {
            keys[keys.len() - 1]
        } else {
            let (a, b) = (keys[i - 1], keys[i]);
            let s = ((t - a.t) / (b.t - a.t)).clamp(0.0, 1.0);
            let lerp = |x: [f32; 3], y: [f32; 3]| Vec3::from(x).lerp(Vec3::from(y), s).to_array();
            CameraKey { t, eye: lerp(a.eye, b.eye), target: lerp(a.target, b.target), up: lerp(a.up, b.up), fov_y_deg: a.fov_y_deg + (b.fov_y_deg - a.fov_y_deg) * s }
        };
        let (eye, mut target, mut up) = (Vec3::from(k.eye), Vec3::from(k.target), Vec3::from(k.up));
        // Interpolation can collapse target onto eye or up onto the view
        // direction; nudge rather than produce a NaN view matrix.
        if (target - eye).length_squared() < 1e-12 {
            target = eye + Vec3::NEG_Z;
        }
        if (target - eye).cross(up).length_squared() < 1e-12 {
            up = if (target - eye).normalize().y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
        }
        Camera { eye, target, up, fov_y_deg: k.fov_y_deg, near: self.near.unwrap_or(near), far: self.far.unwrap_or(far) }
    }

    /// `frames` cameras at uniform times over the path, first at t = first key.
    pub fn frames(&self, frames: usize, near: f32, far: f32) -> Vec<Camera> {
        self.frame_times(frames).into_iter().map(|t| self.sample(t, near, far)).collect()
    }

    /// The times [`frames`](Self::frames) samples the path at.
    pub fn frame_times(&self, frames: usize) -> Vec<f32> {
        let t0 = self.keys.first().map_or(0.0, |k| k.t);
        let dur = self.duration() - t0;
        (0..frames)
            .map(|f| {
                let s = if frames > 1 { f as f32 / (frames - 1) as f32 } else { 0.0 };
                t0 + dur * s
            })
            .collect()
    }

    /// A 10 s orbit around a box, for files that carry no path.
    pub fn orbit(bounds: &super::Aabb) -> Self {
        let c = bounds.center();
        let r = bounds.extent().length().max(1e-3);
        let keys = (0..=8)
            .map(|i| {
                let a = i as f32 / 8.0 * std::f32::consts::TAU;
                let eye = c + Vec3::new(a.cos() * r, r * 0.4, a.sin() * r);
                CameraKey { t: i as f32 * 1.25, eye: eye.to_array(), target: c.to_array(), up: default_up(), fov_y_deg: 60.0 }
            })
            .collect();
        CameraPath::new(keys)
    }
}

/// Near/far planes that fit a scene: far reaches past everything seen from
/// anywhere near it; near is small relative to the scene but keeps depth
/// precision usable.
pub fn clip_planes(bounds: &super::Aabb, path: &CameraPath) -> (f32, f32) {
    let mut all = *bounds;
    for k in &path.keys {
        all = all.grow_point(Vec3::from(k.eye));
    }
    let diag = all.extent().length().max(1e-3);
    let near = (diag * 2e-5).clamp(1e-3, 0.1);
    (near, diag * 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every cascade holds its slice of the camera's frustum and the whole
    /// scene in depth, in both depth conventions: a point of a slice lands
    /// inside its cascade's clip volume, every scene corner between the
    /// planes; the cascades run from the camera outwards.
    #[test]
    fn cascades_hold_their_slices_and_every_caster() {
        let scene = crate::Aabb::new(Vec3::new(-100.0, 0.0, -300.0), Vec3::new(100.0, 30.0, 100.0));
        let camera = Camera { eye: Vec3::new(0.0, 2.0, 50.0), target: Vec3::new(0.0, 2.0, 0.0), up: Vec3::Y, fov_y_deg: 60.0, near: 0.5, far: 400.0 };
        let c = cascades(&camera, 16.0 / 9.0, Vec3::new(0.4, 0.8, 0.45), &scene, 3);
        assert_eq!(c.len(), 3);
        for reversed in [false, true] {
            let clip = |k: usize, p: Vec3| c[k].proj(reversed) * c[k].view * p.extend(1.0);
            let inside = |k: usize, p: Vec3| {
                let q = clip(k, p);
                q.x.abs() <= 1.0 + 1e-4 && q.y.abs() <= 1.0 + 1e-4 && (-1e-4..=1.0 + 1e-4).contains(&q.z)
            };
            // The eye's neighbourhood in the first, a far point on the view axis in the last.
            assert!(inside(0, Vec3::new(0.0, 2.0, 49.0)));
            assert!(!inside(0, Vec3::new(0.0, 2.0, -200.0)));
            assert!(inside(2, Vec3::new(0.0, 2.0, -200.0)));
            for k in 0..3 {
                for i in 0..8u32 {
                    let p =
                        Vec3::new([scene.min.x, scene.max.x][(i & 1) as usize], [scene.min.y, scene.max.y][(i >> 1 & 1) as usize], [scene.min.z, scene.max.z][(i >> 2) as usize]);
                    let z = clip(k, p).z;
                    assert!((0.0..=1.0).contains(&z), "cascade {k}, corner {i} at depth {z}");
                }
            }
            // Nearer the light is nearer in both conventions' sense.
            let (high, low) = (clip(0, Vec3::new(0.0, 30.0, 45.0)).z, clip(0, Vec3::new(0.0, 0.0, 45.0)).z);
            assert!(if reversed { high > low } else { high < low }, "{high} {low}");
        }
    }
}
