//! The demo the forward host's tests and example run: a city with a wall
//! and two blended panels.

use glam::{Mat4, Vec3};
use hroc::DepthRange;

use crate::HostScene;

/// The demo: a generated city, an opaque wall in front of the first camera,
/// one blended panel hidden behind the wall and one in front of it.
pub struct Demo {
    /// The host's scene.
    pub scene: HostScene,
    /// (eye, target) per frame; frame `cut` starts a camera cut.
    pub cameras: Vec<(Vec3, Vec3)>,
    /// The frame of the camera cut.
    pub cut: usize,
    /// The blended panel behind the wall (hidden: must be culled).
    pub glass_behind: usize,
    /// The blended panel in front of the wall (visible: must be drawn).
    pub glass_front: usize,
    /// Near and far plane distances.
    pub near_far: (f32, f32),
    /// The scene crate's hard path over the same objects (frame 0, cuts,
    /// the eye inside boxes, boxes across the near plane), with its own
    /// near and far.
    pub hard: Vec<hroc_scene::Camera>,
}

impl Demo {
    /// `objects` city objects plus the wall and the two panels; `frames`
    /// frames, half from a fixed eye turning a little, half after a cut.
    pub fn new(objects: usize, frames: usize) -> Result<Demo, String> {
        let mut scene = hroc_scene::load("radial-city", Some(objects), 0).map_err(|e| e.to_string())?;
        let (near, far) = hroc_scene::camera::clip_planes(&scene.bounds(), &scene.path);
        let path = scene.path.frames(frames.max(2), near, far);
        let (eye, target) = (path[0].eye, path[0].target);
        let f = (target - eye).normalize();
        let r = f.cross(path[0].up).normalize();
        let u = r.cross(f);
        let mesh = scene.meshes.len() as u32;
        scene.meshes.push(hroc_scene::generators::shapes::cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)).into_mesh("panel"));
        let basis = |c: Vec3, s: Vec3| Mat4::from_cols((r * s.x).extend(0.0), (u * s.y).extend(0.0), (f * s.z).extend(0.0), c.extend(1.0));
        scene.push_object(mesh, basis(eye + f * 10.0, Vec3::new(24.0, 24.0, 0.5)), [0.8, 0.75, 0.7]);
        let glass_behind = scene.objects.len();
        scene.push_object(mesh, basis(eye + f * 14.0, Vec3::new(3.0, 3.0, 0.1)), [0.2, 0.9, 0.3]);
        let glass_front = scene.objects.len();
        scene.push_object(mesh, basis(eye + f * 5.0 + r * 1.0, Vec3::new(2.0, 2.0, 0.1)), [0.9, 0.2, 0.2]);
        let hard_path = hroc_scene::paths::hard_path(&scene);
        let (hn, hf) = hroc_scene::camera::clip_planes(&scene.bounds(), &hard_path);
        let hard = hard_path.frames(frames.max(2) * 2, hn, hf);
        let cut = frames / 2;
        let cameras = (0..frames)
            .map(|k| {
                if k < cut {
                    // A fixed eye, turning 3 degrees either way.
                    let yaw = 3f32.to_radians() * (k as f32 * 0.7).sin();
                    (eye, eye + glam::Quat::from_axis_angle(u, yaw) * f)
                } else {
                    (path[k].eye, path[k].target)
                }
            })
            .collect();
        Ok(Demo { scene: HostScene::from_scene(&scene, &[glass_behind, glass_front]), cameras, cut, glass_behind, glass_front, near_far: (near, far), hard })
    }

    /// View and projection of frame `k`: finite standard depth, or infinite
    /// reversed depth.
    pub fn matrices(&self, k: usize, aspect: f32, depth: DepthRange) -> (Mat4, Mat4) {
        let (eye, target) = self.cameras[k];
        (Mat4::look_at_rh(eye, target, Vec3::Y), projection(60.0, aspect, self.near_far, depth))
    }

    /// View and projection of frame `k` of the hard path.
    pub fn hard_matrices(&self, k: usize, aspect: f32, depth: DepthRange) -> (Mat4, Mat4) {
        let c = &self.hard[k];
        (c.view(), projection(c.fov_y_deg, aspect, (c.near, c.far), depth))
    }
}

/// A right-handed perspective: finite standard depth, or infinite reversed depth.
fn projection(fov_y_deg: f32, aspect: f32, (near, far): (f32, f32), depth: DepthRange) -> Mat4 {
    let fov = fov_y_deg.to_radians();
    match depth {
        DepthRange::Standard => Mat4::perspective_rh(fov, aspect, near, far),
        DepthRange::Reversed => Mat4::perspective_infinite_reverse_rh(fov, aspect, near),
    }
}
