//! hroc's views of Bevy's cameras: one `hroc::View` per camera with
//! [`HrocCulling`](crate::HrocCulling), on the camera's depth texture
//! (reversed depth, as Bevy draws), culled stepwise each frame
//! (`hroc::View::steps`); the three command buffers wait on the camera's
//! render entity for the `Core3d` systems that submit them between Bevy's
//! passes (`crate::steps`).

use std::sync::Mutex;

use bevy_ecs::prelude::*;
use bevy_pbr::{LightEntity, ViewLightEntities, ViewShadowBindings};
use bevy_render::occlusion_culling::OcclusionCulling;
use bevy_render::renderer::RenderDevice;
use bevy_render::view::{ExtractedView, ViewDepthStencilTexture};
use hroc::{DepthRange, FrameInput, Method, Steps, ViewDesc, ViewTargets};

use crate::objects::HrocObjects;
use crate::HrocCulling;

/// A camera's hroc view, its frame's steps and the bind group its
/// preprocessing reads hroc's visibility through.
#[derive(Component)]
pub struct HrocView {
    view: Mutex<hroc::View>,
    /// Findings of validation logged so far: each kind once per mesh.
    logged: Vec<HrocFinding>,
    /// The depth texture, layer and method the view was made for.
    key: Key,
    /// This frame's command buffers, taken by the `Core3d` systems.
    pub steps: Mutex<StepBuffers>,
    /// Visibility and slot map, at group 1 of the preprocessing shaders.
    pub bind_group: Option<wgpu::BindGroup>,
    /// The buffers the bind group holds.
    bound: Option<(wgpu::Buffer, wgpu::Buffer)>,
    /// The frame ([`HrocFrame`]) whose steps were last recorded: the
    /// preprocessing reads hroc's visibility only in that frame.
    pub recorded: u64,
}

/// The render world's frame number, counted by `prepare`: a view whose
/// steps this frame did not record (skipped, or refused) is drawn early
/// whole, never by an earlier frame's visibility.
#[derive(Resource, Default, Clone, Copy, Debug, PartialEq, Eq)]
pub struct HrocFrame(pub u64);

/// The newest frame statistics of a view hroc culls that have come back
/// (`hroc::View::frame_stats`: objects drawn, tagged with their frame), on
/// the render entity of its camera or light view; `None` until the first
/// have come back.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct HrocFrameStats(pub Option<hroc::stats::FrameStats>);

/// A finding of hroc's validation ([`crate::HrocValidation`]) in a view:
/// what Bevy's passes did against the host contract, and the mesh entity
/// it names (the one hroc's check found, or the likeliest: the drawn box
/// nearest the sample, in views without IDs).
#[derive(Clone, Debug, PartialEq)]
pub struct HrocFinding {
    /// The mesh entity (main world), where the finding names an object.
    pub mesh: Option<Entity>,
    /// hroc's finding: the view, frame, pixel, the mistake and its fix.
    pub finding: hroc::stats::Finding,
}

/// The findings of validation logged for a camera or light (on its render
/// entity), each kind once per mesh, oldest first.
#[derive(Component, Clone, Debug, Default)]
pub struct HrocFindings(pub Vec<HrocFinding>);

/// A frame's steps, each taken once.
#[derive(Default)]
pub struct StepBuffers {
    pub begin: Option<wgpu::CommandBuffer>,
    pub occluders_drawn: Option<wgpu::CommandBuffer>,
    pub occludees_drawn: Option<wgpu::CommandBuffer>,
}

/// The method a view runs: Bevy's cameras have no object-ID target, so
/// methods that filter occluders by it run without (`hroc` as `hroc-sf`).
pub fn method_without_ids(method: Method) -> Method {
    match method {
        Method::Hroc(v) if method.needs_ids() => Method::Hroc(hroc::options::Variant { of: false, ..v }),
        m => m,
    }
}

/// The layout of group 1 of the preprocessing shaders.
pub fn bind_group_layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
    let entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: true }, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    [entry(0), entry(1)]
}

/// hroc's view of Bevy's: its projection and view matrices; `unclipped`
/// for Bevy's directional cascades, which draw with depth clamped at the
/// near plane (casters before it land on it).
fn view_desc(view: &ExtractedView, unclipped: bool) -> ViewDesc {
    let world_from_view = glam::Mat4::from_cols_array(&view.world_from_view.to_matrix().to_cols_array());
    let proj = glam::Mat4::from_cols_array(&view.clip_from_view.to_cols_array());
    ViewDesc { view: world_from_view.inverse(), proj, unclipped_depth: unclipped }
}

impl HrocView {
    /// Plans the view's next frame as `extracted` sees it (a cascade:
    /// `unclipped`): whether its late pass draws (`hroc::View::plans_late`).
    pub fn plans_late(&mut self, culler: &hroc::Culler, extracted: &ExtractedView, unclipped: bool) -> bool {
        let input = FrameInput { view: view_desc(extracted, unclipped), cut: false, time: 0.0 };
        self.view.get_mut().unwrap_or_else(|p| p.into_inner()).plans_late(culler, &input)
    }

    /// The planned frame needs recording (`hroc::View::wants_steps`).
    fn wants_steps(&self) -> bool {
        self.view.lock().unwrap_or_else(|p| p.into_inner()).wants_steps()
    }

    /// Records this frame's steps, and group 1 where the buffers changed.
    fn record(&mut self, frame: &Frame, input: &FrameInput, who: &str) -> (Option<HrocFrameStats>, bool) {
        let (culler, slots, layout, device) = (frame.culler, frame.slots, frame.layout, frame.device);
        let view = self.view.get_mut().unwrap_or_else(|p| p.into_inner());
        let stats = view.frame_stats(culler).map(|s| HrocFrameStats(Some(s)));
        let visibility = view.visibility(culler).clone();
        let steps = match view.steps(culler, input) {
            Ok(Steps { begin, occluders_drawn, occludees_drawn, .. }) => {
                self.recorded = frame.number;
                StepBuffers { begin: Some(begin), occluders_drawn: Some(occluders_drawn), occludees_drawn: Some(occludees_drawn) }
            }
            Err(e) => {
                bevy_log::error!("hroc-bevy: {e}");
                StepBuffers::default()
            }
        };
        // Earlier frames' findings, logged once per kind and mesh.
        let mut found = false;
        if let Err(hroc::Error::Validation(finding)) = view.validation(culler) {
            let mesh = finding.object.and_then(|o| frame.objects.entity_of(o));
            if !self.logged.iter().any(|f| f.mesh == mesh && f.finding.mistake == finding.mistake) {
                let named = mesh.map_or(String::new(), |e| format!(" mesh entity {e}:"));
                bevy_log::warn!("hroc-bevy: {who}:{named} {finding}");
                self.logged.push(HrocFinding { mesh, finding });
                found = true;
            }
        }
        *self.steps.get_mut().unwrap_or_else(|p| p.into_inner()) = steps;
        let Some(layout) = layout else { return (stats, found) };
        let bound = (visibility.clone(), slots.clone());
        if self.bound.as_ref() != Some(&bound) {
            self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hroc visibility"),
                layout: &layout.layout,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: visibility.as_entire_binding() }, wgpu::BindGroupEntry { binding: 1, resource: slots.as_entire_binding() }],
            }));
            self.bound = Some(bound);
        }
        (stats, found)
    }
}

/// What a view is culled into and with: the depth texture, its layer,
/// and the method.
type Key = (wgpu::Texture, u32, Method);

/// What every culled view's frame needs.
struct Frame<'a> {
    culler: &'a hroc::Culler,
    objects: &'a HrocObjects,
    slots: &'a wgpu::Buffer,
    layout: Option<&'a crate::preprocess::HrocLayout>,
    device: &'a wgpu::Device,
    seconds: f32,
    /// This frame's number.
    number: u64,
}

impl Frame<'_> {
    /// Culls the view of `entity` (`existing`, or a new one; `who` in
    /// the log) into layer `layer` of `texture` with `method`, as
    /// `extracted` sees (a cascade: `unclipped`).
    fn cull(
        &self,
        commands: &mut Commands,
        (entity, who): (Entity, &str),
        existing: Option<Mut<HrocView>>,
        (texture, layer, method): Key,
        (extracted, unclipped, depth_only): (&ExtractedView, bool, bool),
    ) {
        let targets = ViewTargets::new(&texture, DepthRange::Reversed).at(layer, 0);
        let input = FrameInput { view: view_desc(extracted, unclipped), cut: false, time: self.seconds };
        let key = (texture.clone(), layer, method);
        match existing {
            // A light view Bevy culls by the frustum this frame
            // (`crate::late`), whose frame hroc needs nothing of: its
            // statistics of the last frame it recorded still come back.
            Some(mut v) if v.key == key && !v.wants_steps() => {
                if let Some(stats) = v.view.get_mut().unwrap_or_else(|p| p.into_inner()).frame_stats(self.culler) {
                    commands.entity(entity).insert(HrocFrameStats(Some(stats)));
                }
            }
            Some(mut v) if v.key.2 == method => {
                if v.key != key {
                    // A new size, texture or layer: the view carries over where it can.
                    if let Err(e) = v.view.get_mut().unwrap_or_else(|p| p.into_inner()).resize(self.culler, &targets) {
                        bevy_log::error!("hroc-bevy: {e}");
                        return;
                    }
                    v.key = key;
                }
                let (stats, found) = v.record(self, &input, who);
                if let Some(stats) = stats {
                    commands.entity(entity).insert(stats);
                }
                if found {
                    commands.entity(entity).insert(HrocFindings(v.logged.clone()));
                }
            }
            _ => match self.culler.view_with(method, &targets, &options(&texture, depth_only)) {
                Ok(view) => {
                    let mut v = HrocView { view: Mutex::new(view), logged: Vec::new(), key, steps: Mutex::default(), bind_group: None, bound: None, recorded: 0 };
                    v.record(self, &input, who);
                    // With the view, the plugin's other components on its
                    // entity: its statistics (none back yet), its findings.
                    commands.entity(entity).insert((v, HrocFrameStats(None), HrocFindings::default()));
                }
                Err(e) => bevy_log::error!("hroc-bevy: {e}"),
            },
        }
    }
}

/// What `prepare` reads of a culling camera.
type CameraItem<'a> = (
    Entity,
    Option<&'a bevy_render::sync_world::MainEntity>,
    &'a HrocCulling,
    &'a ExtractedView,
    &'a ViewDepthStencilTexture,
    Option<&'a ViewLightEntities>,
    Option<&'a ViewShadowBindings>,
    Option<&'a mut HrocView>,
);
/// What `prepare` reads of a cascade.
type CascadeItem<'a> = (&'a ExtractedView, Option<&'a mut HrocView>);
/// The light views hroc culls this frame: those with `OcclusionCulling`,
/// and those the plugin took it off for the frame (`crate::late`).
type CascadeFilter = (Or<(With<OcclusionCulling>, With<crate::late::LateLeftOut>)>, Without<HrocCulling>);

/// Render world, once Bevy's depth textures, shadow maps and hroc's
/// objects are ready: each culling camera's view, the views of its
/// directional cascades (those whose light has `OcclusionCulling`, which
/// the plugin gives every directional light), and the views of point and
/// spot lights with [`HrocCulling`] (`crate::lights`), made or resized,
/// and their frames recorded.
#[allow(clippy::too_many_arguments)]
pub fn prepare(
    mut commands: Commands,
    objects: Res<HrocObjects>,
    device: Res<RenderDevice>,
    layout: Option<Res<crate::preprocess::HrocLayout>>,
    mut cameras: Query<CameraItem>,
    mut cascades: Query<CascadeItem, CascadeFilter>,
    light_views: crate::lights::Lights,
    (time, mut number): (Option<Res<bevy_time::Time>>, ResMut<HrocFrame>),
) {
    // Counted first: a frame with nothing to cull records no view's steps.
    number.0 += 1;
    let (Some(culler), Some(slots)) = (objects.culler.as_ref(), objects.slot_buffer.as_ref()) else { return };
    let seconds = time.map_or(0.0, |t| t.elapsed_secs());
    let frame = Frame { culler, objects: &objects, slots, layout: layout.as_deref(), device: device.wgpu_device(), seconds, number: number.0 };
    // Point and spot lights with HrocCulling: shared by every camera, each
    // view culled once, and first, as Bevy draws them (before its cameras).
    for light in light_views.culled() {
        let Ok((extracted, existing)) = cascades.get_mut(light.entity) else { continue };
        frame.cull(&mut commands, (light.entity, &light.who), existing, (light.texture, light.layer, light.method), (extracted, false, true));
    }
    for (entity, main, culling, extracted, depth, lights, shadows, existing) in &mut cameras {
        let method = method_without_ids(culling.method);
        let texture: &wgpu::Texture = depth.texture();
        let camera = format!("camera {}", main.map_or(entity, |m| m.id()));
        frame.cull(&mut commands, (entity, &camera), existing, (texture.clone(), 0, method), (extracted, false, false));
        let (Some(lights), Some(shadows)) = (lights, shadows) else { continue };
        // The camera's directional cascades, in the order Bevy gave them
        // the layers of its shadow map.
        let mut layer = 0;
        for &light in &lights.lights {
            if !matches!(light_views.kind(light), Some(LightEntity::Directional { .. })) {
                continue;
            }
            let this = layer;
            layer += 1;
            // Without OcclusionCulling on its light, Bevy has no late shadow pass for it.
            let Ok((cascade, existing)) = cascades.get_mut(light) else { continue };
            let texture: &wgpu::Texture = &shadows.directional_light_depth_texture;
            let who = format!("{camera}, directional light cascade {this} (render entity {light})");
            frame.cull(&mut commands, (light, &who), existing, (texture.clone(), this, method), (cascade, true, true));
        }
    }
}

/// The options of a view of `texture`: HROC's test on single pixels below
/// 640 × 360, where the reduction to blocks costs more than the rays it
/// saves (docs/history/bevy.md); a light's views, drawn depth only, cull
/// by occlusion only where it saves the triangles of
/// [`hroc::options::DEPTH_ONLY_TRIANGLES`] per pixel, and at shadow-map
/// sizes mark from boxes one pixel in
/// [`hroc::options::BOX_MARKS_SCALE_LIGHTS`]² (the dearest pass of their
/// frames of the frustum before a probe).
fn options(texture: &wgpu::Texture, depth_only: bool) -> hroc::MethodOptions {
    let small = texture.width() * texture.height() < 640 * 360;
    hroc::MethodOptions {
        hroc_test_scale: if small { 1 } else { hroc::MethodOptions::default().hroc_test_scale },
        hroc_frustum_triangles: if depth_only { hroc::options::DEPTH_ONLY_TRIANGLES } else { 0.0 },
        box_marks_scale: if depth_only && !small { hroc::options::BOX_MARKS_SCALE_LIGHTS } else { 1 },
        ..Default::default()
    }
}
