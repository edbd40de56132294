//! A fly camera through a glTF scene written by `hroc scene export`, each
//! object a Bevy mesh entity, lit under a directional light's cascades.
//! `C` switches the camera between hroc's culling and Bevy's own
//! `OcclusionCulling`; the window's title says which, and the objects
//! the main pass drew (read from Bevy's indirect draws every 30 frames). `WASD` move, the arrow keys turn,
//! `Q`/`E` go down and up.
//!
//! `cargo run --release -p hroc-bevy --ignore-rust-version --example bevy-city -- scene.glb [--frames N]`
//! (`--frames N` closes the window after N frames.)

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::gltf::{Gltf, GltfMesh, GltfNode};
use bevy::prelude::*;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::{Render, RenderApp, RenderDebugFlags, RenderPlugin, RenderSystems};
use hroc_bevy::{HrocCulling, HrocPlugin};

#[path = "common/drawn.rs"]
mod drawn;

/// Objects the main pass drew, from the render world to the window's title.
#[derive(Resource, Clone, Default)]
struct Drawn(Arc<AtomicU32>);

#[derive(Resource)]
struct SceneFile(Handle<Gltf>);

/// Frames before the window closes, when asked for.
#[derive(Resource)]
struct Frames(Option<u32>);

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = std::path::Path::new(args.get(1).expect("a .glb written by hroc scene export")).canonicalize().expect("the scene file");
    let frames = args.iter().position(|a| a == "--frames").and_then(|i| args.get(i + 1)).map(|n| n.parse().expect("a count of frames"));
    let drawn = Drawn::default();
    let mut app = App::new();
    let render = RenderPlugin { debug_flags: RenderDebugFlags::ALLOW_COPIES_FROM_INDIRECT_PARAMETERS, ..default() };
    app.add_plugins(DefaultPlugins.set(AssetPlugin { file_path: scene.parent().unwrap().to_string_lossy().into_owned(), ..default() }).set(render))
        .add_plugins(HrocPlugin)
        .insert_resource(drawn.clone())
        .insert_resource(Frames(frames))
        .insert_resource(SceneFile(Handle::default()))
        .add_systems(Startup, move |mut commands: Commands, server: Res<AssetServer>| {
            commands.insert_resource(SceneFile(server.load(scene.file_name().unwrap().to_string_lossy().into_owned())));
            commands.spawn((Camera3d::default(), Tonemapping::AcesFitted, Msaa::Off, DepthPrepass, OcclusionCulling, HrocCulling::default(), Transform::from_xyz(0.0, 1.7, 0.0)));
            commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::from_xyz(0.3, 1.0, 0.4).looking_at(Vec3::ZERO, Vec3::Y)));
        })
        .add_systems(Update, (spawn_scene, fly, switch, title, count_frames));
    app.sub_app_mut(RenderApp).insert_resource(drawn).add_systems(Render, publish.in_set(RenderSystems::Cleanup));
    app.run();
}

/// Render world, every 30th frame: the objects the main opaque pass drew,
/// the instances of Bevy's indirect draws, whichever culls.
fn publish(world: &mut World, mut frame: Local<u32>) {
    *frame += 1;
    if *frame % 30 == 1 {
        let n = drawn::drawn(world);
        world.resource::<Drawn>().0.store(n as u32, Ordering::Relaxed);
    }
}

/// One mesh entity per primitive of every node, Bevy's standard material.
fn spawn_scene(
    mut done: Local<bool>,
    mut commands: Commands,
    file: Res<SceneFile>,
    gltfs: Res<Assets<Gltf>>,
    nodes: Res<Assets<GltfNode>>,
    meshes: Res<Assets<GltfMesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let Some(gltf) = gltfs.get(&file.0).filter(|_| !*done) else { return };
    let material = materials.add(StandardMaterial { base_color: Color::srgb(0.7, 0.7, 0.72), perceptual_roughness: 0.8, ..default() });
    for node in gltf.nodes.iter().filter_map(|h| nodes.get(h)) {
        for primitive in node.mesh.as_ref().and_then(|m| meshes.get(m)).map(|m| m.primitives.as_slice()).unwrap_or_default() {
            commands.spawn((Mesh3d(primitive.mesh.clone()), MeshMaterial3d(material.clone()), node.transform));
        }
    }
    *done = true;
}

fn fly(keys: Res<ButtonInput<KeyCode>>, time: Res<Time>, mut camera: Query<&mut Transform, With<Camera3d>>) {
    let Ok(mut t) = camera.single_mut() else { return };
    let dt = time.delta_secs();
    let key = |k| if keys.pressed(k) { 1.0 } else { 0.0 };
    let turn = key(KeyCode::ArrowLeft) - key(KeyCode::ArrowRight);
    let pitch = key(KeyCode::ArrowUp) - key(KeyCode::ArrowDown);
    t.rotate_y(turn * 1.5 * dt);
    t.rotate_local_x(pitch * 1.0 * dt);
    let (forward, right) = (t.forward().as_vec3(), t.right().as_vec3());
    let walk = forward * (key(KeyCode::KeyW) - key(KeyCode::KeyS)) + right * (key(KeyCode::KeyD) - key(KeyCode::KeyA)) + Vec3::Y * (key(KeyCode::KeyE) - key(KeyCode::KeyQ));
    t.translation += walk * 20.0 * dt;
}

/// `C`: hroc's culling or Bevy's.
fn switch(keys: Res<ButtonInput<KeyCode>>, mut commands: Commands, camera: Query<(Entity, Has<HrocCulling>), With<Camera3d>>) {
    let Ok((entity, hroc)) = camera.single() else { return };
    if keys.just_pressed(KeyCode::KeyC) {
        if hroc {
            commands.entity(entity).remove::<HrocCulling>();
        } else {
            commands.entity(entity).insert(HrocCulling::default());
        }
    }
}

fn title(drawn: Res<Drawn>, camera: Query<Has<HrocCulling>, With<Camera3d>>, mut windows: Query<&mut Window>) {
    let (Ok(hroc), Ok(mut window)) = (camera.single(), windows.single_mut()) else { return };
    let n = drawn.0.load(Ordering::Relaxed);
    window.title = if hroc { format!("hroc: {n} objects drawn (C: Bevy's occlusion culling)") } else { format!("Bevy's occlusion culling: {n} objects drawn (C: hroc)") };
}

fn count_frames(mut frames: ResMut<Frames>, mut exit: MessageWriter<AppExit>) {
    if let Some(n) = frames.0.as_mut() {
        *n = n.saturating_sub(1);
        if *n == 0 {
            exit.write(AppExit::Success);
        }
    }
}
