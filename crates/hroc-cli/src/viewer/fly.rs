//! The free camera: yaw/pitch about world +Y, moved in view space.

use glam::Vec3;

use hroc_bench::scene::Camera;

/// Radians per pixel of mouse motion.
const LOOK_SENSITIVITY: f32 = 0.003;
/// Pitch stays short of straight up or down, where the view basis degenerates.
const MAX_PITCH: f32 = 89.0 * std::f32::consts::PI / 180.0;
/// Speed factor per wheel notch.
const SPEED_STEP: f32 = 1.25;

/// Movement input, each axis in [-1, 1]: forward (W/S), right (D/A), up (E/Q).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Move {
    pub forward: f32,
    pub right: f32,
    pub up: f32,
}

impl Move {
    pub fn is_zero(&self) -> bool {
        *self == Move::default()
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Fly {
    /// Eye, field of view and clip planes; its target and up are derived.
    pub camera: Camera,
    yaw: f32,
    pitch: f32,
    /// World units per second.
    pub speed: f32,
    min_speed: f32,
    max_speed: f32,
}

impl Fly {
    /// Starts at `camera`'s pose, flying at `speed` units per second; the
    /// wheel reaches a thousandth to a thousand times that.
    pub fn new(camera: Camera, speed: f32) -> Fly {
        let speed = speed.max(1e-3);
        let mut fly = Fly { camera, yaw: 0.0, pitch: 0.0, speed, min_speed: speed * 1e-3, max_speed: speed * 1e3 };
        fly.look_from(&camera);
        fly
    }

    /// Takes over `camera`'s pose (eye, view direction, lens); keeps the speed.
    pub fn look_from(&mut self, camera: &Camera) {
        let d = (camera.target - camera.eye).normalize_or(Vec3::NEG_Z);
        self.camera = *camera;
        self.yaw = d.x.atan2(-d.z);
        self.pitch = d.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
        self.sync();
    }

    /// Unit view direction; yaw 0, pitch 0 looks down -Z.
    pub fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(cp * sy, sp, -cp * cy)
    }

    /// Turns by a mouse motion in pixels (right and down positive).
    pub fn turn(&mut self, dx: f32, dy: f32) {
        self.yaw += dx * LOOK_SENSITIVITY;
        self.pitch = (self.pitch - dy * LOOK_SENSITIVITY).clamp(-MAX_PITCH, MAX_PITCH);
        self.sync();
    }

    /// Moves for `dt` seconds: forward along the view, right level with the
    /// ground, up along world +Y.
    pub fn advance(&mut self, m: Move, dt: f32) {
        let f = self.forward();
        let right = f.cross(Vec3::Y).normalize();
        let v = f * m.forward + right * m.right + Vec3::Y * m.up;
        self.camera.eye += v * self.speed * dt;
        self.sync();
    }

    /// Scales the speed by wheel notches (positive: faster).
    pub fn change_speed(&mut self, notches: f32) {
        self.speed = (self.speed * SPEED_STEP.powf(notches)).clamp(self.min_speed, self.max_speed);
    }

    fn sync(&mut self) {
        self.camera.target = self.camera.eye + self.forward();
        self.camera.up = Vec3::Y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(eye: Vec3, target: Vec3) -> Camera {
        Camera { eye, target, up: Vec3::Y, fov_y_deg: 60.0, near: 0.1, far: 100.0 }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn takes_over_the_view_direction() {
        for target in [Vec3::new(3.0, 1.0, -2.0), Vec3::new(-1.0, -0.5, 4.0), Vec3::new(0.0, 0.0, 1.0), Vec3::X] {
            let c = cam(Vec3::ZERO, target);
            let fly = Fly::new(c, 100.0);
            assert!(close(fly.forward(), target.normalize()), "{target}: {}", fly.forward());
            assert!(close(fly.camera.target - fly.camera.eye, target.normalize()));
            assert_eq!((fly.camera.fov_y_deg, fly.camera.near, fly.camera.far), (60.0, 0.1, 100.0));
        }
    }

    #[test]
    fn moves_at_its_speed_in_view_space() {
        let mut fly = Fly::new(cam(Vec3::ZERO, Vec3::NEG_Z), 2.0);
        fly.advance(Move { forward: 1.0, ..Default::default() }, 0.5);
        assert!(close(fly.camera.eye, Vec3::new(0.0, 0.0, -1.0)));
        fly.advance(Move { right: 1.0, ..Default::default() }, 1.0);
        assert!(close(fly.camera.eye, Vec3::new(2.0, 0.0, -1.0)));
        fly.advance(Move { up: -1.0, ..Default::default() }, 1.0);
        assert!(close(fly.camera.eye, Vec3::new(2.0, -2.0, -1.0)));
        // The view direction moves with the eye.
        assert!(close(fly.camera.target - fly.camera.eye, Vec3::NEG_Z));
    }

    #[test]
    fn turning_never_looks_straight_up() {
        let mut fly = Fly::new(cam(Vec3::ZERO, Vec3::NEG_Z), 1.0);
        fly.turn(0.0, -1e6);
        let f = fly.forward();
        assert!(f.y > 0.99 && f.y < 1.0, "{f}");
        // Still a valid view: up is not parallel to the view direction.
        assert!(f.cross(fly.camera.up).length() > 1e-3);
        // Right turns to +X from -Z.
        let mut fly = Fly::new(cam(Vec3::ZERO, Vec3::NEG_Z), 1.0);
        fly.turn(std::f32::consts::FRAC_PI_2 / LOOK_SENSITIVITY, 0.0);
        assert!(close(fly.forward(), Vec3::X), "{}", fly.forward());
    }

    #[test]
    fn wheel_scales_speed_within_bounds() {
        let mut fly = Fly::new(cam(Vec3::ZERO, Vec3::NEG_Z), 1.0);
        fly.change_speed(1.0);
        assert!((fly.speed - 1.25).abs() < 1e-6);
        fly.change_speed(-1.0);
        assert!((fly.speed - 1.0).abs() < 1e-6);
        fly.change_speed(1000.0);
        assert_eq!(fly.speed, 1e3);
        fly.change_speed(-1000.0);
        assert!((fly.speed - 1e-3).abs() < 1e-9);
    }
}
