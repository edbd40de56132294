//! A loaded scene on the GPU with its camera path and BVH: what `bench`,
//! `render` and the tests drive methods through, frame by frame.

use std::path::Path;

use crate::bvh::{Bvh, Split};
use crate::cull::{self, noc::NoCulling, Culler, Frame, MethodOptions, SceneContext};
use crate::error::Result;
use crate::gpu::{Gpu, GpuTimer};
use crate::render::{layout::DrawCommand, DrawList, Renderer};
use crate::scene::{camera::clip_planes, Camera, CameraPath, Scene};

pub struct Session<'g> {
    pub gpu: &'g Gpu,
    pub scene: Scene,
    pub bvh: Bvh,
    pub renderer: Renderer,
    pub cameras: Vec<Camera>,
    /// Camera-path time of each frame (`Frame::path_time`).
    pub times: Vec<f32>,
    /// Parameters handed to the methods `create` builds.
    pub options: MethodOptions,
    timer: GpuTimer,
}

/// `noc`'s picture of one frame: the ground truth every method is checked against.
pub struct Truth {
    /// Objects that own at least one pixel of the ID target, sorted.
    pub visible: Vec<u32>,
    pub depth: Vec<f32>,
}

/// One method's frame, measured.
pub struct FrameResult {
    pub wall_ms: f64,
    pub stages: Vec<(&'static str, f64)>,
    pub lists: Vec<DrawList>,
}

impl FrameResult {
    pub fn gpu_ms(&self) -> f64 {
        self.stages.iter().map(|s| s.1).sum()
    }
}

/// Correctness of one frame against the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Check {
    pub drawn: usize,
    pub false_negatives: usize,
    pub missing_pixels: usize,
}

impl<'g> Session<'g> {
    /// `path` overrides the scene's own camera path.
    pub fn new(gpu: &'g Gpu, mut scene: Scene, path: Option<CameraPath>, frames: usize, (w, h): (u32, u32), split: Split) -> Result<Self> {
        if let Some(p) = path {
            scene.path = p;
        }
        scene.validate()?;
        let (near, far) = clip_planes(&scene.bounds(), &scene.path);
        let cameras = scene.path.frames(frames.max(1), near, far);
        let times = scene.path.frame_times(frames.max(1));
        let boxes: Vec<_> = scene.objects.iter().map(|o| o.bounds).collect();
        let bvh = Bvh::build(&boxes, split);
        let renderer = Renderer::new(gpu, &scene, w, h)?;
        Ok(Session { gpu, scene, bvh, renderer, cameras, times, options: MethodOptions::default(), timer: GpuTimer::new(gpu, 64) })
    }

    pub fn load(gpu: &'g Gpu, spec: &str, objects: Option<usize>, camera_path: Option<&Path>, frames: usize, res: (u32, u32), split: Split) -> Result<Self> {
        let scene = crate::scene::load(spec, objects, 0)?;
        let path = camera_path.map(CameraPath::from_file).transpose()?;
        Self::new(gpu, scene, path, frames, res, split)
    }

    pub fn context(&self) -> SceneContext<'_> {
        SceneContext { gpu: self.gpu, scene: &self.scene, bvh: &self.bvh, renderer: &self.renderer, options: &self.options }
    }

    pub fn create(&self, method: &str) -> Result<Box<dyn Culler>> {
        cull::create(method, &self.context())
    }

    /// Runs one frame of `culler` at camera `k`, timed from the camera
    /// upload to the GPU's completion.
    pub fn run_frame(&mut self, culler: &mut dyn Culler, k: usize) -> Result<FrameResult> {
        let k = k.min(self.cameras.len() - 1);
        self.run_camera(culler, self.cameras[k], self.times[k])
    }

    /// Runs one frame of `culler` from any camera (the viewer's free
    /// flight), timed as [`run_frame`](Self::run_frame); `path_time` is the
    /// frame's [`Frame::path_time`].
    pub fn run_camera(&mut self, culler: &mut dyn Culler, camera: Camera, path_time: f32) -> Result<FrameResult> {
        let start = std::time::Instant::now();
        let mut f = Frame::begin(self.gpu, &self.renderer, &mut self.timer, camera, self.bvh.nodes.len() as u32);
        f.path_time = path_time;
        culler.frame(&mut f)?;
        let lists = f.finish()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let stages = self.timer.read(self.gpu)?;
        Ok(FrameResult { wall_ms, stages, lists })
    }

    /// Renders frame `k` with `noc` and reads back the truth.
    pub fn truth(&mut self, k: usize) -> Result<(FrameResult, Truth)> {
        let r = self.run_frame(&mut NoCulling, k)?;
        Ok((r, self.read_truth()?))
    }

    /// The truth of whatever the targets hold now.
    pub fn read_truth(&self) -> Result<Truth> {
        let ids: Vec<u32> = self.gpu.read_texture(&self.renderer.targets.id, wgpu::TextureAspect::All)?;
        let mut seen = vec![false; self.renderer.object_count as usize];
        for &id in &ids {
            if id > 0 {
                seen[(id - 1) as usize] = true;
            }
        }
        let visible = (0..seen.len() as u32).filter(|&o| seen[o as usize]).collect();
        Ok(Truth { visible, depth: self.read_depth()? })
    }

    pub fn read_depth(&self) -> Result<Vec<f32>> {
        self.gpu.read_texture(&self.renderer.targets.depth, wgpu::TextureAspect::DepthOnly)
    }

    /// Which objects the lists drew (non-empty commands within the GPU count).
    pub fn drawn(&self, lists: &[DrawList]) -> Result<Vec<bool>> {
        let mut drawn = vec![false; self.renderer.object_count as usize];
        for l in lists {
            let count = self.gpu.read::<u32>(&l.count, 0, 1)?[0].min(l.max_count);
            for c in self.gpu.read::<DrawCommand>(&l.commands, 0, count as u64)? {
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
    /// (visible in `noc`, not drawn) and missing pixels (depth farther than `noc`'s).
    pub fn check(&self, r: &FrameResult, truth: &Truth) -> Result<Check> {
        let drawn = self.drawn(&r.lists)?;
        let depth = self.read_depth()?;
        Ok(Check {
            drawn: drawn.iter().filter(|&&d| d).count(),
            false_negatives: truth.visible.iter().filter(|&&o| !drawn[o as usize]).count(),
            missing_pixels: depth.iter().zip(&truth.depth).filter(|(m, t)| m > t).count(),
        })
    }
}
