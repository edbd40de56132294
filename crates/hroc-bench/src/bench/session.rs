//! A loaded scene on the GPU with its camera path and BVH: what `bench`,
//! `render` and the tests drive methods through, frame by frame.

use std::path::Path;

use super::check::Truth;
use crate::bvh::{Bvh, Split};
use crate::error::Result;
use crate::gpu::Headless;
use crate::render::cascades::{self, CascadeRecorder, CascadeView, Cascades};
use crate::render::{DrawList, Recorder, Renderer};
use crate::scene::{camera::clip_planes, Camera, CameraPath, Scene};
use hroc::stats::Stage;
use hroc::{Culler, CullerDesc, FrameInput, View, ViewDesc};
use hroc::{Method, MethodOptions};

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
    /// HROC's bar for the cascades' views, drawn depth only
    /// (`MethodOptions::hroc_frustum_triangles`; default
    /// [`hroc::options::DEPTH_ONLY_TRIANGLES`]).
    pub shadow_triangles: f32,
    noc: Option<View>,
    /// The culler has the objects' oriented boxes ([`Session::set_oriented_boxes`]).
    oriented_boxes: bool,
    /// A directional light's shadow cascades ([`Session::set_shadow_cascades`]).
    pub(super) shadows: Option<Shadows>,
    /// How the camera projects ([`Session::set_projection`]).
    pub(super) projection: Projection,
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
            _ => Err(crate::Error::Options(format!("--projection {s}: perspective or orthographic"))),
        }
    }
}

/// How a session's frame has its view culled: `view.cull(culler, encoder, input, host)`, or a stand-in.
pub type CullCall<'c> = dyn FnMut(&mut View, &Culler, &mut wgpu::CommandEncoder, &FrameInput, &mut dyn hroc::DrawHost) -> hroc::Result<()> + 'c;

/// What a [`Session`] is made of, besides its scene.
#[derive(Clone, Debug)]
pub struct SessionDesc {
    /// A camera path in place of the scene's own.
    pub path: Option<CameraPath>,
    /// Frames sampled over the path.
    pub frames: usize,
    /// The camera's targets, in pixels.
    pub resolution: (u32, u32),
    /// How the culler's BVH is built.
    pub split: Split,
    /// Per-stage GPU timestamps (and pipeline statistics where the device
    /// has them).
    pub timestamps: bool,
    /// Samples per pixel of the camera's targets: 1, or 4 for MSAA.
    pub samples: u32,
    /// The culler validates the host's draws ([`hroc::CullerDesc::validation`]),
    /// and the renderer declares its index buffer's size.
    pub validate: bool,
    /// What the culler runs with, in place of the device's
    /// ([`Headless::capabilities`]).
    pub capabilities: Option<hroc::device::Capabilities>,
}

impl SessionDesc {
    /// `frames` over the scene's own path at `resolution`: SAH, timestamps,
    /// one sample, validation on (every test of the bench validates; `hroc
    /// bench` validates with `--validate`).
    pub fn new(frames: usize, resolution: (u32, u32)) -> Self {
        SessionDesc { path: None, frames, resolution, split: Split::Sah, timestamps: true, samples: 1, validate: true, capabilities: None }
    }
}

/// Samples per pixel wgpu takes on every device: 1 or 4.
pub fn check_samples(samples: u32) -> Result<()> {
    match samples {
        1 | 4 => Ok(()),
        _ => Err(crate::Error::Options(format!(
            "--msaa {samples}: samples per pixel are 1 or 4 (wgpu multisamples 4 times on every device; other counts need TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)"
        ))),
    }
}

/// The light's cascades and their `noc` views.
pub(super) struct Shadows {
    pub(super) cascades: Cascades,
    noc: Vec<View>,
}

/// One method's frame, measured.
pub struct FrameResult {
    pub wall_ms: f64,
    pub stages: Vec<(Stage, f64)>,
    /// Shader invocations per stage (empty without pipeline statistics).
    pub invocations: Vec<(Stage, hroc::stats::Invocations)>,
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

impl<'g> Session<'g> {
    /// `path` overrides the scene's own camera path. Stages are timed
    /// with GPU timestamps, on single-sample targets.
    pub fn new(gpu: &'g Headless, scene: Scene, path: Option<CameraPath>, frames: usize, res: (u32, u32), split: Split) -> Result<Self> {
        Self::with(gpu, scene, SessionDesc { path, split, ..SessionDesc::new(frames, res) })
    }

    /// The session `desc` describes, over `scene`.
    pub fn with(gpu: &'g Headless, mut scene: Scene, desc: SessionDesc) -> Result<Self> {
        let SessionDesc { path, frames, resolution: (w, h), split, timestamps, samples, validate, capabilities } = desc;
        check_samples(samples)?;
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
        let pipeline_statistics = timestamps && gpu.device.features().contains(hroc::device::PIPELINE_STATISTICS_FEATURES);
        let index_count = validate.then(|| scene.meshes.iter().map(|m| m.indices.len() as u32).sum());
        let culler = Culler::new(
            &gpu.device,
            &gpu.queue,
            &CullerDesc { split, timestamps, pipeline_statistics, capabilities: capabilities.or(gpu.capabilities), validation: validate, index_count, ..CullerDesc::new(&descs) },
        )?;
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
            shadow_triangles: hroc::options::DEPTH_ONLY_TRIANGLES,
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

    /// A view of cascade `c` culled by `method`, with [`Session::options`]
    /// and [`Session::shadow_triangles`].
    pub fn create_cascade(&self, method: Method, c: u32) -> Result<View> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
        let options = hroc::MethodOptions { hroc_frustum_triangles: self.shadow_triangles, ..self.options.clone() };
        Ok(self.culler.view_with(method, &s.cascades.view_targets(c), &options)?)
    }

    /// Runs one frame of cascade `c` seen as `cascade` with `view`, timed
    /// as [`Session::run_frame`].
    pub fn run_cascade(&mut self, view: &mut View, c: u32, cascade: &CascadeView, time: f32) -> Result<FrameResult> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
        let start = std::time::Instant::now();
        s.cascades.write_view(self.gpu, c, cascade);
        let mut enc = self.gpu.encoder("cascade");
        s.cascades.clear(&mut enc, c);
        let input = FrameInput { view: cascade.view_desc(), cut: false, time };
        let mut host = CascadeRecorder { renderer: &self.renderer, cascades: &s.cascades, cascade: c, lists: Vec::new() };
        view.cull(&self.culler, &mut enc, &input, &mut host)?;
        let lists = host.lists;
        self.finish_frame(view, enc, start, lists, None)
    }

    /// Runs one frame of the light's cascades, `views[c]` culling cascade
    /// `c` seen as `cascades[c]`, as one set
    /// ([`hroc::Culler::cull_views`]) in one encoder, submitted and waited
    /// for: each cascade's result (the set's time in the first, its views'
    /// stages and invocations in each).
    pub fn run_cascades(&mut self, views: &mut [View], cascades: &[CascadeView], time: f32) -> Result<Vec<FrameResult>> {
        let s = self.shadows.as_ref().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
        let start = std::time::Instant::now();
        let mut enc = self.gpu.encoder("cascades");
        for (c, cascade) in cascades.iter().enumerate() {
            s.cascades.write_view(self.gpu, c as u32, cascade);
            s.cascades.clear(&mut enc, c as u32);
        }
        let mut hosts: Vec<CascadeRecorder> =
            (0..views.len()).map(|c| CascadeRecorder { renderer: &self.renderer, cascades: &s.cascades, cascade: c as u32, lists: Vec::new() }).collect();
        let mut set: Vec<(&mut View, FrameInput, &mut dyn hroc::DrawHost)> = views
            .iter_mut()
            .zip(cascades)
            .zip(hosts.iter_mut())
            .map(|((v, cascade), h)| (v, FrameInput { view: cascade.view_desc(), cut: false, time }, h as &mut dyn hroc::DrawHost))
            .collect();
        self.culler.cull_views(&mut enc, &mut set)?;
        drop(set);
        self.gpu.queue.submit([enc.finish()]);
        self.gpu.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let mut out = Vec::with_capacity(views.len());
        for (c, (view, host)) in views.iter_mut().zip(hosts).enumerate() {
            let stages = view.stage_ms(&self.culler)?.to_vec();
            let invocations = view.stage_invocations(&self.culler)?;
            out.push(FrameResult { wall_ms: if c == 0 { wall_ms } else { 0.0 }, stages, invocations, lists: host.lists, camera: None });
        }
        Ok(out)
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
        let s = self.shadows.as_mut().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
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

    /// Renders the cascades seen as `cascades` with `noc` (as one set,
    /// [`Session::run_cascades`]), and reads back each one's truth.
    pub fn cascade_truths(&mut self, cascades: &[CascadeView], time: f32) -> Result<Vec<(FrameResult, Truth)>> {
        let s = self.shadows.as_mut().ok_or_else(|| crate::Error::Options("the session has no shadow cascades".into()))?;
        let mut noc = std::mem::take(&mut s.noc);
        let r = self.run_cascades(&mut noc, cascades, time);
        self.shadows.as_mut().expect("checked above").noc = noc;
        let s = self.shadows.as_ref().expect("checked above");
        r?.into_iter()
            .enumerate()
            .map(|(c, r)| {
                let ids = self.gpu.read_ids(&s.cascades.ids[c])?;
                let (texture, layer) = s.cascades.depth_of(c as u32);
                let depth = self.gpu.read_depth_layer(texture, layer)?;
                Ok((r, Truth::of(ids, depth, self.renderer.object_count)?))
            })
            .collect()
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
                return Err(crate::Error::Options(format!("object {i} out of range")));
            };
            o.transform = m;
            o.bounds = self.scene.meshes[o.mesh as usize].part_bounds(o.cluster, &m);
            boxes.push((i, o.bounds));
        }
        // From the final transforms: an object may move twice in one call.
        let oriented: Vec<(u32, Option<hroc::geometry::OrientedBox>)> = if self.oriented_boxes {
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
        let boxes: Vec<(u32, Option<hroc::geometry::OrientedBox>)> = (0..scene.objects.len() as u32)
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
                return Err(crate::Error::Options(format!("object {i} out of range")));
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
            return Err(crate::Error::Options(format!("objects {want:?} came back in slots {got:?}: add them in ascending order after removing them")));
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
        self.run_camera_with(view, camera, time, false, &mut |view, culler, enc, input, host| view.cull(culler, enc, input, host))
    }

    /// [`run_frame`](Self::run_frame) with a camera-cut signal
    /// ([`FrameInput::cut`]). The benchmark itself signals no cuts: methods
    /// are measured as they cope with them.
    pub fn run_frame_cut(&mut self, view: &mut View, k: usize, cut: bool) -> Result<FrameResult> {
        let k = k.min(self.cameras.len() - 1);
        self.run_camera_with(view, self.cameras[k], self.times[k], cut, &mut |view, culler, enc, input, host| view.cull(culler, enc, input, host))
    }

    /// [`run_camera`](Self::run_camera) with the view's frame recorded by
    /// `cull` (for a test of a method's building blocks).
    pub fn run_camera_with(&mut self, view: &mut View, camera: Camera, time: f32, cut: bool, cull: &mut CullCall) -> Result<FrameResult> {
        let start = std::time::Instant::now();
        let r = &self.renderer;
        r.write_view(self.gpu, &(self.proj(&camera) * camera.view()));
        let mut enc = self.gpu.encoder("frame");
        r.clear(&mut enc);
        let input = FrameInput { view: self.view_desc(&camera), cut, time };
        let mut host = Recorder { renderer: r, lists: Vec::new() };
        cull(view, &self.culler, &mut enc, &input, &mut host)?;
        let lists = host.lists;
        self.finish_frame(view, enc, start, lists, Some(camera))
    }

    /// The view of camera `camera` as the culler sees it.
    pub fn view_desc(&self, camera: &Camera) -> ViewDesc {
        ViewDesc { view: camera.view(), proj: self.proj(camera), unclipped_depth: false }
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
        self.gpu.read_depth(&self.renderer.targets.depth)
    }
}
