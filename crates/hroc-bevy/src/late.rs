//! Light views whose next frame culls by the frustum alone are, for that
//! frame, views Bevy culls by the frustum.
//!
//! A light view with Bevy's `OcclusionCulling` costs Bevy, every frame,
//! late work items and indirect parameters for each of its batches, and a
//! late shadow pass that records every batch of the view's shadow phase
//! again, one draw each where materials differ (`houses`: 11,000 a
//! cascade), to draw what the occlusion test left. Where hroc's plan for
//! the view's next frame draws nothing late (`hroc::View::plans_late`:
//! HROC's frames of the frustum, where its measurements found occlusion
//! not paying), that is all waste: so once Bevy has made its light views
//! and before it prepares their buffers, [`leave_out`] takes
//! `OcclusionCulling` off such a view for the frame and marks it
//! [`LateLeftOut`]. Bevy then prepares, culls (its own frustum culling,
//! in its preprocessing) and draws it as any view without occlusion
//! culling, in one shadow pass. hroc records the view's frame only where
//! it needs it (`hroc::View::wants_steps`: HROC's frame before a
//! measurement, whose depth makes the measurement's occluders;
//! [`crate::views::prepare`] takes marked views too); the other frames
//! only count toward the next measurement, and on lavapipe a recorded
//! frame of the frustum cost a cascade of `houses` 2-3 ms. Bevy's
//! `prepare_lights` (a directional cascade) or the plugin's
//! `crate::lights::mark` (a point or spot light's view) gives
//! `OcclusionCulling` back the next frame, and the plan is made again. Either way the view's depth is that of drawing
//! everything its frustum holds.

use bevy_ecs::prelude::*;
use bevy_pbr::LightEntity;
use bevy_render::occlusion_culling::OcclusionCulling;
use bevy_render::view::ExtractedView;

use crate::objects::HrocObjects;
use crate::views::HrocView;

/// On a light view that this frame Bevy culls by the frustum alone, where
/// the plugin took `OcclusionCulling` off it.
#[derive(Component, Clone, Copy, Debug)]
pub struct LateLeftOut;

/// Render world, once Bevy and the plugin have given this frame's light
/// views `OcclusionCulling` and before Bevy prepares their buffers: last
/// frame's marks go, and each light view hroc culls whose next frame
/// draws nothing late loses `OcclusionCulling` and is marked.
pub fn leave_out(
    mut commands: Commands,
    marked: Query<Entity, With<LateLeftOut>>,
    mut views: Query<(Entity, &mut HrocView, &ExtractedView, &LightEntity), With<OcclusionCulling>>,
    objects: Res<HrocObjects>,
) {
    for entity in &marked {
        commands.entity(entity).remove::<LateLeftOut>();
    }
    let Some(culler) = objects.culler.as_ref() else { return };
    for (entity, mut view, extracted, kind) in &mut views {
        let cascade = matches!(kind, LightEntity::Directional { .. });
        if !view.plans_late(culler, extracted, cascade) {
            commands.entity(entity).remove::<OcclusionCulling>().insert(LateLeftOut);
        }
    }
}
