//! The window and its event loop. Each redraw runs one culler frame through
//! the session, then draws the frame's picture with the panel over it
//! (egui-wgpu) and presents.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use glam::Vec3;
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use super::fly::{Fly, Move};
use super::ui::{self, Action, Status, VIEWS};
use hroc::{Method, View};
use hroc_bench::bench::Session;
use hroc_bench::error::{Error, Result};
use hroc_bench::render::{pictures, pictures::Picture, DrawList};
use hroc_bench::scene::{Camera, Scene};

/// Path seconds per frame under `--frames`, so a run is deterministic.
const FIXED_DT: f32 = 1.0 / 30.0;
/// Longest real step: a stall (method switch, check) must not jump the path.
const MAX_DT: f32 = 0.25;
/// Tested boxes in the groups view: leaves and interior groups (as `hroc render`).
const LEAF_BOX: [u8; 4] = [255, 220, 0, 255];
const GROUP_BOX: [u8; 4] = [255, 40, 40, 255];

/// How `hroc view` was asked to start.
pub struct Options {
    /// Index into `METHODS`.
    pub method: usize,
    pub view: Picture,
    /// Frames to present before exiting; `None` runs until the window closes.
    pub frames: Option<u64>,
    /// Where the last of `frames` is saved.
    pub screenshot: Option<PathBuf>,
}

/// The window's resources, made once the event loop runs.
struct Display {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    egui: egui_winit::State,
    painter: egui_wgpu::Renderer,
    /// The renderer's colour target, shown as is in the colour view.
    color_tex: egui::TextureId,
    /// The other views' pixels, uploaded each frame.
    overlay: wgpu::Texture,
    overlay_tex: egui::TextureId,
}

pub struct App<'g> {
    instance: &'g wgpu::Instance,
    session: Session<'g>,
    culler: View,
    opts: Options,
    /// The viewer's state as the panel shows it (method, view, play, time...).
    status: Status,
    fly: Fly,
    /// Seconds since start, handed to methods as `FrameInput::time`: it
    /// keeps running while the path is paused or loops (`soq` expires by it).
    clock: f32,
    /// Movement keys held.
    keys: HashSet<KeyCode>,
    /// Right mouse button held: mouse motion turns the fly camera.
    looking: bool,
    check_next: bool,
    screenshot_next: bool,
    presented: u64,
    last: Option<Instant>,
    display: Option<Display>,
    error: Option<Error>,
}

impl<'g> App<'g> {
    pub fn new(instance: &'g wgpu::Instance, session: Session<'g>, opts: Options) -> Result<Self> {
        let culler = session.create(Method::ALL[opts.method])?;
        let scene = &session.scene;
        let st = scene.stats();
        let keys = &scene.path.keys;
        let path = (keys.first().map_or(0.0, |k| k.t), scene.path.duration());
        let status = Status {
            scene: format!("{}: {} objects, {} triangles", scene.name, st.objects, st.triangles),
            adapter: session.gpu.adapter_name(),
            objects: st.objects,
            method: opts.method,
            view: opts.view,
            playing: true,
            free: false,
            speed: 0.0,
            time: path.0,
            path,
            fps: 0.0,
            wall_ms: 0.0,
            stages: Vec::new(),
            drawn: 0,
            culled_by: Method::ALL[opts.method].name(),
            stats: Vec::new(),
            boxes: None,
            check: None,
            message: String::new(),
        };
        let fly = Fly::new(session.cameras[0], path_speed(scene));
        Ok(App {
            instance,
            session,
            culler,
            opts,
            status,
            fly,
            clock: 0.0,
            keys: HashSet::new(),
            looking: false,
            check_next: false,
            screenshot_next: false,
            presented: 0,
            last: None,
            display: None,
            error: None,
        })
    }

    /// The first error that stopped the event loop, if any.
    pub fn finish(self) -> Result<()> {
        self.error.map_or(Ok(()), Err)
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let gpu = self.session.gpu;
        let t = &self.session.renderer.targets;
        let attrs = Window::default_attributes().with_title(format!("hroc view: {}", self.session.scene.name)).with_inner_size(winit::dpi::PhysicalSize::new(t.width, t.height));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| Error::Device(format!("cannot open a window: {e}")))?);
        let surface = self.instance.create_surface(window.clone()).map_err(|e| Error::Device(format!("cannot draw into the window: {e}")))?;
        if !gpu.adapter.is_surface_supported(&surface) {
            return Err(Error::NoAdapter(format!("{} cannot present to this window", gpu.info.name)));
        }
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| Error::Device(format!("{} offers no format for this window", gpu.info.name)))?;
        // egui blends in gamma space and prefers a non-sRGB target.
        let formats = surface.get_capabilities(&gpu.adapter).formats;
        config.format = formats.iter().copied().find(|f| !f.is_srgb()).unwrap_or(config.format);
        // Frame rates measure the methods, not the display's refresh.
        config.present_mode = wgpu::PresentMode::AutoNoVsync;
        surface.configure(&gpu.device, &config);
        gpu.check()?;

        let ctx = egui::Context::default();
        let max_side = gpu.limits().max_texture_dimension_2d as usize;
        let egui = egui_winit::State::new(ctx, egui::ViewportId::ROOT, &window, Some(window.scale_factor() as f32), None, Some(max_side));
        let mut painter = egui_wgpu::Renderer::new(&gpu.device, config.format, egui_wgpu::RendererOptions::default());
        let color_tex = painter.register_native_texture(&gpu.device, &t.color_view, wgpu::FilterMode::Linear);
        let overlay = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("view"),
            size: wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let overlay_tex = painter.register_native_texture(&gpu.device, &overlay.create_view(&Default::default()), wgpu::FilterMode::Linear);
        window.request_redraw();
        self.display = Some(Display { window, surface, config, egui, painter, color_tex, overlay, overlay_tex });
        Ok(())
    }

    fn path_camera(&self) -> Camera {
        // Every camera of the session shares the scene's clip planes.
        let c = self.session.cameras[0];
        self.session.scene.path.sample(self.status.time, c.near, c.far)
    }

    fn camera(&self) -> Camera {
        if self.status.free {
            self.fly.camera
        } else {
            self.path_camera()
        }
    }

    /// Hands the view to the fly camera where the path is now, pausing it.
    fn take_over(&mut self) {
        if !self.status.free {
            self.fly.look_from(&self.path_camera());
            self.status.free = true;
            self.status.playing = false;
        }
    }

    fn movement(&self) -> Move {
        let axis = |pos, neg| (self.keys.contains(&pos) as i32 - self.keys.contains(&neg) as i32) as f32;
        Move { forward: axis(KeyCode::KeyW, KeyCode::KeyS), right: axis(KeyCode::KeyD, KeyCode::KeyA), up: axis(KeyCode::KeyE, KeyCode::KeyQ) }
    }

    /// Seconds to advance this frame; also updates the fps.
    fn step_time(&mut self) -> f32 {
        let now = Instant::now();
        let real = self.last.map_or(0.0, |l| (now - l).as_secs_f32());
        self.last = Some(now);
        if real > 0.0 {
            let fps = 1.0 / real as f64;
            self.status.fps = if self.status.fps == 0.0 { fps } else { 0.9 * self.status.fps + 0.1 * fps };
        }
        if self.opts.frames.is_some() {
            FIXED_DT
        } else {
            real.min(MAX_DT)
        }
    }

    fn advance(&mut self, dt: f32) {
        self.clock += dt;
        let m = self.movement();
        if !m.is_zero() {
            self.take_over();
            self.fly.advance(m, dt);
        }
        if self.status.playing {
            let (start, end) = self.status.path;
            let t = self.status.time + dt;
            self.status.time = if end > start && t > end { start + (t - start) % (end - start) } else { t.min(end.max(start)) };
        }
        self.status.speed = self.fly.speed;
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let dt = self.step_time();
        self.advance(dt);
        let last_frame = self.opts.frames.is_some_and(|n| self.presented + 1 >= n);
        let shot = std::mem::take(&mut self.screenshot_next);
        let camera = self.camera();
        let pixels = self.render_scene(&camera, shot || last_frame)?;
        if let Some(px) = &pixels {
            let (w, h) = (self.session.renderer.targets.width, self.session.renderer.targets.height);
            if let (true, Some(path)) = (last_frame, &self.opts.screenshot) {
                pictures::save_png(path, w, h, px)?;
            }
            if shot {
                // A failed interactive screenshot is reported, not fatal.
                let path = screenshot_name();
                self.status.message = match pictures::save_png(&path, w, h, px) {
                    Ok(()) => format!("saved {}", path.display()),
                    Err(e) => e.to_string(),
                };
            }
        }
        if self.present()? {
            self.presented += 1;
            if last_frame {
                event_loop.exit();
                return Ok(());
            }
        }
        if let Some(d) = &self.display {
            d.window.request_redraw();
        }
        Ok(())
    }

    /// Runs the method's frame at `camera` and updates the panel's numbers.
    /// Returns the current view's pixels when they were read back: for the
    /// views drawn on the CPU (uploaded for display here), and for colour
    /// only when `want_pixels` (screenshots).
    fn render_scene(&mut self, camera: &Camera, want_pixels: bool) -> Result<Option<Vec<[u8; 4]>>> {
        let gpu = self.session.gpu;
        let check = std::mem::take(&mut self.check_next);
        // `noc` first, when the frame is checked or the method (`ref`) needs its visible set.
        let truth = if check || self.culler.wants_oracle() { Some(self.session.truth_at(*camera, self.clock)?.1) } else { None };
        if let (true, Some(t)) = (self.culler.wants_oracle(), &truth) {
            self.culler.set_oracle(&self.session.culler, &t.visible)?;
        }
        let r = self.session.run_camera(&mut self.culler, *camera, self.clock)?;
        self.status.wall_ms = r.wall_ms;
        self.status.stages = r.stages.iter().map(|(s, ms)| (s.name(), *ms)).collect();
        self.status.stats = self.culler.stats(&self.session.culler)?.into_iter().filter(|(s, _)| *s != hroc::stats::Stat::Chosen).map(|(s, v)| (s.name(), v)).collect();
        self.status.culled_by = self.culler.culled_by().name();
        match (check, &truth) {
            (true, Some(t)) => {
                let c = self.session.check(&r, t)?;
                self.status.drawn = c.drawn;
                let at = if self.status.free { format!("free camera at {:.1?}", camera.eye.to_array()) } else { format!("t = {:.2} s", self.status.time) };
                self.status.check = Some((format!("{} at {at}", Method::ALL[self.status.method]), c));
            }
            _ => self.status.drawn = self.session.drawn(&r.lists)?.iter().filter(|&&d| d).count(),
        }
        let nodes = if self.status.view == Picture::Groups { self.culler.tested_nodes(&self.session.culler)? } else { None };
        self.status.boxes = nodes.as_ref().map(Vec::len);
        if self.status.view == Picture::Color && !want_pixels {
            return Ok(None);
        }
        let px = self.picture(&r.lists, camera, nodes.as_deref())?;
        if let (false, Some(d)) = (self.status.view == Picture::Color, &self.display) {
            let t = &self.session.renderer.targets;
            gpu.queue.write_texture(
                d.overlay.as_image_copy(),
                bytemuck::cast_slice(&px),
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * t.width), rows_per_image: Some(t.height) },
                wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
            );
        }
        Ok(Some(px))
    }

    /// RGBA8 pixels of the current view of the frame just drawn.
    fn picture(&self, lists: &[DrawList], camera: &Camera, nodes: Option<&[u32]>) -> Result<Vec<[u8; 4]>> {
        let (gpu, r, bvh) = (self.session.gpu, &self.session.renderer, &self.session.bvh());
        if self.status.view != Picture::Groups {
            return pictures::capture(gpu, r, self.status.view, lists);
        }
        let mut px = pictures::capture(gpu, r, Picture::Color, lists)?;
        if let Some(nodes) = nodes {
            let boxes: Vec<_> = nodes.iter().map(|&n| (bvh.aabb(n), if bvh.is_leaf(n) { LEAF_BOX } else { GROUP_BOX })).collect();
            pictures::draw_boxes(&mut px, (r.targets.width, r.targets.height), &camera.view_proj(r.aspect()), &boxes);
        }
        Ok(px)
    }

    /// Draws the picture and the panel into the window and presents.
    /// False when the window had no image to draw into this time.
    fn present(&mut self) -> Result<bool> {
        let gpu = self.session.gpu;
        let Some(d) = self.display.as_mut() else {
            return Ok(false);
        };
        let (frame, suboptimal) = match d.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => (t, false),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => (t, true),
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(false),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                d.surface.configure(&gpu.device, &d.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                gpu.check()?;
                return Err(Error::Device("the window's surface failed validation".into()));
            }
        };

        let texture = if self.status.view == Picture::Color { d.color_tex } else { d.overlay_tex };
        let aspect = self.session.renderer.aspect();
        let status = &self.status;
        let mut actions = Vec::new();
        let ctx = d.egui.egui_ctx().clone();
        let out = ctx.run_ui(d.egui.take_egui_input(&d.window), |ui| {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            ui.painter().image(texture, fit(ui.max_rect(), aspect), uv, egui::Color32::WHITE);
            actions.extend(ui::panel(ui.ctx(), status));
        });
        d.egui.handle_platform_output(&d.window, out.platform_output);
        let prims = ctx.tessellate(out.shapes, out.pixels_per_point);
        for (id, deltas) in &out.textures_delta.set {
            for delta in deltas {
                d.painter.update_texture(&gpu.device, &gpu.queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor { size_in_pixels: [d.config.width, d.config.height], pixels_per_point: out.pixels_per_point };
        let mut enc = gpu.encoder("panel");
        let callbacks = d.painter.update_buffers(&gpu.device, &gpu.queue, &mut enc, &prims, &screen);
        let view = frame.texture.create_view(&Default::default());
        {
            let mut pass = enc
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("panel"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.08, g: 0.08, b: 0.08, a: 1.0 }), store: wgpu::StoreOp::Store },
                    })],
                    ..Default::default()
                })
                .forget_lifetime();
            d.painter.render(&mut pass, &prims, &screen);
        }
        gpu.queue.submit(callbacks.into_iter().chain([enc.finish()]));
        gpu.queue.present(frame);
        for id in &out.textures_delta.free {
            d.painter.free_texture(id);
        }
        if suboptimal {
            d.surface.configure(&gpu.device, &d.config);
        }
        gpu.check()?;
        for a in actions {
            self.apply(a);
        }
        Ok(true)
    }

    fn apply(&mut self, action: Action) {
        let st = &mut self.status;
        match action {
            Action::Method(i) => match self.session.create(Method::ALL[i]) {
                Ok(c) => {
                    self.culler = c;
                    st.method = i;
                    st.check = None;
                    st.message.clear();
                }
                // A method this scene or device cannot run leaves the current one.
                Err(e) => st.message = format!("{}: {e}", Method::ALL[i]),
            },
            Action::View(v) => st.view = v,
            Action::Play(p) => {
                st.playing = p;
                // Playing resumes the path where it was left.
                if p {
                    st.free = false;
                }
            }
            Action::Seek(t) => {
                st.time = t;
                st.free = false;
            }
            Action::Check => self.check_next = true,
            Action::Screenshot => self.screenshot_next = true,
        }
    }

    /// Movement keys are held state; the rest are actions on press.
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode, pressed: bool, repeat: bool) -> Option<Action> {
        use KeyCode as K;
        if matches!(code, K::KeyW | K::KeyA | K::KeyS | K::KeyD | K::KeyE | K::KeyQ) {
            if pressed {
                self.keys.insert(code);
            } else {
                self.keys.remove(&code);
            }
            return None;
        }
        if !pressed || repeat {
            return None;
        }
        let n = Method::ALL.len();
        let m = self.status.method;
        match code {
            K::Space => Some(Action::Play(!self.status.playing)),
            K::Digit1 | K::Digit2 | K::Digit3 | K::Digit4 => {
                let i = [K::Digit1, K::Digit2, K::Digit3, K::Digit4].iter().position(|&k| k == code)?;
                Some(Action::View(VIEWS[i].0))
            }
            K::KeyM => Some(Action::Method((m + 1) % n)),
            K::KeyN => Some(Action::Method((m + n - 1) % n)),
            K::F12 | K::KeyP => Some(Action::Screenshot),
            K::Escape => {
                event_loop.exit();
                None
            }
            _ => None,
        }
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.display.is_none() {
            if let Err(e) = self.open(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(d) = self.display.as_mut() else {
            return;
        };
        // egui sees every event first; what it uses (clicks on the panel) stops here.
        let consumed = d.egui.on_window_event(&d.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) if size.width > 0 && size.height > 0 => {
                d.config.width = size.width;
                d.config.height = size.height;
                d.surface.configure(&self.session.gpu.device, &d.config);
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            // Releases always count, so no key stays held.
            WindowEvent::KeyboardInput { event: KeyEvent { physical_key: PhysicalKey::Code(code), state, repeat, .. }, .. } if !(consumed && state.is_pressed()) => {
                if let Some(a) = self.key(event_loop, code, state.is_pressed(), repeat) {
                    self.apply(a);
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Right, .. } => self.looking = state.is_pressed() && !consumed,
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.fly.change_speed(notches);
            }
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.looking = false;
            }
            _ => {}
        }
    }

    fn device_event(&mut self, _event_loop: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        // Raw motion: looking keeps working when the cursor reaches the window's edge.
        if let (true, DeviceEvent::MouseMotion { delta: (dx, dy) }) = (self.looking, event) {
            self.take_over();
            self.fly.turn(dx as f32, dy as f32);
        }
    }
}

/// The camera path's mean eye speed (the fly camera's default), or a
/// fiftieth of the scene's diagonal per second for a path that stands still.
fn path_speed(scene: &Scene) -> f32 {
    let keys = &scene.path.keys;
    let length: f32 = keys.windows(2).map(|k| Vec3::from(k[1].eye).distance(Vec3::from(k[0].eye))).sum();
    let duration = scene.path.duration() - keys.first().map_or(0.0, |k| k.t);
    if length > 0.0 && duration > 0.0 {
        length / duration
    } else {
        scene.bounds().extent().length() / 50.0
    }
}

/// The largest rectangle of `aspect` centred in `screen`.
fn fit(screen: egui::Rect, aspect: f32) -> egui::Rect {
    let size = if screen.aspect_ratio() > aspect { egui::vec2(screen.height() * aspect, screen.height()) } else { egui::vec2(screen.width(), screen.width() / aspect) };
    egui::Rect::from_center_size(screen.center(), size)
}

/// `hroc-YYYYMMDD-HHMMSS-mmm.png` (UTC) in the current directory.
fn screenshot_name() -> PathBuf {
    let t = SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or_default();
    let s = t.as_secs();
    let (y, m, d) = hroc_bench::bench::civil_from_days((s / 86_400) as i64);
    PathBuf::from(format!("hroc-{y:04}{m:02}{d:02}-{:02}{:02}{:02}-{:03}.png", s / 3600 % 24, s / 60 % 60, s % 60, t.subsec_millis()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_fit_inside_the_window() {
        let wide = fit(egui::Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(400.0, 100.0)), 2.0);
        assert_eq!((wide.min, wide.max), (egui::pos2(100.0, 0.0), egui::pos2(300.0, 100.0)));
        let tall = fit(egui::Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(100.0, 400.0)), 2.0);
        assert_eq!((tall.min, tall.max), (egui::pos2(0.0, 175.0), egui::pos2(100.0, 225.0)));
    }
}
