//! Camera paths that break careless culling, where conservativeness is
//! lost: frame 0, camera cuts, the eye inside object
//! and group boxes, and boxes crossing the near plane. Every conservative
//! method is tested on them against `noc`.

use glam::Vec3;

use super::camera::{CameraKey, CameraPath};
use super::Scene;

fn key(t: f32, eye: Vec3, target: Vec3) -> CameraKey {
    CameraKey { t, eye: eye.to_array(), target: target.to_array(), up: [0.0, 1.0, 0.0], fov_y_deg: 60.0 }
}

/// A 10 s path with a cut every stretch: overview, then inside the largest
/// object's box, then grazing a box face closer than the near plane, then a
/// street-level walk across the scene, then the scene's own path start.
pub fn hard_path(scene: &Scene) -> CameraPath {
    let b = scene.bounds();
    let c = b.center();
    let ext = b.extent().max(Vec3::splat(1e-3));
    let mut keys = Vec::new();
    // Frame 0 from outside, looking in.
    let out = c + Vec3::new(ext.x * 0.9, ext.y * 0.8 + ext.length() * 0.2, ext.z * 0.9);
    keys.push(key(0.0, out, c));
    keys.push(key(1.5, out * 0.7 + c * 0.3, c));
    // Cut: eye inside the biggest object box (also inside every group box above it).
    let big = scene.objects.iter().max_by(|a, b| a.bounds.area().total_cmp(&b.bounds.area())).map(|o| o.bounds).unwrap_or(b);
    let inside = big.center();
    keys.push(key(1.5, inside, inside + Vec3::new(1.0, 0.0, 0.3) * ext.length()));
    keys.push(key(3.0, inside + Vec3::new(0.0, 0.0, big.extent().z * 0.2), inside + Vec3::new(-1.0, -0.2, 0.5) * ext.length()));
    // Cut: eye just outside an object's face, closer than any near plane, so
    // the box crosses the near plane.
    let mid = scene.objects.get(scene.objects.len() / 2).map(|o| o.bounds).unwrap_or(b);
    let face = Vec3::new(mid.center().x, mid.center().y, mid.max.z + 1e-4);
    keys.push(key(3.0, face, face + Vec3::new(0.2, 0.0, -1.0)));
    keys.push(key(4.5, face + Vec3::new(0.0, 0.0, 1e-4), face + Vec3::new(1.0, 0.1, -0.1)));
    // Cut: low walk through the middle of the scene, turning around.
    let low = b.min.y + ext.y * 0.1;
    let a = Vec3::new(b.min.x + ext.x * 0.2, low, c.z);
    let z = Vec3::new(b.max.x - ext.x * 0.2, low, c.z);
    keys.push(key(4.5, a, z));
    keys.push(key(6.5, (a + z) * 0.5, (a + z) * 0.5 + Vec3::new(0.0, 0.0, ext.z)));
    keys.push(key(8.0, z, a));
    // Cut back to the scene's own start.
    if let Some(k0) = scene.path.keys.first() {
        keys.push(CameraKey { t: 8.0, ..*k0 });
        keys.push(CameraKey { t: 10.0, ..scene.path.keys.get(1).copied().unwrap_or(*k0) });
    }
    CameraPath { keys, near: None, far: None }
}

/// Times of the cuts in `path` (two keys with the same time).
pub fn cut_times(path: &CameraPath) -> Vec<f32> {
    path.keys.windows(2).filter(|w| w[0].t == w[1].t).map(|w| w[0].t).collect()
}
