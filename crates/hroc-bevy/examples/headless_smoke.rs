//! Bevy on lavapipe without a window: a camera with Bevy's occlusion
//! culling renders a row of cubes into an image, frames driven by hand.

use bevy::app::PluginsState;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::batching::gpu_preprocessing::GpuPreprocessingSupport;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::render::{RenderApp, RenderPlugin};
use bevy::window::ExitCondition;

fn main() {
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
    app.add_systems(Startup, setup);
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    let support = app
        .sub_app(RenderApp)
        .world()
        .get_resource::<GpuPreprocessingSupport>()
        .map(|s| matches!(s.max_supported_mode, bevy::render::batching::gpu_preprocessing::GpuPreprocessingMode::Culling));
    println!("gpu culling: {support:?}");
    let t = std::time::Instant::now();
    for _ in 0..10 {
        app.update();
    }
    println!("10 frames in {:.0} ms", t.elapsed().as_secs_f64() * 1e3);
}

fn setup(mut commands: Commands, mut images: ResMut<Assets<Image>>, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut image = Image::new_target_texture(320, 180, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = images.add(image);
    commands.spawn((
        Camera3d::default(),
        RenderTarget::Image(target.into()),
        Msaa::Off,
        DepthPrepass,
        OcclusionCulling,
        Tonemapping::None,
        Transform::from_xyz(0.0, 1.5, 8.0).looking_at(Vec3::new(0.0, 1.0, -10.0), Vec3::Y),
    ));
    let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    let grey = materials.add(StandardMaterial::default());
    for z in 0..20 {
        commands.spawn((Mesh3d(cube.clone()), MeshMaterial3d(grey.clone()), Transform::from_xyz(0.0, 0.5, -(z as f32) * 2.0)));
    }
    commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::from_xyz(3.0, 10.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y)));
}
