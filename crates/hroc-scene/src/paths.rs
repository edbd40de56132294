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

/// A 10 s path of incoherent frames, the case that breaks temporal
/// coherence (HROC §6): a camera cut every second to a random eye, at a
/// random height from street level to most of the scene's height, inside
/// the scene. Even seconds turn on the spot at 720°/s; odd seconds move
/// ahead at a tenth of the scene's width per second while turning at
/// 90°/s. `seed` picks the eyes.
pub fn cut_path(scene: &Scene, seed: u64) -> CameraPath {
    let b = scene.bounds();
    let ext = b.extent().max(Vec3::splat(1e-3));
    let mut rng = crate::generators::rng::Rng::derive(seed, "cut path");
    let mut keys = Vec::new();
    for s in 0..10 {
        let t0 = s as f32;
        let eye = Vec3::new(b.min.x + ext.x * rng.range(0.1, 0.9), b.min.y + (ext.y * rng.range(0.0, 0.7)).max(1.7).min(ext.y), b.min.z + ext.z * rng.range(0.1, 0.9));
        let yaw0 = rng.range(0.0, std::f32::consts::TAU);
        let pitch = rng.range(-0.25, 0.1);
        let look = |eye: Vec3, yaw: f32| eye + Vec3::new(yaw.cos(), pitch, yaw.sin()) * ext.length() * 0.05;
        if s % 2 == 0 {
            // 720°/s: a key every 45° so the target's chord stays close to the turn.
            for j in 0..=16 {
                let yaw = yaw0 + j as f32 * std::f32::consts::FRAC_PI_4;
                keys.push(key(t0 + j as f32 / 16.0, eye, look(eye, yaw)));
            }
        } else {
            for j in 0..=4 {
                let yaw = yaw0 + j as f32 * std::f32::consts::FRAC_PI_8;
                let at = eye + Vec3::new(yaw0.cos(), 0.0, yaw0.sin()) * ext.x.max(ext.z) * 0.1 * (j as f32 / 4.0);
                keys.push(key(t0 + j as f32 / 4.0, at, look(at, yaw)));
            }
        }
    }
    CameraPath { keys, near: None, far: None }
}

/// A built-in path by name, for `--camera-path`: `hard` ([`hard_path`]) or
/// `cuts` ([`cut_path`]); `None` for any other name (a file).
pub fn builtin(scene: &Scene, name: &str) -> Option<CameraPath> {
    match name {
        "hard" => Some(hard_path(scene)),
        "cuts" => Some(cut_path(scene, 1)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cut_path_cuts_every_second_inside_the_scene() {
        let scene = crate::load("radial-city", Some(800), 0).unwrap();
        let p = cut_path(&scene, 1);
        p.validate().unwrap();
        assert_eq!(cut_times(&p), (1..10).map(|s| s as f32).collect::<Vec<_>>());
        assert_eq!(p.duration(), 10.0);
        let b = scene.bounds();
        for k in &p.keys {
            let eye = Vec3::from(k.eye);
            assert!(eye.cmpge(b.min).all() && eye.cmple(b.max).all(), "eye {eye} outside the scene {b:?}");
        }
        // 720°/s in the first second: the view turns 45° between keys.
        let dir = |k: &CameraKey| (Vec3::from(k.target) - Vec3::from(k.eye)).normalize();
        let turn = dir(&p.keys[0]).dot(dir(&p.keys[1])).acos().to_degrees();
        assert!((40.0..50.0).contains(&turn), "{turn}°");
        assert_ne!(cut_path(&scene, 2).keys[0].eye, p.keys[0].eye, "the seed picks the eyes");
        assert!(builtin(&scene, "cuts").is_some() && builtin(&scene, "hard").is_some() && builtin(&scene, "x.json").is_none());
    }
}
