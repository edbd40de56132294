//! The `Core3d` systems that hand Bevy hroc's command buffers at the
//! points of its frame where hroc's steps belong: before the early
//! preprocessing, after the early passes (the camera's prepass and its
//! cascades' early shadow passes, or a point or spot light view's early
//! shadow pass in its own `Core3d` run), after the late ones. Bevy submits
//! a view's command buffers in the order of its systems.

use bevy_ecs::prelude::*;
use bevy_pbr::ViewLightEntities;
use bevy_render::renderer::{RenderContext, ViewQuery};

use crate::views::{HrocView, StepBuffers};

/// Which of a frame's three steps.
#[derive(Clone, Copy)]
enum Step {
    Begin,
    OccludersDrawn,
    OccludeesDrawn,
}

fn take(view: &HrocView, step: Step) -> Option<wgpu::CommandBuffer> {
    let mut steps = view.steps.lock().unwrap_or_else(|p| p.into_inner());
    let StepBuffers { begin, occluders_drawn, occludees_drawn } = &mut *steps;
    match step {
        Step::Begin => begin.take(),
        Step::OccludersDrawn => occluders_drawn.take(),
        Step::OccludeesDrawn => occludees_drawn.take(),
    }
}

fn submit(step: Step, current: ViewQuery<Option<&ViewLightEntities>>, views: Query<&HrocView>, ctx: &mut RenderContext) {
    let camera = current.entity();
    let lights = current.into_inner().map(|l| l.lights.clone()).unwrap_or_default();
    for entity in std::iter::once(camera).chain(lights) {
        if let Some(buffer) = views.get(entity).ok().and_then(|v| take(v, step)) {
            ctx.add_command_buffer(buffer);
        }
    }
}

/// Before the early preprocessing.
pub fn begin(current: ViewQuery<Option<&ViewLightEntities>>, views: Query<&HrocView>, mut ctx: RenderContext) {
    submit(Step::Begin, current, views, &mut ctx);
}

/// After the early prepass and early shadow passes.
pub fn occluders_drawn(current: ViewQuery<Option<&ViewLightEntities>>, views: Query<&HrocView>, mut ctx: RenderContext) {
    submit(Step::OccludersDrawn, current, views, &mut ctx);
}

/// After the late prepass and late shadow passes.
pub fn occludees_drawn(current: ViewQuery<Option<&ViewLightEntities>>, views: Query<&HrocView>, mut ctx: RenderContext) {
    submit(Step::OccludeesDrawn, current, views, &mut ctx);
}
