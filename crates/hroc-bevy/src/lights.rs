//! Point and spot lights' shadows culled by hroc: a light with
//! [`HrocCulling`] has each of its shadow views (a point light's six cube
//! faces, a spot light's one) culled by occlusion against its own layer of
//! Bevy's shadow map. Bevy 0.20 culls only directional lights' shadows by
//! occlusion: the plugin gives these views Bevy's `OcclusionCulling`,
//! which makes Bevy build their late work items and run their late shadow
//! pass (Bevy's shared shadow passes already run both phases for any view
//! with it), and hroc's steps run at Bevy's points of each such view's own
//! `Core3d` frame (`crate::steps`).

use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use bevy_pbr::{ExtractedPointLight, GlobalClusterableObjectMeta, LightEntity, ViewLightEntities, ViewShadowBindings};
use bevy_render::occlusion_culling::OcclusionCulling;
use bevy_render::view::ExtractedView;
use hroc::Method;

use crate::views::HrocView;
use crate::HrocCulling;

/// The light a point or spot light's view belongs to; `None` for a
/// directional cascade.
fn point_or_spot(kind: &LightEntity) -> Option<Entity> {
    match kind {
        LightEntity::Point { light_entity, .. } | LightEntity::Spot { light_entity } => Some(*light_entity),
        LightEntity::Directional { .. } => None,
    }
}

/// Render world, once Bevy has made its lights' views: the views of point
/// and spot lights with [`HrocCulling`] get Bevy's `OcclusionCulling`;
/// those of lights that lost it lose it, and their hroc views.
pub fn mark(mut commands: Commands, views: Query<(Entity, &LightEntity, Has<OcclusionCulling>)>, culled: Query<(), (With<HrocCulling>, Without<ExtractedView>)>) {
    for (view, kind, marked) in &views {
        let Some(light) = point_or_spot(kind) else { continue };
        match (culled.contains(light), marked) {
            (true, false) => {
                commands.entity(view).insert(OcclusionCulling);
            }
            (false, true) => {
                commands.entity(view).remove::<(OcclusionCulling, HrocView)>();
            }
            _ => {}
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
    kinds: Query<'w, 's, (Entity, &'static LightEntity)>,
    culling: Query<'w, 's, &'static HrocCulling, Without<ExtractedView>>,
    meta: Option<Res<'w, GlobalClusterableObjectMeta>>,
    points: Query<'w, 's, &'static ExtractedPointLight>,
    cameras: Query<'w, 's, (&'static ViewShadowBindings, &'static ViewLightEntities)>,
}

impl Lights<'_, '_> {
    /// The kind of the light view `entity`.
    pub fn kind(&self, entity: Entity) -> Option<&LightEntity> {
        self.kinds.get(entity).ok().map(|(_, k)| k)
    }

    /// The views of point and spot lights with [`HrocCulling`], each with
    /// the layer Bevy's `prepare_lights` gives it: a point light's faces
    /// are layers `6 i` to `6 i + 5` of the point lights' cube map array,
    /// `i` its index among Bevy's clustered lights (point lights first);
    /// a spot light's layer of the directional shadow map follows the
    /// most directional cascades any camera has. Both maps are shared by
    /// every camera (any camera's `ViewShadowBindings` holds them).
    pub fn culled(&self) -> Vec<LightView> {
        let (Some(meta), Some((bindings, _))) = (self.meta.as_ref(), self.cameras.iter().next()) else { return Vec::new() };
        let point_lights = self.points.iter().filter(|l| l.spot_light_angles.is_none()).count();
        let cascades =
            self.cameras.iter().map(|(_, lights)| lights.lights.iter().filter(|&&l| matches!(self.kind(l), Some(LightEntity::Directional { .. }))).count()).max().unwrap_or(0);
        let mut views = Vec::new();
        for (entity, kind) in &self.kinds {
            let Some(light) = point_or_spot(kind) else { continue };
            let (Ok(culling), Some(&index)) = (self.culling.get(light), meta.entity_to_index.get(&light)) else { continue };
            let (texture, layer, who) = match *kind {
                LightEntity::Point { face_index, .. } => (&bindings.point_light_depth_texture, index * 6 + face_index, format!("point light {light}, face {face_index}")),
                _ => (&bindings.directional_light_depth_texture, cascades + index.saturating_sub(point_lights), format!("spot light {light}")),
            };
            let texture: &wgpu::Texture = texture;
            if layer as u32 >= texture.depth_or_array_layers() {
                continue;
            }
            views.push(LightView { entity, method: crate::views::method_without_ids(culling.method), texture: texture.clone(), layer: layer as u32, who });
        }
        views
    }
}
