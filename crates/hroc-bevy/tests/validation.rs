//! The plugin's validation (`HrocValidation`), Bevy on lavapipe, no
//! window: a row of cubes before a wall, one drawn with a material whose
//! vertex shader lifts it 0.6 above its `Aabb` (in the depth prepass, the
//! shadow pass and the main pass, as a wind or displacement shader does).
//! Culled by the plugin with validation on, the lifted cube is reported
//! within 3 frames, naming its entity; without it, the same scene raises
//! nothing.

use bevy::asset::uuid_handle;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::pbr::{ExtendedMaterial, MaterialExtension};
use bevy::prelude::*;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::render_resource::{AsBindGroup, TextureFormat};
use bevy::render::RenderApp;
use bevy::shader::ShaderRef;
use hroc_bevy::{HrocCulling, HrocFindings, HrocPlugin, HrocValidation};

mod common {
    pub mod headless;
}

const LIFT_PREPASS: Handle<Shader> = uuid_handle!("4f0b8a52-3c1e-4d7a-9a4e-6b2f1c8d0e71");
const LIFT_MAIN: Handle<Shader> = uuid_handle!("4f0b8a52-3c1e-4d7a-9a4e-6b2f1c8d0e72");

/// Bevy's vertex stage with the mesh lifted 0.6, on the vertex and
/// output types of `io` (the prepass's, for depth and shadows, or the
/// main pass's), setting also `outputs`.
fn lifting_shader(io: &str, outputs: &str) -> String {
    format!(
        r#"
import {io}::{{Vertex, VertexOutput, decompress_vertex}};
import bevy_pbr::render::{{mesh_functions, view_transformations::position_world_to_clip}};

@vertex
fn vertex(vertex_in: Vertex) -> VertexOutput {{
    var out: VertexOutput;
    let v = decompress_vertex(vertex_in, vertex_in.instance_index);
    let world_from_local = mesh_functions::get_world_from_local(vertex_in.instance_index);
    out.world_position = mesh_functions::mesh_position_local_to_world(world_from_local, vec4<f32>(v.position, 1.0)) + vec4<f32>(0.0, 0.6, 0.0, 0.0);
    out.position = position_world_to_clip(out.world_position.xyz);
    {outputs}
    @if(VERTEX_UVS_A) out.uv = v.uv;
    @if(VERTEX_OUTPUT_INSTANCE_INDEX) out.instance_index = vertex_in.instance_index;
    return out;
}}
"#
    )
}

/// What the prepass (depth and shadows) sets beyond: depth clamped, not
/// clipped, in orthographic shadow views.
const PREPASS_OUTPUTS: &str = "@if(UNCLIPPED_DEPTH_ORTHO_EMULATION) { out.unclipped_depth = out.position.z; out.position.z = min(out.position.z, 1.0); }";
/// What the main pass sets beyond: the normal.
const MAIN_OUTPUTS: &str = "out.world_normal = mesh_functions::mesh_normal_local_to_world(v.normal, vertex_in.instance_index);";

/// A material that lifts its mesh 0.6 above where its `Aabb` says.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
struct Lift {}

impl MaterialExtension for Lift {
    fn vertex_shader() -> ShaderRef {
        LIFT_MAIN.into()
    }
    fn prepass_vertex_shader() -> ShaderRef {
        LIFT_PREPASS.into()
    }
}

type Lifted = ExtendedMaterial<StandardMaterial, Lift>;

/// The cube (of `CUBES`) drawn lifted, before the wall and in view.
const LIFTED: usize = 2;
/// The cubes' x, before the wall.
const CUBES: [f32; 5] = [-4.0, -2.0, 0.0, 2.0, 4.0];

#[derive(Resource)]
struct LiftedCube(Entity);

fn app(lift: bool) -> App {
    let mut app = App::new();
    app.add_plugins(common::headless::plugins(Default::default(), None));
    app.add_plugins((HrocPlugin, MaterialPlugin::<Lifted>::default()));
    app.insert_resource(HrocValidation(true));
    {
        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
        let _ = shaders.insert(LIFT_PREPASS.id(), Shader::from_wesl(lifting_shader("bevy_pbr::prepass::io", PREPASS_OUTPUTS), "embedded://hroc_bevy_test/lift_prepass.wesl"));
        let _ = shaders.insert(LIFT_MAIN.id(), Shader::from_wesl(lifting_shader("bevy_pbr::render::forward_io", MAIN_OUTPUTS), "embedded://hroc_bevy_test/lift_main.wesl"));
    }
    let mut image = Image::new_target_texture(160, 90, TextureFormat::Rgba8Unorm, None);
    image.texture_descriptor.usage |= bevy::render::render_resource::TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.add_systems(Startup, move |mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut plain: ResMut<Assets<StandardMaterial>>, mut lifted: ResMut<Assets<Lifted>>| {
        commands.spawn((
            Camera3d::default(),
            bevy::camera::RenderTarget::Image(target.clone().into()),
            Msaa::Off,
            Tonemapping::None,
            DebandDither::Disabled,
            DepthPrepass,
            OcclusionCulling,
            HrocCulling { method: hroc::Method::Hzb, cascades: true },
            Transform::from_xyz(0.0, 1.5, 9.0).looking_at(Vec3::new(0.0, 1.0, -6.0), Vec3::Y),
        ));
        commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::from_xyz(3.0, 12.0, 8.0).looking_at(Vec3::new(0.0, 0.0, -6.0), Vec3::Y)));
        let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
        let base = StandardMaterial { base_color: Color::srgb(0.6, 0.5, 0.4), unlit: true, ..default() };
        let material = plain.add(base.clone());
        commands.spawn((Mesh3d(cube.clone()), MeshMaterial3d(material.clone()), Transform::from_xyz(0.0, 2.0, -6.25).with_scale(Vec3::new(20.0, 4.0, 0.5))));
        for (i, x) in CUBES.into_iter().enumerate() {
            let at = Transform::from_xyz(x, 0.5, 0.0);
            if lift && i == LIFTED {
                let e = commands.spawn((Mesh3d(cube.clone()), MeshMaterial3d(lifted.add(Lifted { base: base.clone(), extension: Lift {} })), at)).id();
                commands.insert_resource(LiftedCube(e));
            } else {
                commands.spawn((Mesh3d(cube.clone()), MeshMaterial3d(material.clone()), at));
            }
        }
    });
    common::headless::start(&mut app);
    app
}

/// The findings on every view's render entity after each of `frames`
/// frames once the plugin culls.
fn findings(app: &mut App, frames: usize) -> Vec<Vec<hroc_bevy::HrocFinding>> {
    for _ in 0..60 {
        app.update();
        if HrocPlugin::ready(app) {
            break;
        }
    }
    assert!(HrocPlugin::ready(app), "the plugin is not ready after 60 frames");
    (0..frames)
        .map(|_| {
            app.update();
            let render = app.sub_app_mut(RenderApp).world_mut();
            render.query::<&HrocFindings>().iter(render).flat_map(|f| f.0.clone()).collect()
        })
        .collect()
}

#[test]
fn a_mesh_lifted_past_its_aabb_by_its_vertex_shader_is_reported() {
    let mut app = app(true);
    let found = findings(&mut app, 4);
    let lifted = app.world().resource::<LiftedCube>().0;
    let first = found.iter().position(|f| !f.is_empty());
    assert!(first.is_some_and(|k| k < 3), "nothing reported within 3 frames: {found:?}");
    let f = &found[first.unwrap()][0];
    assert_eq!(f.mesh, Some(lifted), "the finding names the lifted cube's entity: {f:?}");
    assert!(f.finding.cause.contains("in front of every box") && f.finding.cause.contains("vertex shader"), "{}", f.finding);
}

#[test]
fn the_same_scene_without_the_lift_raises_nothing() {
    let mut app = app(false);
    let found = findings(&mut app, 4);
    assert!(found.iter().all(|f| f.is_empty()), "{found:?}");
}
