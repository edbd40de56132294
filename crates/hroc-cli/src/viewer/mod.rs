//! `hroc view`: a window over a scene. The scene's camera path plays, or a
//! fly camera takes over; the method is switched live; an egui panel shows
//! per-stage GPU ms, C/N, the method's statistics and, on demand, false
//! negatives against `noc`.
//!
//! - [`app`]: the window, its event loop and the frame;
//! - [`fly`]: the free camera;
//! - [`ui`]: the panel.

pub mod app;
pub mod fly;
pub mod ui;

use std::path::PathBuf;

use hroc::Method;
use hroc_bench::bench::Session;
use hroc_bench::bvh::Split;
use hroc_bench::error::{Error, Result};
use hroc_bench::gpu::{Backend, Headless, Tier};
use hroc_bench::render::pictures::Picture;
use hroc_bench::scene::CameraPath;

/// Command-line options of `hroc view`.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// Built-in scene key or a .gltf/.glb/.obj path.
    #[arg(default_value = "radial-city")]
    pub scene: String,
    /// Object count of a generated scene (its default when omitted).
    #[arg(long)]
    pub objects: Option<usize>,
    /// Method to start with (switch live in the panel).
    #[arg(long, default_value_t = Method::HROC)]
    pub method: Method,
    /// Renders this many frames, then exits (smoke tests).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Saves the last frame to this PNG on exit: the current view at
    /// --resolution, without the panel (as the P key does).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Render resolution and initial window size (the picture is scaled to fit a resized window).
    #[arg(long, default_value = "960x540", value_parser = hroc_bench::bench::parse_resolution)]
    pub resolution: (u32, u32),
    /// View to start with (keys 1-4).
    #[arg(long, default_value_t = Picture::Color)]
    pub view: Picture,
    #[arg(long, default_value_t = Split::Sah)]
    pub split: Split,
    /// Clusters of at most T triangles, `off`, or `auto` (as `hroc bench`).
    #[arg(long, default_value = "auto", value_parser = crate::parse_clusters)]
    pub clusters: crate::Clusters,
    /// JSON camera path file (keys of t, eye, target, up, fov_y_deg).
    #[arg(long)]
    pub camera_path: Option<PathBuf>,
    /// Graphics API: `vulkan`, or `gl` (OpenGL).
    #[arg(long, default_value_t = Backend::Vulkan)]
    pub backend: Backend,
    /// What the culler runs with: `full`, `gl`, `dx12`, `portable` or `boxes` (as `hroc bench`);
    /// the most the device allows when omitted.
    #[arg(long)]
    pub tier: Option<Tier>,
}

/// Opens the window and runs until it is closed (or `--frames` are done).
pub fn run(args: ViewArgs) -> Result<()> {
    let method = Method::ALL.iter().position(|&m| m == args.method).unwrap_or_default();
    if args.frames == Some(0) {
        return Err(Error::Options("--frames must be at least 1".into()));
    }
    // Bad inputs fail before a window opens.
    let mut scene = hroc_bench::scene::load(&args.scene, args.objects, 0)?;
    if let Some(t) = args.clusters.triangles(&args.scene) {
        scene = scene.clustered(hroc_bench::scene::ClusterOptions::new(t))?;
    }
    let path = args.camera_path.as_deref().map(CameraPath::from_file).transpose()?;

    let event_loop = winit::event_loop::EventLoop::new().map_err(|e| {
        // winit prefixes its own source location; the reason is what helps.
        let text = e.to_string();
        let reason = text.strip_prefix("os error at ").and_then(|r| r.split_once(": ")).map_or(text.as_str(), |(_, why)| why);
        Error::NoAdapter(format!("no display: run under X11/Wayland or Xvfb ({reason})"))
    })?;
    let mut desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(event_loop.owned_display_handle()));
    desc.backends = args.backend.wgpu();
    let instance = wgpu::Instance::new(desc);
    let mut gpu = Headless::with_instance(&instance, args.backend)?;
    gpu.capabilities = args.tier.map(Tier::capabilities);
    let session = Session::new(&gpu, scene, path, 1, args.resolution, args.split)?;
    let opts = app::Options { method, view: args.view, frames: args.frames, screenshot: args.screenshot };
    let mut app = app::App::new(&instance, session, opts)?;
    event_loop.run_app(&mut app).map_err(|e| Error::Device(format!("event loop: {e}")))?;
    app.finish()
}
