//! The headless comparison: a glTF scene written by `hroc scene export`,
//! loaded through Bevy's glTF loader (each object a Bevy mesh entity), its
//! camera path (`--path-out`) replayed at a fixed rate under a directional
//! light's shadow cascades, in one run per mode: no culling, Bevy's
//! frustum culling, Bevy's `OcclusionCulling`, and the plugin with `hroc`,
//! `hzb` and `auto`. Per mode: objects drawn per frame (read from Bevy's
//! indirect arguments of the main opaque pass), C/R (culled over the
//! objects that own no pixel of the unculled ID image), ms per frame (the
//! frame's update and its GPU work), and pixels and objects that differ
//! from drawing everything.
//!
//! `cargo run --release -p hroc-bevy --ignore-rust-version --example compare -- scene.glb path.json [frames] [msaa] [WxH]`
//!
//! Environment: `MODES` (comma-separated ends of mode names, e.g.
//! `OcclusionCulling,hroc`; all when unset), `SHADOWS=0` (no light),
//! `CASCADES=0` (the light's cascades culled by the frustum in every
//! mode; else by occlusion wherever the camera is: Bevy's
//! `OcclusionCulling` on the light, the plugin's `HrocCulling::cascades`),
//! `POINT_LIGHTS=n` (n point lights casting shadows along the camera
//! path, 1.5 above its eye every `frames / n` frames: culled per cube face
//! by the frustum in Bevy's modes, by the plugin's method in its modes
//! (`HrocCulling` on the light) unless `CASCADES=0`; CPU clustering in
//! every mode, as Bevy's GPU
//! clustering lights a frame from statistics read back as timing allows),
//! `REPEATS=n` (every mode run n times in turn, ms the median),
//! `TIMES_ONLY=1` (no ID and reference runs: drawn and ms only),
//! `VALIDATE=1` (the plugin's modes validate Bevy's passes,
//! `HrocValidation`, and their findings are listed after the table).

use std::path::Path;

use bevy::camera::visibility::NoFrustumCulling;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::gltf::{Gltf, GltfMesh, GltfNode};
use bevy::prelude::*;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::texture::GpuImage;
use bevy::render::{RenderApp, RenderDebugFlags};
use hroc::Method;
use hroc_bevy::{HrocCulling, HrocFindings, HrocPlugin, HrocValidation};
use hroc_scene::camera::{Camera as PathCamera, CameraPath};

#[path = "common/drawn.rs"]
mod drawn;
#[path = "../tests/common/headless.rs"]
mod headless;
use drawn::drawn;

#[derive(Clone, Copy, PartialEq, Debug)]
enum Mode {
    /// Unlit, one colour per object, nothing culled: which objects own a pixel.
    Ids,
    NoCulling,
    Frustum,
    Bevy,
    Plugin(Method),
}

impl Mode {
    fn name(self) -> String {
        match self {
            Mode::Ids => "ids".into(),
            Mode::NoCulling => "no culling".into(),
            Mode::Frustum => "Bevy frustum".into(),
            Mode::Bevy => "Bevy OcclusionCulling".into(),
            Mode::Plugin(m) => format!("hroc-bevy {m}"),
        }
    }
}

#[derive(Resource, Clone)]
struct Setup {
    mode: Mode,
    scene: String,
    target: Handle<Image>,
    msaa: Msaa,
    /// A directional light with shadow cascades.
    shadows: bool,
    /// Its cascades culled by occlusion in the modes that cull the camera
    /// by occlusion (Bevy's `OcclusionCulling` on the light, the plugin's
    /// `HrocCulling::cascades`); else by the frustum.
    cascades: bool,
    /// The plugin validates Bevy's passes.
    validate: bool,
    /// Point lights casting shadows, where.
    point_lights: Vec<Vec3>,
}

/// One mode's frames: images, objects drawn, ms.
#[derive(Clone)]
struct Run {
    images: Vec<Vec<u32>>,
    drawn: Vec<u64>,
    ms: Vec<f64>,
    /// What the plugin's validation found (with `VALIDATE=1`).
    findings: Vec<String>,
}

fn app(setup: &Setup, dir: &Path, size: (u32, u32)) -> App {
    let mut app = App::new();
    app.add_plugins(headless::plugins(RenderDebugFlags::ALLOW_COPIES_FROM_INDIRECT_PARAMETERS, Some(dir.to_string_lossy().into_owned())));
    if let Mode::Plugin(_) = setup.mode {
        app.add_plugins(HrocPlugin).insert_resource(HrocValidation(setup.validate));
    }
    app.insert_resource(bevy::light::DirectionalLightShadowMap { size: 1024 }).insert_resource(bevy::light::PointLightShadowMap { size: 256 });
    let mut image = Image::new_target_texture(size.0, size.1, TextureFormat::Rgba8Unorm, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.insert_resource(Setup { target, ..setup.clone() });
    app.add_systems(Startup, spawn);
    app.add_systems(Update, (spawn_scene, prepare_meshes).chain());
    headless::start(&mut app);
    if !setup.point_lights.is_empty() {
        app.world_mut().resource_mut::<bevy::light::cluster::GlobalClusterSettings>().gpu_clustering = None;
    }
    app
}

fn spawn(mut commands: Commands, setup: Res<Setup>, server: Res<AssetServer>) {
    let mut camera =
        commands.spawn((Camera3d::default(), RenderTarget::Image(setup.target.clone().into()), setup.msaa, Tonemapping::None, DebandDither::Disabled, Transform::default()));
    match setup.mode {
        Mode::Ids => {
            camera.insert((Hdr, Msaa::Off));
        }
        Mode::Bevy => {
            camera.insert((DepthPrepass, OcclusionCulling));
        }
        Mode::Plugin(method) => {
            camera.insert((DepthPrepass, OcclusionCulling, HrocCulling { method, cascades: setup.cascades }));
        }
        Mode::NoCulling | Mode::Frustum => {}
    }
    if setup.mode != Mode::Ids && setup.shadows {
        let mut light = commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::from_xyz(0.3, 1.0, 0.4).looking_at(Vec3::ZERO, Vec3::Y)));
        // Bevy's switch for culling a light's shadows by occlusion, as the
        // plugin's cascades are.
        if setup.mode == Mode::Bevy && setup.cascades {
            light.insert(OcclusionCulling);
        }
    }
    for &at in setup.point_lights.iter().filter(|_| setup.mode != Mode::Ids) {
        let mut light = commands.spawn((PointLight { shadow_maps_enabled: true, intensity: 4.0e6, range: 60.0, ..default() }, Transform::from_translation(at)));
        if let (Mode::Plugin(method), true) = (setup.mode, setup.cascades) {
            light.insert(HrocCulling::new(method));
        }
    }
    commands.insert_resource(SceneFile(server.load(setup.scene.clone())));
}

/// The glTF file, as Bevy's loader read it.
#[derive(Resource)]
struct SceneFile(Handle<Gltf>);

/// Once loaded: one mesh entity per primitive of every node, at the node's
/// transform (the export's nodes are at the root), with Bevy's standard
/// material.
fn spawn_scene(
    mut done: Local<bool>,
    mut commands: Commands,
    file: Option<Res<SceneFile>>,
    gltfs: Res<Assets<Gltf>>,
    nodes: Res<Assets<GltfNode>>,
    meshes: Res<Assets<GltfMesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let Some(gltf) = file.as_ref().and_then(|f| gltfs.get(&f.0)) else { return };
    if *done {
        return;
    }
    let material = materials.add(StandardMaterial { base_color: Color::srgb(0.7, 0.7, 0.72), perceptual_roughness: 0.8, ..default() });
    for node in gltf.nodes.iter().filter_map(|h| nodes.get(h)) {
        let Some(mesh) = node.mesh.as_ref().and_then(|m| meshes.get(m)) else { continue };
        for primitive in &mesh.primitives {
            commands.spawn((Mesh3d(primitive.mesh.clone()), MeshMaterial3d(material.clone()), node.transform));
        }
    }
    *done = true;
}

/// The meshes as each mode wants them: no frustum culling, or (ids) one
/// unlit colour per object, in entity order.
fn prepare_meshes(mut commands: Commands, setup: Res<Setup>, meshes: Query<Entity, (With<Mesh3d>, Without<NoFrustumCulling>)>, mut materials: ResMut<Assets<StandardMaterial>>) {
    if !matches!(setup.mode, Mode::NoCulling | Mode::Ids) {
        return;
    }
    let mut entities: Vec<Entity> = meshes.iter().collect();
    entities.sort();
    for (i, e) in entities.into_iter().enumerate() {
        let mut entity = commands.entity(e);
        entity.insert(NoFrustumCulling);
        if setup.mode == Mode::Ids {
            let id = i as u32 + 1;
            let channel = |shift: u32| ((id >> shift) & 0xff) as f32 / 255.0;
            let material = materials.add(StandardMaterial { base_color: Color::LinearRgba(LinearRgba::new(channel(0), channel(8), channel(16), 1.0)), unlit: true, ..default() });
            entity.insert(MeshMaterial3d(material));
        }
    }
}

fn set_camera(app: &mut App, c: &PathCamera) {
    let mut q = app.world_mut().query_filtered::<(&mut Transform, &mut Projection), With<Camera3d>>();
    let (mut t, mut p) = q.single_mut(app.world_mut()).unwrap();
    *t = Transform::from_translation(c.eye.to_array().into()).looking_at(c.target.to_array().into(), Vec3::from_array(c.up.to_array()));
    *p = Projection::Perspective(PerspectiveProjection { fov: c.fov_y_deg.to_radians(), near: c.near, far: c.far, ..default() });
}

/// What every mode's run shares.
struct Config<'a> {
    glb: &'a Path,
    cameras: &'a [PathCamera],
    msaa: Msaa,
    size: (u32, u32),
    shadows: bool,
    cascades: bool,
    validate: bool,
    point_lights: &'a [Vec3],
}

fn run(mode: Mode, c: &Config) -> Run {
    let (glb, cameras, size) = (c.glb, c.cameras, c.size);
    let msaa = if mode == Mode::Ids { Msaa::Off } else { c.msaa };
    let setup = Setup {
        mode,
        scene: glb.file_name().unwrap().to_string_lossy().into_owned(),
        target: Handle::default(),
        msaa,
        shadows: c.shadows,
        cascades: c.cascades,
        validate: c.validate,
        point_lights: c.point_lights.to_vec(),
    };
    let mut app = app(&setup, glb.parent().unwrap(), size);
    // Until the scene is spawned, steady, and the plugin culls.
    let mut last = (0, 0);
    app.update();
    for k in 0..600 {
        set_camera(&mut app, &cameras[0]);
        app.update();
        let n = app.world_mut().query::<&Mesh3d>().iter(app.world()).count();
        last = if n == last.0 { (n, last.1 + 1) } else { (n, 0) };
        let ready = !matches!(mode, Mode::Plugin(_)) || HrocPlugin::ready(&app);
        if n > 0 && last.1 >= 5 && ready && k > 10 {
            break;
        }
    }
    let target = app.world().resource::<Setup>().target.clone();
    let mut out = Run { images: Vec::new(), drawn: Vec::new(), ms: Vec::new(), findings: Vec::new() };
    for c in cameras {
        set_camera(&mut app, c);
        let start = std::time::Instant::now();
        app.update();
        let render = app.sub_app_mut(RenderApp).world_mut();
        let device = render.resource::<RenderDevice>().wgpu_device().clone();
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        out.ms.push(start.elapsed().as_secs_f64() * 1e3);
        let queue: wgpu::Queue = (**render.resource::<RenderQueue>()).clone();
        let texture = render.resource::<RenderAssets<GpuImage>>().get(&target).expect("the target on the GPU").texture.clone();
        out.images.push(hroc_readback::read_texture(&device, &queue, &texture, wgpu::TextureAspect::All).unwrap());
        out.drawn.push(drawn(render));
    }
    if c.validate {
        // The last frames' findings, once the GPU is done.
        app.update();
        let render = app.sub_app_mut(RenderApp).world_mut();
        out.findings = render.query::<&HrocFindings>().iter(render).flat_map(|f| f.0.iter().map(|f| f.finding.to_string())).collect();
    }
    out
}

/// The median of `v`.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let glb = Path::new(args.get(1).expect("a .glb written by hroc scene export")).canonicalize().expect("the scene file");
    let path = CameraPath::from_file(Path::new(args.get(2).expect("a camera path written by --path-out"))).expect("the camera path");
    let frames: usize = args.get(3).map_or(60, |s| s.parse().expect("frames"));
    let msaa = match args.get(4).map_or("1", String::as_str) {
        "4" => Msaa::Sample4,
        _ => Msaa::Off,
    };
    let size = args.get(5).and_then(|s| s.split_once('x')).map_or((320, 180), |(w, h)| (w.parse().unwrap(), h.parse().unwrap()));
    let env_on = |name: &str| std::env::var(name).map_or(true, |v| v != "0");
    let repeats: usize = std::env::var("REPEATS").ok().and_then(|s| s.parse().ok()).unwrap_or(1).max(1);
    let times_only = std::env::var("TIMES_ONLY").is_ok_and(|v| v != "0");
    let cameras = path.frames(frames, path.near.unwrap_or(0.1), path.far.unwrap_or(2000.0));
    let validate = std::env::var("VALIDATE").is_ok_and(|v| v != "0");
    let lights: usize = std::env::var("POINT_LIGHTS").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
    let point_lights: Vec<Vec3> = (0..lights)
        .map(|i| {
            let c = &cameras[i * frames / lights];
            Vec3::from_array(c.eye.to_array()) + 1.5 * Vec3::from_array(c.up.to_array()).normalize()
        })
        .collect();
    let config = Config { glb: &glb, cameras: &cameras, msaa, size, shadows: env_on("SHADOWS"), cascades: env_on("CASCADES"), validate, point_lights: &point_lights };
    let all = [Mode::NoCulling, Mode::Frustum, Mode::Bevy, Mode::Plugin(Method::HROC), Mode::Plugin(Method::Hzb), Mode::Plugin(Method::Auto)];
    let wanted = std::env::var("MODES").unwrap_or_default();
    let modes: Vec<Mode> = all.into_iter().filter(|m| wanted.is_empty() || wanted.split(',').any(|w| m.name().ends_with(w))).collect();
    // Which objects own a pixel, and the image of drawing everything.
    let reference = (!times_only).then(|| {
        let ids = run(Mode::Ids, &config);
        let objects = ids.drawn.iter().copied().max().unwrap_or(0);
        // Object id + 1 per pixel.
        let id_images: Vec<Vec<u32>> = ids.images.iter().map(|img| img.iter().map(|p| p & 0xff_ffff).collect()).collect();
        let visible: Vec<usize> = id_images.iter().map(|img| img.iter().filter(|&&i| i > 0).collect::<std::collections::BTreeSet<_>>().len()).collect();
        (objects, id_images, visible, run(Mode::NoCulling, &config))
    });
    let cascades = match (config.shadows, config.cascades) {
        (false, _) => "no shadows",
        (true, true) => "a directional light's 4 cascades culled by occlusion (Bevy's OcclusionCulling on the light, the plugin's cascades)",
        (true, false) => "a directional light's 4 cascades culled by the frustum",
    };
    println!("{} ({frames} frames at {}x{}, MSAA {}, {cascades}, {lights} point lights; ms: median of {repeats})", glb.display(), size.0, size.1, msaa.samples());
    println!("| mode | drawn/frame | C/R | ms/frame | false negatives | missing px |");
    println!("|---|--:|--:|--:|--:|--:|");
    let warm = 4.min(frames.saturating_sub(1));
    // Each repeat runs every mode in turn, so that a slow spell of the
    // machine falls on all of them.
    let mut runs: Vec<Vec<Run>> = modes.iter().map(|_| Vec::new()).collect();
    for r in 0..repeats {
        for (m, mode) in modes.iter().enumerate() {
            // The reference is the first run of drawing everything.
            let first_reference = (r == 0 && *mode == Mode::NoCulling).then(|| reference.as_ref().map(|(.., run)| run.clone())).flatten();
            runs[m].push(first_reference.unwrap_or_else(|| run(*mode, &config)));
        }
    }
    for (mode, runs) in modes.iter().zip(&runs) {
        let per_run: Vec<f64> = runs.iter().map(|r| r.ms[warm..].iter().sum::<f64>() / (frames - warm).max(1) as f64).collect();
        let (lo, hi) = per_run.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &m| (lo.min(m), hi.max(m)));
        let ms = match repeats {
            1 => format!("{:.1}", per_run[0]),
            _ => format!("{:.1} ({lo:.1}-{hi:.1})", median(per_run)),
        };
        let drawn = runs[0].drawn.iter().sum::<u64>() as f64 / frames as f64;
        let Some((objects, id_images, visible, reference)) = reference.as_ref() else {
            println!("| {} | {drawn:.0} | - | {ms} | - | - |", mode.name());
            continue;
        };
        let (mut missing, mut false_negatives, mut culled, mut hidden) = (0usize, 0usize, 0.0f64, 0.0f64);
        for r in runs {
            for ((image, expected), ids) in r.images.iter().zip(&reference.images).zip(id_images) {
                let wrong: std::collections::BTreeSet<u32> = image.iter().zip(expected).zip(ids).filter(|((a, b), _)| a != b).map(|(_, &id)| id).collect();
                missing += image.iter().zip(expected).filter(|(a, b)| a != b).count();
                false_negatives += wrong.len();
            }
        }
        for (&drawn, &visible) in runs[0].drawn.iter().zip(visible) {
            culled += *objects as f64 - drawn as f64;
            hidden += *objects as f64 - visible as f64;
        }
        println!("| {} | {drawn:.0} | {:.3} | {ms} | {false_negatives} | {missing} |", mode.name(), culled / hidden.max(1.0));
    }
    if validate {
        for (mode, runs) in modes.iter().zip(&runs).filter(|(m, _)| matches!(m, Mode::Plugin(_))) {
            let found: Vec<&String> = runs.iter().flat_map(|r| &r.findings).collect();
            println!("\n{}: validation on, {} findings in {} runs", mode.name(), found.len(), runs.len());
            for f in found {
                println!("- {f}");
            }
        }
    }
}
