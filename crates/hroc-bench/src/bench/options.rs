//! What a bench run is asked for ([`BenchOptions`]), and the one check of it.

use std::path::PathBuf;

use super::Projection;
use crate::bvh::Split;
use crate::error::Result;
use hroc::Method;

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: String,
    pub objects: Option<usize>,
    pub methods: Vec<Method>,
    pub frames: usize,
    /// Frames per second of camera path (`--fps`): replaces `frames` with
    /// `fps × duration + 1`, so runs at 5, 30 and 60 sample the same path
    /// at a known rate.
    pub fps: Option<f32>,
    pub resolution: (u32, u32),
    pub split: Split,
    /// Split meshes into clusters of at most this many triangles, each a
    /// cullable object (`--clusters`; [`crate::scene::Scene::clustered`]).
    pub clusters: Option<u32>,
    /// Give the culler the rotated objects' oriented boxes
    /// (`--oriented-boxes`; [`Session::set_oriented_boxes`](super::Session::set_oriented_boxes)).
    pub oriented_boxes: bool,
    /// A camera path file, or a built-in path of the scene by name
    /// (`hard`, `cuts`: [`crate::scene::paths::builtin`]).
    pub camera_path: Option<PathBuf>,
    pub progress: bool,
    /// Fraction of the objects that move every frame (`--moving`), 0 to 1,
    /// each as its scene moves them ([`crate::scene::motion`]).
    pub moving: f32,
    /// Flag the moving objects [`hroc::ObjectFlags::DYNAMIC`] (HROC §6's
    /// hybrid) instead of refitting them into the BVH (`--dynamic`).
    pub dynamic: bool,
    /// Refit and rebuild policy (`--refit`, `--rebuild-growth`).
    pub motion: hroc::options::MotionOptions,
    /// Parameters of the methods (`--soq-base-time`, `--chc-*`).
    pub method_options: hroc::MethodOptions,
    /// Time every stage with GPU timestamps (`--breakdown`). Each stamp is a
    /// point the GPU must reach before the next command (on lavapipe, a
    /// flush of the rasterizer), which costs methods of many stages most:
    /// runs compare ms/frame without them.
    pub timestamps: bool,
    /// Samples per pixel of the camera's targets (`--msaa`; 1: none).
    pub msaa: u32,
    /// Cascades of a directional light's shadow map (`--shadow-cascades`,
    /// 0 to 4), each a view of its own culled by every method and checked
    /// against its own `noc` picture.
    pub shadow_cascades: u32,
    /// HROC's bar for the cascades' views, drawn depth only
    /// (`--hroc-frustum-triangles`; `MethodOptions::hroc_frustum_triangles`).
    pub shadow_triangles: f32,
    /// How the camera projects (`--projection`).
    pub projection: Projection,
    /// Validate every view's draws ([`hroc::CullerDesc::validation`],
    /// `--validate`): a finding fails the run. [`BenchOptions::new`]
    /// validates (the bench's tests run so); `hroc bench` only when asked,
    /// since validation adds passes to every frame.
    pub validate: bool,
}

impl BenchOptions {
    /// `hroc bench`'s defaults for `scene`, `objects` (the scene's own
    /// count when `None`) and `methods`: 60 frames at 640 × 360, SAH, no
    /// clusters, oriented boxes, the scene's own path, nothing moving, no
    /// timestamps; validation on.
    pub fn new(scene: &str, objects: Option<usize>, methods: Vec<Method>) -> BenchOptions {
        BenchOptions {
            scene: scene.to_string(),
            objects,
            methods,
            frames: 60,
            fps: None,
            resolution: (640, 360),
            split: Split::Sah,
            clusters: None,
            oriented_boxes: true,
            camera_path: None,
            progress: false,
            moving: 0.0,
            dynamic: false,
            motion: hroc::options::MotionOptions::default(),
            method_options: hroc::MethodOptions::default(),
            timestamps: false,
            msaa: 1,
            shadow_cascades: 0,
            shadow_triangles: hroc::options::DEPTH_ONLY_TRIANGLES,
            projection: Projection::Perspective,
            validate: true,
        }
    }
}

impl BenchOptions {
    /// The one check of the options a run takes: the fraction moving, the
    /// methods that take motion, the frame rate and the samples per pixel.
    /// [`super::run_scene`] makes it; a front end may make it before it
    /// loads anything.
    pub fn check(&self) -> Result<()> {
        let arg = |msg: String| Err(crate::Error::Options(msg));
        if !(0.0..=1.0).contains(&self.moving) {
            return arg(format!("--moving {} is not a fraction from 0 to 1", self.moving));
        }
        if self.moving > 0.0 {
            if let Some(m) = self.methods.iter().find(|m| !m.takes_motion()) {
                return arg(format!("{m} keeps its own copy of the BVH and takes static scenes only: drop it, or use --moving 0"));
            }
        }
        if let Some(fps) = self.fps.filter(|f| !(*f > 0.0 && *f <= 1000.0)) {
            return arg(format!("--fps {fps} is not a rate from 0 to 1000 frames per path second"));
        }
        super::session::check_samples(self.msaa)
    }
}
