//! A loaded scene on the GPU with its camera path and BVH: what `bench`,
//! `render` and the tests drive methods through, frame by frame.

use std::path::Path;

use crate::bvh::{Bvh, Split};
use crate::cull::{Method, MethodOptions, Stage};
use crate::error::Result;
use crate::gpu::Headless;
use crate::render::cascades::{self, CascadeRecorder, CascadeView, Cascades};
use crate::render::{DrawList, Recorder, Renderer};
use crate::scene::{camera::clip_planes, Camera, CameraPath, Scene};
use hroc::{Culler, CullerDesc, FrameInput, View, ViewDesc};

/// A scene on the GPU as a host would hold it: hroc's renderer, a
/// [`hroc::Culler`] over its objects, and the camera path. Every method runs
/// through the public API ([`View::cull`]), so the benchmark measures what
/// a user gets.
pub struct Session<'g> {
    pub gpu: &'g Headless,
    pub scene: Scene,
    pub culler: Culler,
    pub renderer: Renderer,
    pub cameras: Vec<Camera>,
    /// Camera-path time of each frame (`FrameInput::time`).
    pub times: Vec<f32>,
    /// Parameters handed to the methods `create` builds.
    pub options: MethodOptions,
    noc: Option<View>,
    /// The culler has the objects' oriented boxes ([`Session::set_oriented_boxes`]).
    oriented_boxes: bool,
    /// A directional light's shadow cascades ([`Session::set_shadow_cascades`]).
    shadows: Option<Shadows>,
    /// How the camera projects ([`Session::set_projection`]).
    projection: Projection,
}

/// How the bench's camera projects.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    /// The camera's perspective.
    #[default]
    Perspective,
    /// Parallel rays along the camera's view direction, through a box as
    /// wide and high as the perspective frustum is at the distance of the
    /// scene's centre, between the same near and far planes: the same
    /// path, seen as a directional light's cascade sees a scene.
    Orthographic,
}

impl std::str::FromStr for Projection {
    type Err = crate::Error;
    fn from_str(s: &str) -> Result<Projection> {
        match s {
            "perspective" => Ok(Projection::Perspective),
            "orthographic" => Ok(Projection::Orthographic),
            _ => Err(crate::Error::Arg(format!("--projection {s}: perspective or orthographic"))),
        }
    }
}

/// The light's cascades and their `noc` views.
struct Shadows {
    cascades: Cascades,
    noc: Vec<View>,
}

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
                *seen.get_mut(o as usize).ok_or_else(|| crate::Error::Gpu(format!("object ID {id} in noc's picture, of {objects} objects")))? = true;
            }
        }
        let visible = (0..objects).filter(|&o| seen[o as usize]).collect();
        Ok(Truth { visible, depth, ids })
    }
}

/// One method's frame, measured.
pub struct FrameResult {
    pub wall_ms: f64,
    pub stages: Vec<(Stage, f64)>,
    /// Shader invocations per stage (empty without pipeline statistics).
    pub invocations: Vec<(Stage, hroc::testing::gpu::Invocations)>,
    pub lists: Vec<DrawList>,
    /// The camera of a camera view's frame (`None`: a shadow cascade's).
    pub camera: Option<Camera>,
}

impl FrameResult {
    pub fn gpu_ms(&self) -> f64 {
        self.stages.iter().map(|s| s.1).sum()
    }

    /// Adds another view's frame to this one (the frame of a light's
    /// cascade to the camera's): its time, stages and invocations.
    pub fn add(&mut self, other: &FrameResult) {
        self.wall_ms += other.wall_ms;
        self.stages.extend(other.stages.iter().copied());
        self.invocations.extend(other.invocations.iter().copied());
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

impl<'g> Session<'g> {
    /// `path` overrides the scene's own camera path.
    /// Stages are timed with GPU timestamps.
    pub fn new(gpu: &'g Headless, scene: Scene, path: Option<CameraPath>, frames: usize, res: (u32, u32), split: Split) -> Result<Self> {
        Self::new_timed(gpu, scene, path, frames, res, split, true)
    }

    /// [`Session::new`], with per-stage GPU timestamps or without; with
    /// them, also per-stage pipeline statistics where the device has them.
    pub fn new_timed(gpu: &'g Headless, scene: Scene, path: Option<CameraPath>, frames: usize, res: (u32, u32), split: Split, timestamps: bool) -> Result<Self> {
        Self::new_msaa(gpu, scene, path, frames, res, split, timestamps, 1)
    }

    /// [`Session::new_timed`] with targets of `samples` samples per pixel
    /// (MSAA above 1).
    #[allow(clippy::too_many_arguments)]
    pub fn new_msaa(
        gpu: &'g Headless,
        mut scene: Scene,
        path: Option<CameraPath>,
        frames: usize,
        (w, h): (u32, u32),
        split: Split,
        timestamps: bool,
        samples: u32,
    ) -> Result<Self> {
        if !matches!(samples, 1 | 4) {
            return Err(crate::Error::Arg(format!("--msaa {samples}: wgpu multisamples 4 times on every device (other counts need TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)")));
        }
        if let Some(p) = path {
            scene.path = p;
        }
        scene.validate()?;
        let (near, far) = clip_planes(&scene.bounds(), &scene.path);
        let cameras = scene.path.frames(frames.max(1), near, far);
        let times = scene.path.frame_times(frames.max(1));
        crate::render::check_limits(&scene, &gpu.limits())?;
        // The renderer's pipelines take the culler's marks layout, and the
        // culler takes the renderer's draws: build the objects first.
        let descs = crate::render::object_descs(&scene);
        let pipeline_statistics = timestamps && gpu.device.features().contains(hroc::PIPELINE_STATISTICS_FEATURES);
        let culler = Culler::new(&gpu.device, &gpu.queue, &CullerDesc { split, timestamps, pipeline_statistics, capabilities: gpu.capabilities, ..CullerDesc::new(&descs) })?;
        let renderer = Renderer::new(gpu, &scene, (w, h, samples), culler.marks_layout())?;
        let noc = culler.view(Method::Noc, &renderer.view_targets())?;
        Ok(Session {
            gpu,
            scene,
            culler,
            renderer,
            cameras,
            times,
            options: MethodOptions::default(),
            noc: Some(noc),
            oriented_boxes: true,
            shadows: None,
            projection: Projection::Perspective,
        })
    }

    /// Projects the camera as `projection` says from the next frame on.
    pub fn set_projection(&mut self, projection: Projection) {
        self.projection = projection;
    }

    /// The camera's projection, as [`Session::set_projection`] chose.
    pub fn proj(&self, camera: &Camera) -> glam::Mat4 {
        let aspect = self.renderer.aspect();
        match self.projection {
            Projection::Perspective => camera.proj(aspect),
            Projection::Orthographic => {
                let h = (camera.fov_y_deg.to_radians() * 0.5).tan() * self.scene.bounds().center().distance(camera.eye).max(camera.near);
                glam::Mat4::orthographic_rh(-h * aspect, h * aspect, -h, h, camera.near, camera.far)
            }
        }
    }

    /// Lights the scene with a directional light (the renderer's) whose
    /// shadow map has `count` cascades, each a view culled on its own
    /// ([`Session::cascades`]); 0 takes the light's shadows away.
    pub fn set_shadow_cascades(&mut self, count: u32) -> Result<()> {
        self.shadows = match count {
            0 => None,
            n => {
                let cascades = Cascades::new(self.gpu, &self.renderer, n)?;
                let noc = (0..n).map(|c| self.culler.view(Method::Noc, &cascades.view_targets(c))).collect::<hroc::Result<Vec<_>>>()?;
                Some(Shadows { cascades, noc })
            }
        };
        Ok(())
    }

    /// Cascades of the light's shadow map (0 without shadows).
    pub fn cascade_count(&self) -> u32 {
        self.shadows.as_ref().map_or(0, |s| s.cascades.count)
    }

    /// The cascades fitted to camera `k`.
    pub fn cascades(&self, k: usize) -> Vec<CascadeView> {
        let k = k.min(self.cameras.len() - 1);
        cascades::fit(&self.cameras[k], self.renderer.aspect(), self.renderer.light_dir, &self.scene.bounds(), self.cascade_count())
    }

    /// A view of cascade `c` culled by `method`, with [`Session::options`].
    pub fn create_cascade(&self, method: Method, c: u32) -> Result<View> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Arg("the session has no shadow cascades".into()))?;
        Ok(self.culler.view_with(method, &s.cascades.view_targets(c), &self.options)?)
    }

    /// Runs one frame of cascade `c` seen as `cascade` with `view`, timed
    /// as [`Session::run_frame`].
    pub fn run_cascade(&mut self, view: &mut View, c: u32, cascade: &CascadeView, time: f32) -> Result<FrameResult> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Arg("the session has no shadow cascades".into()))?;
        let start = std::time::Instant::now();
        s.cascades.write_view(self.gpu, c, cascade);
        let mut enc = self.gpu.encoder("cascade");
        s.cascades.clear(&mut enc, c);
        let input = FrameInput { view: cascade.view_desc(), targets: s.cascades.view_targets(c), cut: false, time };
        let mut host = CascadeRecorder { renderer: &self.renderer, cascades: &s.cascades, cascade: c, lists: Vec::new() };
        view.cull(&self.culler, &mut enc, &input, &mut host)?;
        let lists = host.lists;
        self.finish_frame(view, enc, start, lists, None)
    }

    /// Submits a view's frame recorded in `enc` and waits: the frame's
    /// result, timed from `start`.
    fn finish_frame(&self, view: &mut View, enc: wgpu::CommandEncoder, start: std::time::Instant, lists: Vec<DrawList>, camera: Option<Camera>) -> Result<FrameResult> {
        self.gpu.queue.submit([enc.finish()]);
        self.gpu.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let stages = view.stage_ms(&self.culler)?.to_vec();
        let invocations = view.stage_invocations(&self.culler)?;
        Ok(FrameResult { wall_ms, stages, invocations, lists, camera })
    }

    /// Renders cascade `c` seen as `cascade` with `noc`, and reads back its truth.
    pub fn cascade_truth(&mut self, c: u32, cascade: &CascadeView, time: f32) -> Result<(FrameResult, Truth)> {
        let s = self.shadows.as_mut().ok_or_else(|| crate::Error::Arg("the session has no shadow cascades".into()))?;
        let mut noc = std::mem::take(&mut s.noc);
        let r = self.run_cascade(&mut noc[c as usize], c, cascade, time);
        self.shadows.as_mut().expect("checked above").noc = noc;
        let r = r?;
        let s = self.shadows.as_ref().expect("checked above");
        let ids = self.gpu.read_ids(&s.cascades.ids[c as usize])?;
        let (texture, layer) = s.cascades.depth_of(c);
        let depth = self.gpu.read_depth_layer(texture, layer)?;
        Ok((r, Truth::of(ids, depth, self.renderer.object_count)?))
    }

    /// Checks cascade `c`'s frame just rendered against `truth` (every
    /// differing texel counts: the stray-fragment test is the camera's).
    pub fn check_cascade(&self, c: u32, r: &FrameResult, truth: &Truth) -> Result<Check> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Arg("the session has no shadow cascades".into()))?;
        let (texture, layer) = s.cascades.depth_of(c);
        let depth = self.gpu.read_depth_layer(texture, layer)?;
        self.check_with(r, truth, &depth, None)
    }

    pub fn load(gpu: &'g Headless, spec: &str, objects: Option<usize>, camera_path: Option<&Path>, frames: usize, res: (u32, u32), split: Split) -> Result<Self> {
        let scene = crate::scene::load(spec, objects, 0)?;
        let path = camera_path.map(CameraPath::from_file).transpose()?;
        Self::new(gpu, scene, path, frames, res, split)
    }

    /// Moves objects to new transforms: the scene's objects and their tight
    /// boxes (the host's work), the culler's boxes and BVH
    /// ([`hroc::Culler::set_bounds`]) and their oriented boxes where the
    /// session gives them, then the renderer's transforms.
    /// Returns the culler's part in ms: its CPU work plus the GPU's
    /// completion of its uploads (and refit), waited for here.
    pub fn move_objects(&mut self, moves: &[(u32, glam::Mat4)]) -> Result<f64> {
        let mut boxes = Vec::with_capacity(moves.len());
        for &(i, m) in moves {
            let Some(o) = self.scene.objects.get_mut(i as usize) else {
                return Err(crate::Error::Arg(format!("object {i} out of range")));
            };
            o.transform = m;
            o.bounds = self.scene.meshes[o.mesh as usize].part_bounds(o.cluster, &m);
            boxes.push((i, o.bounds));
        }
        // From the final transforms: an object may move twice in one call.
        let oriented: Vec<(u32, Option<hroc::OrientedBox>)> = if self.oriented_boxes {
            moves.iter().map(|&(i, _)| (i, crate::render::oriented_box(&self.scene, &self.scene.objects[i as usize]))).filter(|(_, b)| b.is_some()).collect()
        } else {
            Vec::new()
        };
        self.gpu.queue.submit([]);
        self.gpu.wait()?;
        let t = std::time::Instant::now();
        self.culler.set_bounds(&boxes)?;
        self.culler.set_oriented(&oriented)?;
        self.culler.flush();
        self.gpu.queue.submit([]);
        self.gpu.wait()?;
        let culler_ms = t.elapsed().as_secs_f64() * 1e3;
        let colors: Vec<[f32; 3]> = self.scene.objects.iter().map(|o| o.color).collect();
        self.renderer.set_transforms(self.gpu, moves, &colors);
        Ok(culler_ms)
    }

    /// Gives the culler every rotated object's box in its own frame
    /// ([`crate::render::oriented_box`], the default), or takes them all
    /// away, from the next frame on.
    pub fn set_oriented_boxes(&mut self, on: bool) -> Result<()> {
        let scene = &self.scene;
        let boxes: Vec<(u32, Option<hroc::OrientedBox>)> = (0..scene.objects.len() as u32)
            .filter(|&i| self.culler.is_live(i))
            .map(|i| (i, on.then(|| crate::render::oriented_box(scene, &scene.objects[i as usize])).flatten()))
            .collect();
        self.culler.set_oriented(&boxes)?;
        self.oriented_boxes = on;
        Ok(())
    }

    /// Removes scene objects from the culler (their slots draw nothing,
    /// for every view and for `noc`).
    pub fn remove_objects(&mut self, objects: &[u32]) -> Result<()> {
        Ok(self.culler.remove_objects(objects)?)
    }

    /// Adds removed scene objects back at new transforms. The culler hands
    /// free slots out lowest first, so objects added back in ascending
    /// order after their removal get their own slots again, which is what
    /// the renderer's per-object data needs; anything else is an error.
    pub fn add_objects(&mut self, adds: &[(u32, glam::Mat4)]) -> Result<()> {
        for &(i, m) in adds {
            let Some(o) = self.scene.objects.get_mut(i as usize) else {
                return Err(crate::Error::Arg(format!("object {i} out of range")));
            };
            o.transform = m;
            o.bounds = self.scene.meshes[o.mesh as usize].part_bounds(o.cluster, &m);
        }
        let all = crate::render::object_descs(&self.scene);
        let descs: Vec<hroc::ObjectDesc> =
            adds.iter().map(|&(i, _)| hroc::ObjectDesc { oriented: all[i as usize].oriented.filter(|_| self.oriented_boxes), ..all[i as usize] }).collect();
        let got = self.culler.add_objects(&descs)?;
        let want: Vec<u32> = adds.iter().map(|a| a.0).collect();
        if got != want {
            return Err(crate::Error::Arg(format!("objects {want:?} came back in slots {got:?}: add them in ascending order after removing them")));
        }
        let colors: Vec<[f32; 3]> = self.scene.objects.iter().map(|o| o.color).collect();
        self.renderer.set_transforms(self.gpu, adds, &colors);
        Ok(())
    }

    /// Sets an object's flags ([`hroc::ObjectFlags::DYNAMIC`] and the others).
    pub fn set_flags(&mut self, i: u32, flags: hroc::ObjectFlags) -> Result<()> {
        Ok(self.culler.set_flags(i, flags)?)
    }

    /// The object BVH the culler built.
    pub fn bvh(&self) -> &Bvh {
        self.culler.bvh()
    }

    /// A view of the scene culled by `method`, with [`Session::options`].
    pub fn create(&self, method: Method) -> Result<View> {
        Ok(self.culler.view_with(method, &self.renderer.view_targets(), &self.options)?)
    }

    /// Runs one frame of `view` at camera `k`, timed from the camera
    /// upload to the GPU's completion.
    pub fn run_frame(&mut self, view: &mut View, k: usize) -> Result<FrameResult> {
        let k = k.min(self.cameras.len() - 1);
        self.run_camera(view, self.cameras[k], self.times[k])
    }

    /// Runs one frame of `view` from any camera (the viewer's free
    /// flight), timed as [`run_frame`](Self::run_frame); `time` is the
    /// frame's [`FrameInput::time`].
    pub fn run_camera(&mut self, view: &mut View, camera: Camera, time: f32) -> Result<FrameResult> {
        self.run_camera_with(view, camera, time, false, None)
    }

    /// [`run_frame`](Self::run_frame) with a camera-cut signal
    /// ([`FrameInput::cut`]). The benchmark itself signals no cuts: methods
    /// are measured as they cope with them.
    pub fn run_frame_cut(&mut self, view: &mut View, k: usize, cut: bool) -> Result<FrameResult> {
        let k = k.min(self.cameras.len() - 1);
        self.run_camera_with(view, self.cameras[k], self.times[k], cut, None)
    }

    /// [`run_camera`](Self::run_camera) with `body` recorded in place of
    /// the method's frame ([`View::cull_with`]).
    pub fn run_camera_with(&mut self, view: &mut View, camera: Camera, time: f32, cut: bool, body: Option<hroc::testing::cull::FrameBody>) -> Result<FrameResult> {
        let start = std::time::Instant::now();
        let r = &self.renderer;
        r.write_view(self.gpu, &(self.proj(&camera) * camera.view()));
        let mut enc = self.gpu.encoder("frame");
        r.clear(&mut enc);
        let input = FrameInput { view: self.view_desc(&camera), targets: r.view_targets(), cut, time };
        let mut host = Recorder { renderer: r, lists: Vec::new() };
        match body {
            Some(body) => view.cull_with(&self.culler, &mut enc, &input, &mut host, body)?,
            None => view.cull(&self.culler, &mut enc, &input, &mut host)?,
        }
        let lists = host.lists;
        self.finish_frame(view, enc, start, lists, Some(camera))
    }

    /// The view of camera `camera` as the culler sees it.
    pub fn view_desc(&self, camera: &Camera) -> ViewDesc {
        ViewDesc { view: camera.view(), proj: self.proj(camera), depth: hroc::DepthRange::Standard, unclipped_depth: false }
    }

    /// The `Frame` uniform the culler writes for camera `k` (CPU references).
    pub fn frame_uniform(&self, k: usize) -> Result<hroc::testing::layout::FrameUniform> {
        let g = self.view_desc(&self.cameras[k]).geometry()?;
        Ok(g.uniform((self.renderer.targets.width, self.renderer.targets.height), self.renderer.object_count, self.bvh().nodes.len() as u32, hroc::DepthRange::Standard))
    }

    /// Renders frame `k` with `noc` and reads back the truth.
    pub fn truth(&mut self, k: usize) -> Result<(FrameResult, Truth)> {
        let mut noc = self.noc.take().expect("noc view");
        let r = self.run_frame(&mut noc, k);
        self.noc = Some(noc);
        let r = r?;
        Ok((r, self.read_truth()?))
    }

    /// Renders `camera` with `noc` (the viewer's free flight).
    pub fn truth_at(&mut self, camera: Camera, time: f32) -> Result<(FrameResult, Truth)> {
        let mut noc = self.noc.take().expect("noc view");
        let r = self.run_camera(&mut noc, camera, time);
        self.noc = Some(noc);
        let r = r?;
        Ok((r, self.read_truth()?))
    }

    /// The truth of whatever the targets hold now.
    pub fn read_truth(&self) -> Result<Truth> {
        let ids = self.gpu.read_ids(&self.renderer.targets.id)?;
        Truth::of(ids, self.read_depth()?, self.renderer.object_count)
    }

    pub fn read_depth(&self) -> Result<Vec<f32>> {
        Ok(self.gpu.read_depth(&self.renderer.targets.depth)?)
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
        let cpu = hroc::testing::cull::hroc::cpu::padded_px;
        let b = cpu(*bounds, eye, self.pixel, hroc::testing::cull::hroc::cpu::block_pad_px(1, self.samples));
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
