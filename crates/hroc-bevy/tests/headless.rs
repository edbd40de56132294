//! Bevy on lavapipe, no window: a street of unlit cubes behind a wall,
//! each cube its own colour, drawn along a camera path (a walk, a cut, the
//! eye inside a box). Every frame of a camera culled by the plugin is the
//! image of drawing everything (no frustum or occlusion culling), pixel for
//! pixel, for `hroc`, `hzb` and `auto`; and the plugin culls.

use bevy::app::PluginsState;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::render::texture::GpuImage;
use bevy::render::{RenderApp, RenderPlugin};
use bevy::window::ExitCondition;
use hroc_bevy::{HrocCulling, HrocFrameStats, HrocPlugin};

const SIZE: (u32, u32) = (160, 90);

#[derive(Clone, Copy, PartialEq, Debug)]
enum Mode {
    /// No frustum culling, no occlusion culling.
    Everything,
    /// The plugin, with a method.
    Hroc(hroc::Method),
}

#[derive(Resource, Clone)]
struct Target(Handle<Image>);

fn app(mode: Mode) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin { primary_window: None, exit_condition: ExitCondition::DontExit, close_when_requested: false, ..default() })
            .set(RenderPlugin {
                render_creation: RenderCreation::Automatic(Box::new(WgpuSettings { backends: Some(Backends::VULKAN), ..default() })),
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>(),
    );
    if let Mode::Hroc(_) = mode {
        app.add_plugins(HrocPlugin);
    }
    let mut image = Image::new_target_texture(SIZE.0, SIZE.1, TextureFormat::Rgba8Unorm, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.insert_resource(Target(target));
    app.add_systems(Startup, move |commands: Commands, target: Res<Target>, meshes: ResMut<Assets<Mesh>>, materials: ResMut<Assets<StandardMaterial>>| {
        scene(mode, commands, &target, meshes, materials)
    });
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    app
}

/// The street's boxes: a wall, cubes before and behind it, a large box the
/// camera enters.
fn boxes() -> Vec<(Vec3, Vec3)> {
    let mut b = vec![(Vec3::new(-10.0, 0.0, -6.5), Vec3::new(10.0, 4.0, -6.0))];
    for x in (-8i32..=8).step_by(2) {
        for z in (-20..=0).step_by(3) {
            b.push((Vec3::new(x as f32 - 0.5, 0.0, z as f32 - 0.5), Vec3::new(x as f32 + 0.5, 1.0 + (x + z).rem_euclid(3) as f32, z as f32 + 0.5)));
        }
    }
    b.push((Vec3::new(-2.0, 0.0, 1.0), Vec3::new(2.0, 3.0, 4.0)));
    b
}

fn scene(mode: Mode, mut commands: Commands, target: &Target, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut camera = commands.spawn((
        Camera3d::default(),
        RenderTarget::Image(target.0.clone().into()),
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        DepthPrepass,
        Transform::default(),
    ));
    if let Mode::Hroc(method) = mode {
        camera.insert((OcclusionCulling, HrocCulling { method }));
    }
    let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    for (i, (lo, hi)) in boxes().into_iter().enumerate() {
        let k = i as u32 + 1;
        let colour = Color::LinearRgba(LinearRgba::new((k * 37 % 256) as f32 / 255.0, (k * 91 % 256) as f32 / 255.0, (k * 53 % 256) as f32 / 255.0, 1.0));
        let material = materials.add(StandardMaterial { base_color: colour, unlit: true, ..default() });
        let mut object = commands.spawn((Mesh3d(cube.clone()), MeshMaterial3d(material), Transform::from_translation((lo + hi) / 2.0).with_scale(hi - lo)));
        if mode == Mode::Everything {
            object.insert(NoFrustumCulling);
        }
    }
}

/// The camera path: a walk, a cut to above the wall, the eye inside the last box.
fn path() -> Vec<Transform> {
    let look = |eye: Vec3, at: Vec3| Transform::from_translation(eye).looking_at(at, Vec3::Y);
    let mut p: Vec<Transform> = (0..6).map(|k| look(Vec3::new(-3.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0))).collect();
    p.push(look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)));
    p.push(look(Vec3::new(0.0, 1.5, 2.5), Vec3::new(0.0, 1.0, -10.0)));
    p.push(look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)));
    p
}

/// Each frame's image along `path`, and what hroc drew (where it culls).
fn frames(mode: Mode, path: &[Transform]) -> Vec<(Vec<u32>, Option<u32>)> {
    let mut app = app(mode);
    let set_camera = |app: &mut App, t: Transform| {
        let mut q = app.world_mut().query_filtered::<&mut Transform, With<Camera3d>>();
        *q.single_mut(app.world_mut()).unwrap() = t;
    };
    // Until the plugin culls (Bevy's shader loads, pipelines compile).
    app.update();
    set_camera(&mut app, path[0]);
    for _ in 0..60 {
        app.update();
        if mode == Mode::Everything || HrocPlugin::ready(&app) {
            break;
        }
    }
    assert!(mode == Mode::Everything || HrocPlugin::ready(&app), "the plugin is not ready after 60 frames");
    let target = app.world().resource::<Target>().0.clone();
    path.iter()
        .map(|&t| {
            set_camera(&mut app, t);
            app.update();
            let render = app.sub_app_mut(RenderApp).world_mut();
            let texture = render.resource::<RenderAssets<GpuImage>>().get(&target).expect("the target on the GPU").texture.clone();
            let device = render.resource::<RenderDevice>().wgpu_device().clone();
            let queue: wgpu::Queue = (**render.resource::<RenderQueue>()).clone();
            let image: Vec<u32> = hroc_readback::read_texture(&device, &queue, &texture, wgpu::TextureAspect::All).unwrap();
            let drawn = render.query::<&HrocFrameStats>().iter(render).next().map(|s| s.0.objects);
            (image, drawn)
        })
        .collect()
}

#[test]
fn every_frame_is_the_image_of_drawing_everything() {
    let path = path();
    let truth = frames(Mode::Everything, &path);
    assert!(truth.iter().all(|(image, _)| image.iter().any(|&p| p != truth[0].0[0])), "the street is in view");
    for method in [hroc::Method::HROC, hroc::Method::Hzb, hroc::Method::Auto] {
        let culled = frames(Mode::Hroc(method), &path);
        for (k, ((image, drawn), (expected, _))) in culled.iter().zip(&truth).enumerate() {
            let differ = image.iter().zip(expected).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "{method} frame {k}: {differ} pixels differ from drawing everything (drawn {drawn:?})");
        }
        let drawn: Vec<u32> = culled.iter().filter_map(|f| f.1).collect();
        assert!(!drawn.is_empty() && drawn.iter().any(|&d| (d as usize) < boxes().len()), "{method} culls: drawn {drawn:?} of {}", boxes().len());
    }
}
