//! Bevy without a window on lavapipe, frames driven by hand: what the
//! plugin's test and its comparison example share.

use bevy::app::{PluginGroupBuilder, PluginsState};
use bevy::prelude::*;
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::render::{RenderDebugFlags, RenderPlugin};
use bevy::window::ExitCondition;

/// Bevy's default plugins on Vulkan, no window, pipelines compiled when
/// queued, the render world run within each update; assets read from
/// `assets` when given.
pub fn plugins(debug_flags: RenderDebugFlags, assets: Option<String>) -> PluginGroupBuilder {
    let group = DefaultPlugins
        .set(WindowPlugin { primary_window: None, exit_condition: ExitCondition::DontExit, close_when_requested: false, ..default() })
        .set(RenderPlugin {
            render_creation: RenderCreation::Automatic(Box::new(WgpuSettings { backends: Some(Backends::VULKAN), ..default() })),
            synchronous_pipeline_compilation: true,
            debug_flags,
        })
        .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>()
        // No display: no event loop (the windowed example has one).
        .disable::<bevy::winit::WinitPlugin>();
    match assets {
        Some(dir) => group.set(AssetPlugin { file_path: dir, ..default() }),
        None => group,
    }
}

/// Finishes building `app` as its runner would, without running it.
pub fn start(app: &mut App) {
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
}
