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

pub use hroc::frustum::{aabb_in_frustum, frustum_planes};

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
