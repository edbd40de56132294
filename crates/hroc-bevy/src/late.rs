//! Light views whose frame draws nothing in the late pass leave it out.
//!
//! Bevy runs a light view's late shadow pass wherever the view has
//! `OcclusionCulling`: it builds the pass's indirect parameters and
//! records every batch of the view's shadow phase again, one draw each
//! where materials differ (`houses`: 11,000 a cascade), to draw what the
//! occlusion test left. Where hroc's frame hands no occludees
//! (`hroc::Steps::late` false: HROC's frames of the frustum, where
//! occlusion does not pay in the view), that pass draws nothing, and it
//! cost the plugin's `houses` cascades more than their culling saved.
//! So once the frame's steps are recorded, such a view loses Bevy's
//! `OcclusionCulling` for the frame's render ([`leave_out`]): Bevy's late
//! shadow pass returns at once for a view without it, and the plugin's
//! late preprocessing skips it. Its buffers and bind groups were prepared
//! with it, and Bevy's `prepare_lights` (a directional cascade) or the
//! plugin's `crate::lights::mark` (a point or spot light's view) gives it
//! back the next frame, before they are prepared again. The plugin's
//! early preprocessing reads [`LateLeftOut`] as occlusion culling still.

use bevy_ecs::prelude::*;
use bevy_pbr::LightEntity;
use bevy_render::occlusion_culling::OcclusionCulling;

use crate::views::{HrocFrame, HrocView};

/// On a light view whose late pass this frame (the number) leaves out.
#[derive(Component, Clone, Copy, Debug)]
pub struct LateLeftOut(pub u64);

/// Render world, after the bind groups are prepared and before Bevy's
/// render: light views whose steps this frame recorded with no late draws
/// lose `OcclusionCulling` for the frame.
pub fn leave_out(mut commands: Commands, views: Query<(Entity, &HrocView), (With<OcclusionCulling>, With<LightEntity>)>, frame: Res<HrocFrame>) {
    for (entity, view) in &views {
        if view.recorded == frame.0 && !view.late {
            commands.entity(entity).remove::<OcclusionCulling>().insert(LateLeftOut(frame.0));
        }
    }
}

/// Whether a view culled by occlusion this frame: it has
/// `OcclusionCulling`, or [`leave_out`] took it off for this frame.
pub fn occlusion(has: bool, left_out: Option<&LateLeftOut>, frame: &HrocFrame) -> bool {
    has || left_out.is_some_and(|l| l.0 == frame.0)
}
