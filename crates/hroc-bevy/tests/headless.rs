//! Bevy on lavapipe, no window: a street of cubes behind a wall, each
//! cube its own colour, under a directional light's shadow cascades, a
//! point light among the cubes and a spot light, all casting shadows,
//! drawn along a camera path (a walk, a cut, the eye inside a box) while a
//! cube moves out from behind the wall, one is despawned and one spawned
//! (the same in every run). Every
//! frame of a camera culled by the plugin, single-sample and at MSAA 4, is
//! the image of drawing everything (no frustum or occlusion culling),
//! pixel for pixel, and
//! every shadow map's depth (cascades, the spot light's layer, the point
//! light's six faces) is the depth of drawing everything, bit for bit,
//! for `hroc`, `hzb` and `auto`; the plugin culls, the lights' views
//! included; and its validation
//! (`HrocValidation`, on here) raises nothing.

use bevy::camera::visibility::NoFrustumCulling;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy::render::occlusion_culling::OcclusionCulling;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::texture::GpuImage;
use bevy::render::RenderApp;
use hroc_bevy::{HrocCulling, HrocFindings, HrocFrameStats, HrocPlugin, HrocValidation};

mod common {
    pub mod headless;
}

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

fn app(mode: Mode, msaa: Msaa) -> App {
    let mut app = App::new();
    app.add_plugins(common::headless::plugins(Default::default(), None));
    if let Mode::Hroc(_) = mode {
        app.add_plugins(HrocPlugin).insert_resource(HrocValidation(true));
    }
    app.insert_resource(bevy::light::DirectionalLightShadowMap { size: 256 }).insert_resource(bevy::light::PointLightShadowMap { size: 128 });
    let mut image = Image::new_target_texture(SIZE.0, SIZE.1, TextureFormat::Rgba8Unorm, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.insert_resource(Target(target));
    app.add_systems(Startup, move |commands: Commands, target: Res<Target>, meshes: ResMut<Assets<Mesh>>, materials: ResMut<Assets<StandardMaterial>>| {
        scene((mode, msaa), commands, &target, meshes, materials)
    });
    common::headless::start(&mut app);
    // Bevy's GPU clustering sizes each frame's light lists from statistics
    // read back from earlier frames, as timing allows: a light could light
    // a frame differently in two runs. CPU clustering lights each frame
    // from that frame alone.
    app.world_mut().resource_mut::<bevy::light::cluster::GlobalClusterSettings>().gpu_clustering = None;
    app
}

/// The street's boxes: a wall, cubes before and behind it, a large box the
/// camera enters, the ground.
fn boxes() -> Vec<(Vec3, Vec3)> {
    let mut b = vec![(Vec3::new(-10.0, 0.0, -6.5), Vec3::new(10.0, 4.0, -6.0))];
    for x in (-8i32..=8).step_by(2) {
        for z in (-20..=0).step_by(3) {
            b.push((Vec3::new(x as f32 - 0.5, 0.0, z as f32 - 0.5), Vec3::new(x as f32 + 0.5, 1.0 + (x + z).rem_euclid(3) as f32, z as f32 + 0.5)));
        }
    }
    b.push((Vec3::new(-2.0, 0.0, 1.0), Vec3::new(2.0, 3.0, 4.0)));
    // The ground, which the point light's lower face sees.
    b.push((Vec3::new(-12.0, -0.2, -24.0), Vec3::new(12.0, 0.0, 6.0)));
    b
}

fn scene((mode, msaa): (Mode, Msaa), mut commands: Commands, target: &Target, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut camera =
        commands.spawn((Camera3d::default(), RenderTarget::Image(target.0.clone().into()), msaa, Tonemapping::None, DebandDither::Disabled, DepthPrepass, Transform::default()));
    if let Mode::Hroc(method) = mode {
        // Cascades culled by hroc too (the default leaves them to Bevy's frustum culling).
        camera.insert((OcclusionCulling, HrocCulling { method, cascades: true }));
    }
    commands.spawn((
        DirectionalLight { shadow_maps_enabled: true, illuminance: 2000.0, ..default() },
        Transform::from_xyz(3.0, 12.0, 8.0).looking_at(Vec3::new(0.0, 0.0, -8.0), Vec3::Y),
    ));
    // A point light among the cubes (each face sees cubes hide cubes) and
    // a spot light over the street.
    let mut point = commands.spawn((PointLight { shadow_maps_enabled: true, intensity: 2.0e6, range: 30.0, ..default() }, Transform::from_xyz(0.0, 0.6, -10.5)));
    if let Mode::Hroc(method) = mode {
        point.insert(HrocCulling::new(method));
    }
    let mut spot = commands.spawn((
        SpotLight { shadow_maps_enabled: true, intensity: 4.0e6, range: 40.0, outer_angle: 0.7, ..default() },
        Transform::from_xyz(-6.0, 7.0, 3.0).looking_at(Vec3::new(0.0, 0.0, -9.0), Vec3::Y),
    ));
    if let Mode::Hroc(method) = mode {
        spot.insert(HrocCulling::new(method));
    }
    let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    for (i, (lo, hi)) in boxes().into_iter().enumerate() {
        let k = i as u32 + 1;
        let colour = Color::LinearRgba(LinearRgba::new((k * 37 % 256) as f32 / 255.0, (k * 91 % 256) as f32 / 255.0, (k * 53 % 256) as f32 / 255.0, 1.0));
        let material = materials.add(StandardMaterial { base_color: colour, ..default() });
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

/// Every layer of a depth array texture (bound, not copied: Bevy's shadow
/// maps have no `COPY_SRC`).
fn read_layers(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Vec<Vec<f32>> {
    let (w, h, layers) = (texture.width(), texture.height(), texture.depth_or_array_layers());
    let source = "@group(0) @binding(0) var t: texture_depth_2d_array;\n\
        @group(0) @binding(1) var<storage, read_write> out: array<f32>;\n\
        @compute @workgroup_size(8, 8) fn main(@builtin(global_invocation_id) g: vec3<u32>) {\n\
            let s = textureDimensions(t);\n\
            if g.x >= s.x || g.y >= s.y { return; }\n\
            out[(g.z * s.y + g.y) * s.x + g.x] = textureLoad(t, g.xy, i32(g.z), 0);\n\
        }";
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: None, source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (w * h * layers * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let view =
        texture.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
            wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), layers);
    }
    queue.submit([enc.finish()]);
    let texels: Vec<f32> = hroc_readback::read(device, queue, &out, 0, (w * h * layers) as u64).unwrap();
    texels.chunks((w * h) as usize).map(<[f32]>::to_vec).collect()
}

/// A frame: the camera's image, the shadow maps' depth (the directional
/// map's layers, cascades then the spot light's, then the point light's
/// faces), what hroc drew in the camera, and whether a point light face
/// culled by the plugin drew fewer objects than Bevy's frustum culling
/// lists for it.
type Frame = (Vec<u32>, Vec<Vec<f32>>, Option<u32>, bool);

/// Each frame along `path`.
fn frames(mode: Mode, msaa: Msaa, path: &[Transform]) -> Vec<Frame> {
    let mut app = app(mode, msaa);
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
    let frames: Vec<Frame> = path
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            set_camera(&mut app, t);
            change(&mut app, mode, k);
            app.update();
            let render = app.sub_app_mut(RenderApp).world_mut();
            let texture = render.resource::<RenderAssets<GpuImage>>().get(&target).expect("the target on the GPU").texture.clone();
            let device = render.resource::<RenderDevice>().wgpu_device().clone();
            let queue: wgpu::Queue = (**render.resource::<RenderQueue>()).clone();
            let image: Vec<u32> = hroc_readback::read_texture(&device, &queue, &texture, wgpu::TextureAspect::All).unwrap();
            let shadows = render.query::<&bevy::pbr::ViewShadowBindings>().iter(render).next().expect("the camera's shadow maps");
            let (directional, point) = (shadows.directional_light_depth_texture.clone(), shadows.point_light_depth_texture.clone());
            let mut depth = read_layers(&device, &queue, &directional);
            depth.extend(read_layers(&device, &queue, &point));
            let drawn = render.query_filtered::<&HrocFrameStats, Without<bevy::pbr::LightEntity>>().iter(render).next().and_then(|s| s.0.map(|f| f.objects));
            let mut faces = Vec::new();
            if let Mode::Hroc(_) = mode {
                // Every light view culled by hroc: 4 cascades, the spot's view, 6 faces.
                let lights = render.query_filtered::<&HrocFrameStats, With<bevy::pbr::LightEntity>>().iter(render).filter(|s| s.0.is_some()).count();
                assert!(k < 2 || lights == 11, "{mode:?} frame {k}: {lights} light views culled by hroc");
                for (stats, kind) in render.query::<(&HrocFrameStats, &bevy::pbr::LightEntity)>().iter(render) {
                    if let (bevy::pbr::LightEntity::Point { face_index, .. }, Some(s)) = (kind, stats.0) {
                        faces.push((*face_index, s.objects));
                    }
                }
            }
            let world = app.world_mut();
            let lists = world.query::<&bevy::camera::visibility::CubemapVisibleEntities>().iter(world).next().map(|c| c.iter().map(|f| f.entities.len()).collect::<Vec<_>>());
            let occluded = lists.is_some_and(|l| faces.iter().any(|&(f, drawn)| (drawn as usize) < l[f]));
            (image, depth, drawn, occluded)
        })
        .collect();
    // The last frames' findings, once the GPU is done.
    app.update();
    let render = app.sub_app_mut(RenderApp).world_mut();
    let found: Vec<_> = render.query::<&HrocFindings>().iter(render).flat_map(|f| f.0.clone()).collect();
    assert!(found.is_empty(), "{mode:?} {msaa:?}: validation found {found:?}");
    frames
}

/// The scene's changes before frame `k`: a cube behind the wall moves in
/// front of it, then one is despawned, then one spawned.
fn change(app: &mut App, mode: Mode, k: usize) {
    let world = app.world_mut();
    let mut q = world.query::<(Entity, &Transform, &Mesh3d, &MeshMaterial3d<StandardMaterial>)>();
    let mut cubes: Vec<(Entity, Transform, Mesh3d, MeshMaterial3d<StandardMaterial>)> = q.iter(world).map(|(e, t, m, mat)| (e, *t, m.clone(), mat.clone())).collect();
    cubes.sort_by_key(|c| c.0);
    match k {
        2 => {
            // (Behind the wall, at z = -20.)
            let (e, t, ..) = cubes[15];
            world.entity_mut(e).insert(Transform { translation: Vec3::new(t.translation.x, t.translation.y, -3.0), ..t });
        }
        4 => {
            world.despawn(cubes[10].0);
        }
        5 => {
            let (_, _, mesh, material) = cubes[30].clone();
            let mut cube = world.spawn((mesh, material, Transform::from_xyz(1.0, 0.4, -2.5).with_scale(Vec3::splat(0.8))));
            if mode == Mode::Everything {
                cube.insert(NoFrustumCulling);
            }
        }
        _ => {}
    }
}

#[test]
fn every_frame_is_the_image_of_drawing_everything() {
    for msaa in [Msaa::Off, Msaa::Sample4] {
        same_frames_as_drawing_everything(msaa);
    }
}

fn same_frames_as_drawing_everything(msaa: Msaa) {
    let path = path();
    let truth = frames(Mode::Everything, msaa, &path);
    assert!(truth.iter().all(|(image, ..)| image.iter().any(|&p| p != truth[0].0[0])), "the street is in view");
    let held = |depth: &[Vec<f32>]| depth.iter().map(|l| l.iter().any(|&d| d != 0.0)).collect::<Vec<_>>();
    assert_eq!(truth[0].1.len(), 11, "4 cascades, the spot light, 6 faces");
    assert!(truth.iter().all(|(_, depth, ..)| held(depth).iter().all(|&h| h)), "every shadow map layer holds the street's depth: {:?}", held(&truth[0].1));
    for method in [hroc::Method::HROC, hroc::Method::Hzb, hroc::Method::Auto] {
        let culled = frames(Mode::Hroc(method), msaa, &path);
        for (k, ((image, depth, drawn, _), (expected, expected_depth, ..))) in culled.iter().zip(&truth).enumerate() {
            assert_eq!(depth.len(), expected_depth.len(), "{method} {msaa:?} frame {k}: shadow map layers");
            let layers: Vec<usize> = depth.iter().zip(expected_depth).map(|(l, e)| l.iter().zip(e).filter(|(a, b)| a.to_bits() != b.to_bits()).count()).collect();
            let differ = image.iter().zip(expected).filter(|(a, b)| a != b).count();
            let most = image.iter().zip(expected).map(|(a, b)| (0..4).map(|c| ((a >> (8 * c)) & 255).abs_diff((b >> (8 * c)) & 255)).max().unwrap()).max().unwrap();
            let (lo, hi) = image.iter().zip(expected).enumerate().filter(|(_, (a, b))| a != b).fold((usize::MAX, 0), |(lo, hi), (i, _)| (lo.min(i), hi.max(i)));
            assert_eq!(differ, 0, "{method} {msaa:?} frame {k}: {differ} pixels differ from drawing everything, by up to {most}, from {lo} to {hi} (drawn {drawn:?}; texels differing per shadow map layer {layers:?})");
            assert!(layers.iter().all(|&d| d == 0), "{method} {msaa:?} frame {k}: shadow map texels differ from drawing everything, per layer: {layers:?}");
        }
        let drawn: Vec<u32> = culled.iter().filter_map(|f| f.2).collect();
        assert!(!drawn.is_empty() && drawn.iter().any(|&d| (d as usize) < boxes().len()), "{method} {msaa:?} culls: drawn {drawn:?} of {}", boxes().len());
        if method != hroc::Method::Auto {
            assert!(culled.iter().any(|f| f.3), "{method} {msaa:?}: no point light face drew fewer objects than Bevy's frustum culling lists for it");
        }
    }
}
