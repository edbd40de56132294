//! # hroc-bevy: hroc's occlusion culling in Bevy 0.20
//!
//! ```ignore
//! app.add_plugins(hroc_bevy::HrocPlugin);
//! commands.spawn((Camera3d::default(), DepthPrepass, OcclusionCulling, Msaa::Off, HrocCulling::default()));
//! ```
//!
//! A camera with [`HrocCulling`] (and Bevy's `DepthPrepass` and
//! `OcclusionCulling`, whose two-phase frame it drives) is culled by hroc
//! in place of Bevy's Hi-Z test, under every material of the scene, the
//! user's own included: Bevy's early prepass draws what hroc's early step
//! says, Bevy's late prepass what its occlusion test found, and the main
//! passes both. Its directional lights' cascades can be culled the same
//! way, each against its own shadow map ([`HrocCulling::cascades`], off
//! by default: on lavapipe it cost more than it saved), and so can point
//! and spot lights' shadows, each face against its own ([`HrocCulling`]
//! on the light). The
//! plugin takes each `Mesh3d` entity as one hroc object (its world box
//! `Aabb` × `GlobalTransform`; skinned and morphed meshes are never
//! culled), culls with marks from boxes
//! (`hroc::device::Marks::Boxes`: no shader of the user's changes), and
//! runs each camera's frame stepwise (`hroc::View::steps`) at Bevy's own
//! points. Bevy's preprocessing shader is Bevy's, taken at run time, with
//! its Hi-Z test replaced by a read of hroc's visibility.
//!
//! [`HrocValidation`] (on in debug builds) checks Bevy's passes against
//! the host contract (`hroc::CullerDesc::validation`): each finding is
//! logged once through Bevy's log, naming the camera or light, the mesh
//! entity and the fix, and kept in [`HrocFindings`] on the view's render
//! entity. A mesh whose vertex shader moves it past its `Aabb` (wind,
//! vertex animation, a custom material's displacement) is such a
//! finding: hroc culls by the box, so it could cull that mesh while in
//! view.
//!
//! Pinned to Bevy 0.20.1: it replaces two of Bevy's render systems
//! (`early_gpu_preprocess`, `late_gpu_preprocess`) by its own, which
//! dispatch Bevy's work items with Bevy's bind groups, and builds Bevy's
//! Hi-Z pyramids (`early_downsample_depth`, `late_downsample_depth`) only
//! for cameras hroc does not cull, which Bevy culls as it would. A light
//! view whose next frame culls by the frustum alone (`hroc::View::plans_late`)
//! loses Bevy's `OcclusionCulling` for that frame, so that Bevy culls and
//! draws it as a view without: no late work items, no late shadow pass,
//! which would record every batch of the view again to draw none.

mod late;
mod lights;
mod objects;
mod preprocess;
mod shader;
mod steps;
mod views;

use bevy_app::{App, Plugin, Update};
use bevy_core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleCleanupPolicy;
use bevy_render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy_render::sync_component::SyncComponent;
use bevy_render::{ExtractSchedule, Render, RenderApp, RenderSystems};
use hroc::Method;
pub use views::{HrocFinding, HrocFindings, HrocFrameStats};

/// Culls a camera with hroc: put it on a `Camera3d` that has Bevy's
/// `DepthPrepass` and `OcclusionCulling`.
///
/// On a `PointLight` or `SpotLight` that casts shadows, it culls the
/// light's shadows by occlusion with `method` (`cascades` unused): each of
/// a point light's six cube faces and a spot light's one view against its
/// own layer of Bevy's shadow map, which Bevy 0.20 does not do. These
/// views are shared by every camera and culled once per frame; their
/// depth stays bit-equal to drawing everything (`tests/headless.rs`).
/// Each face is a view with the whole culling frame: measured on lavapipe
/// (BENCHMARKS.md, "Bevy"), 4 point lights over radial-city 5,000 (24
/// faces of 256²) took 1.35 × Bevy's frustum culling with `hroc` and
/// 2.9 × with `hzb`.
/// Where occlusion hides little, HROC culls a view by its frustum between
/// measurements (as cascades).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct HrocCulling {
    /// The method. Bevy's cameras have no object-ID target: `hroc` runs
    /// as `hroc-sf` (HROC without occluder filtering by IDs).
    pub method: Method,
    /// Also cull the camera's directional-light cascades by occlusion,
    /// each against its own shadow map, with `method`: the plugin gives
    /// every directional light Bevy's `OcclusionCulling` (Bevy's switch for
    /// culling a light's shadows by occlusion, which adds their late
    /// shadow pass). Where false, cascades are culled as Bevy culls them:
    /// by the frustum, or by hroc where the user gave the light
    /// `OcclusionCulling`.
    ///
    /// Off by default: the mode that pays. A light looking down on roofs
    /// hides little, and culling its cascades by occlusion makes Bevy add
    /// preprocessing per cascade, and a late shadow pass wherever a
    /// cascade's frame tests by occlusion; measured on lavapipe at
    /// 320 × 180 with 4 cascades of a 1024² map (BENCHMARKS.md, "Bevy"),
    /// the plugin's `hroc` took 0.85 × (radial-city 5,000) and 0.96 ×
    /// (`houses`) Bevy's frustum culling with cascades left to the
    /// frustum, and 0.90 × and 0.98 × with them culled by occlusion.
    ///
    /// Where on, HROC chooses per view by measurement: each cascade culls
    /// by occlusion where one frame in eight finds that occlusion culls at
    /// least 5 % of the objects in its frustum and either half of them or
    /// 0.05 triangles per pixel of the view
    /// (`hroc::options::DEPTH_ONLY_TRIANGLES`, the bar of every light
    /// view), and more triangles than the boxes its test draws (12 for
    /// each object it tests: over objects no richer than their boxes, as
    /// on `houses`, never, and it does not measure);
    /// and by the frustum alone otherwise
    /// (`hroc::MethodOptions::hroc_frustum_below`,
    /// `hroc::MethodOptions::hroc_frustum_triangles`), measuring again
    /// after 32 frames, then 64, then every 128. A frame of the frustum
    /// is, for Bevy, a view without `OcclusionCulling` (one shadow pass,
    /// Bevy's own frustum culling; `hroc::View::plans_late`), and hroc
    /// records it only before a measurement. The frame of the frustum before each
    /// measurement makes the boxes its depth shows the measurement's
    /// occluders, and a cascade cut with its camera stays with the
    /// frustum until its next measurement. Light views of 640 × 360 or
    /// more mark one pixel in 4 × 4
    /// (`hroc::options::BOX_MARKS_SCALE_LIGHTS`).
    pub cascades: bool,
}

impl Default for HrocCulling {
    /// HROC on the camera; its cascades left to Bevy's frustum culling
    /// ([`HrocCulling::cascades`]).
    fn default() -> Self {
        HrocCulling { method: Method::HROC, cascades: false }
    }
}

impl HrocCulling {
    /// Culls the camera with `method`; cascades as by default.
    pub fn new(method: Method) -> Self {
        HrocCulling { method, ..Default::default() }
    }
}

impl SyncComponent<RenderApp> for HrocCulling {
    type Target = (HrocCulling, views::HrocView, views::HrocFrameStats, views::HrocFindings);
}

impl ExtractComponent<RenderApp> for HrocCulling {
    type QueryData = &'static HrocCulling;
    type QueryFilter = ();
    type Out = HrocCulling;

    fn extract_component(culling: &HrocCulling) -> Option<HrocCulling> {
        Some(*culling)
    }
}

/// Validation of Bevy's passes by hroc (`hroc::CullerDesc::validation`),
/// on by default in debug builds, off in release: insert
/// `HrocValidation(true)` or `HrocValidation(false)` into the app before
/// its first frame with meshes (the culler is made then, with or without
/// it). It costs a few compute passes per view and frame, each reading at
/// most 1,024 pixels. Findings are logged once each ([`HrocFindings`]).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct HrocValidation(pub bool);

impl bevy_render::extract_resource::ExtractResource<RenderApp> for HrocValidation {
    type Source = HrocValidation;

    fn extract_resource(source: &HrocValidation) -> Self {
        *source
    }
}

// On in debug builds: not the derived `false` (which release builds see).
#[allow(clippy::derivable_impls)]
impl Default for HrocValidation {
    fn default() -> Self {
        HrocValidation(cfg!(debug_assertions))
    }
}

/// Directional lights get Bevy's `OcclusionCulling` once a camera culls
/// its cascades with hroc ([`HrocCulling::cascades`]): Bevy then gives
/// their cascades a late shadow pass, which draws what hroc's test of each
/// cascade finds.
fn cull_cascades(
    mut commands: Commands,
    lights: Query<Entity, (With<bevy_light::DirectionalLight>, Without<bevy_render::occlusion_culling::OcclusionCulling>)>,
    cameras: Query<&HrocCulling, With<bevy_camera::Camera>>,
) {
    if !cameras.iter().any(|c| c.cascades) {
        return;
    }
    for light in &lights {
        commands.entity(light).insert(bevy_render::occlusion_culling::OcclusionCulling);
    }
}

/// The camera whose `Core3d` runs is not culled by hroc: Bevy's Hi-Z is
/// built for it (and its cascades), which Bevy's own test reads.
fn not_culled_by_hroc(current: Res<bevy_render::renderer::CurrentView>, hroc: Query<(), With<HrocCulling>>) -> bool {
    !hroc.contains(current.0)
}

/// hroc's culling for every camera with [`HrocCulling`].
pub struct HrocPlugin;

impl HrocPlugin {
    /// True once the plugin culls: its preprocessing pipelines are
    /// compiled (Bevy's shader is loaded as an asset, so a few frames
    /// after start; until then Bevy culls as it would).
    pub fn ready(app: &App) -> bool {
        let Some(render) = app.get_sub_app(RenderApp) else { return false };
        let world = render.world();
        let (Some(ours), Some(cache)) = (world.get_resource::<preprocess::HrocPipelines>(), world.get_resource::<bevy_render::render_resource::PipelineCache>()) else {
            return false;
        };
        ours.compiled(cache)
    }
}

impl Plugin for HrocPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(ExtractComponentPlugin::<HrocCulling>::default());
        app.init_resource::<shader::HrocShaders>().add_systems(Update, (shader::make_shaders, cull_cascades));
        app.add_plugins(bevy_render::extract_resource::ExtractResourcePlugin::<shader::HrocShaders>::default());
        app.init_resource::<HrocValidation>().add_plugins(bevy_render::extract_resource::ExtractResourcePlugin::<HrocValidation>::default());
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else { return };
        render_app
            .init_resource::<objects::ExtractedInstances>()
            .init_resource::<objects::HrocObjects>()
            .init_resource::<preprocess::HrocPipelines>()
            .init_resource::<views::HrocFrame>()
            .add_systems(ExtractSchedule, objects::extract)
            .add_systems(
                Render,
                (
                    objects::sync.in_set(RenderSystems::PrepareResourcesFlush),
                    preprocess::queue_pipelines.in_set(RenderSystems::Prepare),
                    lights::mark.in_set(RenderSystems::PrepareViews),
                    late::leave_out.in_set(RenderSystems::PrepareViews).after(lights::mark),
                    views::prepare.in_set(RenderSystems::PrepareBindGroups),
                ),
            );
    }

    fn cleanup(&self, app: &mut App) {
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else { return };
        use bevy_core_pipeline::mip_generation::experimental::depth::{early_downsample_depth, late_downsample_depth};
        // Bevy's Hi-Z pyramids (built from every occlusion-culled view's
        // depth, its cascades' included) serve only Bevy's test: built
        // again below for cameras hroc does not cull.
        for removed in [
            render_app.remove_systems_in_set(Core3d, bevy_pbr::early_gpu_preprocess, ScheduleCleanupPolicy::RemoveSystemsOnly),
            render_app.remove_systems_in_set(Core3d, bevy_pbr::late_gpu_preprocess, ScheduleCleanupPolicy::RemoveSystemsOnly),
            render_app.remove_systems_in_set(Core3d, early_downsample_depth, ScheduleCleanupPolicy::RemoveSystemsOnly),
            render_app.remove_systems_in_set(Core3d, late_downsample_depth, ScheduleCleanupPolicy::RemoveSystemsOnly),
        ] {
            if let Err(e) = removed {
                bevy_log::error!("hroc-bevy: Bevy's preprocessing systems are not those of Bevy 0.20.1: {e}");
                return;
            }
        }
        use bevy_core_pipeline::prepass::node::{early_prepass, late_prepass};
        use bevy_pbr::{
            early_prepass_build_indirect_parameters, late_prepass_build_indirect_parameters, per_view_shadow_pass, shared_shadow_pass, unpack_bins, EARLY_SHADOW_PASS,
            LATE_SHADOW_PASS,
        };
        render_app.add_systems(
            Core3d,
            (
                steps::begin.after(unpack_bins).before(preprocess::early_preprocess),
                preprocess::early_preprocess.after(unpack_bins).before(early_prepass_build_indirect_parameters),
                // (Bevy's deferred prepass does not take occlusion culling.)
                steps::occluders_drawn
                    .after(early_prepass)
                    .after(per_view_shadow_pass::<EARLY_SHADOW_PASS>)
                    .after(shared_shadow_pass::<EARLY_SHADOW_PASS>)
                    .before(preprocess::late_preprocess),
                preprocess::late_preprocess.after(steps::occluders_drawn).before(late_prepass_build_indirect_parameters).before(late_prepass),
                steps::occludees_drawn
                    .after(late_prepass)
                    .after(per_view_shadow_pass::<LATE_SHADOW_PASS>)
                    .after(shared_shadow_pass::<LATE_SHADOW_PASS>)
                    .before(Core3dSystems::MainPass),
                early_downsample_depth.run_if(not_culled_by_hroc).after(early_prepass).before(late_prepass).before(preprocess::late_preprocess),
                late_downsample_depth.run_if(not_culled_by_hroc).in_set(Core3dSystems::PostProcess),
            ),
        );
    }
}
