//! Point and spot lights' shadows culled by hroc: a light with
//! [`HrocCulling`] has each of its shadow views (a point light's six cube
//! faces, a spot light's one) culled by occlusion against its own layer of
//! Bevy's shadow map. Bevy 0.20 culls only directional lights' shadows by
//! occlusion: the plugin gives these views Bevy's `OcclusionCulling`,
//! which makes Bevy build their late work items and run their late shadow
//! pass (Bevy's shared shadow passes already run both phases for any view
//! with it; left out in frames that draw nothing late, `crate::late`), and
//! hroc's steps run at Bevy's points of each such view's own `Core3d`
//! frame (`crate::steps`).

use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use bevy_pbr::{ExtractedPointLight, GlobalClusterableObjectMeta, LightEntity, ShadowView, ViewLightEntities, ViewShadowBindings};
use bevy_render::camera::ExtractedCamera;
use bevy_render::occlusion_culling::OcclusionCulling;
use bevy_render::view::{ExtractedView, NoIndirectDrawing};
use hroc::Method;

use crate::views::{HrocFindings, HrocFrameStats, HrocView};
use crate::HrocCulling;

/// The light a point or spot light's view belongs to; `None` for a
/// directional cascade.
pub(crate) fn point_or_spot(kind: &LightEntity) -> Option<Entity> {
    match kind {
        LightEntity::Point { light_entity, .. } | LightEntity::Spot { light_entity } => Some(*light_entity),
        LightEntity::Directional { .. } => None,
    }
}

/// The shadow map and layer a point or spot light's view draws into, as
/// Bevy's `prepare_lights` chose them when it last made the view's
/// `ShadowView` (which it makes again only when the light changes).
#[derive(Component, Clone, Debug)]
pub struct ShadowLayer {
    pub texture: wgpu::Texture,
    pub layer: u32,
}

/// What finding a light view's layer takes.
#[derive(SystemParam)]
pub struct Layers<'w, 's> {
    meta: Option<Res<'w, GlobalClusterableObjectMeta>>,
    points: Query<'w, 's, &'static ExtractedPointLight>,
    cameras: Query<'w, 's, (&'static ViewLightEntities, &'static ViewShadowBindings), With<ExtractedCamera>>,
    kinds: Query<'w, 's, &'static LightEntity>,
}

impl Layers<'_, '_> {
    /// The map and layer `prepare_lights` gives a view of `kind` this
    /// frame: a point light's faces are layers `6 i` to `6 i + 5` of the
    /// point lights' cube map array, `i` its index among Bevy's clustered
    /// lights (point lights first); a spot light's layer of the
    /// directional shadow map follows the most directional cascades any
    /// camera has. Both maps are shared by every camera (any active
    /// camera's `ViewShadowBindings` holds this frame's).
    fn of(&self, kind: &LightEntity) -> Option<ShadowLayer> {
        let index = *self.meta.as_ref()?.entity_to_index.get(&point_or_spot(kind)?)?;
        let (_, bindings) = self.cameras.iter().next()?;
        let (texture, layer): (&wgpu::Texture, usize) = match *kind {
            LightEntity::Point { face_index, .. } => (&bindings.point_light_depth_texture, index * 6 + face_index),
            _ => {
                let point_lights = self.points.iter().filter(|l| l.spot_light_angles.is_none()).count();
                let directional = |l: &&Entity| matches!(self.kinds.get(**l), Ok(LightEntity::Directional { .. }));
                let cascades = self.cameras.iter().map(|(lights, _)| lights.lights.iter().filter(directional).count()).max().unwrap_or(0);
                (&bindings.directional_light_depth_texture, cascades + index.checked_sub(point_lights)?)
            }
        };
        let layer = u32::try_from(layer).ok().filter(|&l| l < texture.depth_or_array_layers())?;
        Some(ShadowLayer { texture: texture.clone(), layer })
    }
}

/// What `mark` reads of a light's view.
type LightViewItem<'a> = (Entity, &'a LightEntity, Ref<'a, ShadowView>, Has<OcclusionCulling>, Has<ShadowLayer>, Has<NoIndirectDrawing>);

/// Render world, once Bevy has made its lights' views: the views of point
/// and spot lights with [`HrocCulling`] (and indirect draws) get their
/// [`ShadowLayer`] whenever Bevy (re)makes their `ShadowView`, and, once
/// the plugin's pipelines have compiled, Bevy's `OcclusionCulling`; those
/// of lights that lost it, or whose layer is not known, lose both and
/// what hroc kept on them. (Bevy allocates such a view a Hi-Z and never
/// builds it: until hroc's steps for a frame are recorded, the plugin's
/// preprocessing draws the whole view early.)
pub fn mark(
    mut commands: Commands,
    views: Query<LightViewItem>,
    culled: Query<(), (With<HrocCulling>, Without<ExtractedView>)>,
    layers: Layers,
    pipelines: Res<crate::preprocess::HrocPipelines>,
    cache: Res<bevy_render::render_resource::PipelineCache>,
) {
    let compiled = pipelines.compiled(&cache);
    let forget = |commands: &mut Commands, view| {
        commands.entity(view).remove::<(OcclusionCulling, ShadowLayer, HrocView, HrocFrameStats, HrocFindings)>();
    };
    for (view, kind, shadow, marked, placed, direct) in &views {
        let Some(light) = point_or_spot(kind) else { continue };
        if !culled.contains(light) || direct {
            if marked || placed {
                forget(&mut commands, view);
            }
            continue;
        }
        if shadow.is_changed() || !placed {
            let Some(layer) = layers.of(kind) else {
                forget(&mut commands, view);
                continue;
            };
            commands.entity(view).insert(layer);
        }
        if compiled && !marked {
            commands.entity(view).insert(OcclusionCulling);
        }
    }
}

/// A point or spot light's view hroc culls.
pub struct LightView {
    /// The view's render entity.
    pub entity: Entity,
    /// The light's method (as run without IDs).
    pub method: Method,
    /// Bevy's shadow map the view draws into, and its layer.
    pub texture: wgpu::Texture,
    pub layer: u32,
    /// The view's name in the log.
    pub who: String,
}

/// What finding the point and spot lights' views takes.
#[derive(SystemParam)]
pub struct Lights<'w, 's> {
    kinds: Query<'w, 's, (Entity, &'static LightEntity, Option<&'static ShadowLayer>)>,
    culling: Query<'w, 's, &'static HrocCulling, Without<ExtractedView>>,
}

impl Lights<'_, '_> {
    /// The kind of the light view `entity`.
    pub fn kind(&self, entity: Entity) -> Option<&LightEntity> {
        self.kinds.get(entity).ok().map(|(_, k, _)| k)
    }

    /// The views of point and spot lights with [`HrocCulling`] and a
    /// [`ShadowLayer`].
    pub fn culled(&self) -> Vec<LightView> {
        let mut views = Vec::new();
        for (entity, kind, placed) in &self.kinds {
            let (Some(light), Some(ShadowLayer { texture, layer })) = (point_or_spot(kind), placed) else { continue };
            let Ok(culling) = self.culling.get(light) else { continue };
            let who = match *kind {
                LightEntity::Point { face_index, .. } => format!("point light {light}, face {face_index}"),
                _ => format!("spot light {light}"),
            };
            views.push(LightView { entity, method: crate::views::method_without_ids(culling.method), texture: texture.clone(), layer: *layer, who });
        }
        views
    }
}
