//! hroc's views of Bevy's cameras: one `hroc::View` per camera with
//! [`HrocCulling`](crate::HrocCulling), on the camera's depth texture
//! (reversed depth, as Bevy draws), culled stepwise each frame
//! (`hroc::View::steps`); the three command buffers wait on the camera's
//! render entity for the `Core3d` systems that submit them between Bevy's
//! passes (`crate::steps`).

use std::sync::Mutex;

use bevy_ecs::prelude::*;
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
    /// The depth texture and method the view was made for.
    key: (wgpu::Texture, Method),
    /// This frame's command buffers, taken by the `Core3d` systems.
    pub steps: Mutex<StepBuffers>,
    /// Visibility and slot map, at group 1 of the preprocessing shaders.
    pub bind_group: Option<wgpu::BindGroup>,
    /// The buffers the bind group holds.
    bound: Option<(wgpu::Buffer, wgpu::Buffer)>,
}

/// The newest frame statistics of a camera's hroc view that have come
/// back (`hroc::View::frame_stats`: objects drawn, tagged with their
/// frame), on the camera's render entity.
#[derive(Component, Clone, Copy, Debug)]
pub struct HrocFrameStats(pub hroc::stats::FrameStats);

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

fn view_desc(view: &ExtractedView) -> ViewDesc {
    let world_from_view = glam::Mat4::from_cols_array(&view.world_from_view.to_matrix().to_cols_array());
    let proj = glam::Mat4::from_cols_array(&view.clip_from_view.to_cols_array());
    ViewDesc { view: world_from_view.inverse(), proj, unclipped_depth: false }
}

impl HrocView {
    /// Records this frame's steps, and group 1 where the buffers changed.
    fn record(
        &mut self,
        culler: &hroc::Culler,
        input: &FrameInput,
        slots: &wgpu::Buffer,
        layout: Option<&crate::preprocess::HrocLayout>,
        device: &wgpu::Device,
    ) -> Option<HrocFrameStats> {
        let view = self.view.get_mut().unwrap_or_else(|p| p.into_inner());
        let stats = view.frame_stats(culler).map(HrocFrameStats);
        let visibility = view.visibility(culler).clone();
        let steps = match view.steps(culler, input) {
            Ok(Steps { begin, occluders_drawn, occludees_drawn }) => {
                StepBuffers { begin: Some(begin), occluders_drawn: Some(occluders_drawn), occludees_drawn: Some(occludees_drawn) }
            }
            Err(e) => {
                bevy_log::error!("hroc-bevy: {e}");
                StepBuffers::default()
            }
        };
        *self.steps.get_mut().unwrap_or_else(|p| p.into_inner()) = steps;
        let Some(layout) = layout else { return stats };
        let bound = (visibility.clone(), slots.clone());
        if self.bound.as_ref() != Some(&bound) {
            self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hroc visibility"),
                layout: &layout.layout,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: visibility.as_entire_binding() }, wgpu::BindGroupEntry { binding: 1, resource: slots.as_entire_binding() }],
            }));
            self.bound = Some(bound);
        }
        stats
    }
}

/// Render world, once Bevy's depth textures and hroc's objects are ready:
/// each culling camera's view made or resized, and its frame recorded.
pub fn prepare(
    mut commands: Commands,
    objects: Res<HrocObjects>,
    device: Res<RenderDevice>,
    layout: Option<Res<crate::preprocess::HrocLayout>>,
    mut cameras: Query<(Entity, &HrocCulling, &ExtractedView, &ViewDepthStencilTexture, Option<&mut HrocView>)>,
    time: Option<Res<bevy_time::Time>>,
) {
    let (Some(culler), Some(slots)) = (objects.culler.as_ref(), objects.slot_buffer.as_ref()) else { return };
    let seconds = time.map_or(0.0, |t| t.elapsed_secs());
    for (entity, culling, extracted, depth, existing) in &mut cameras {
        let method = method_without_ids(culling.method);
        let texture: &wgpu::Texture = depth.texture();
        let key = (texture.clone(), method);
        let targets = ViewTargets::new(texture, DepthRange::Reversed);
        let input = FrameInput { view: view_desc(extracted), cut: false, time: seconds };
        match existing {
            Some(mut v) => {
                if v.key != key {
                    // A new size or texture: the view carries over where it can.
                    let result = v.view.get_mut().unwrap_or_else(|p| p.into_inner()).resize(culler, &targets);
                    if let Err(e) = result {
                        bevy_log::error!("hroc-bevy: {e}");
                        continue;
                    }
                    v.key = key;
                }
                if let Some(stats) = v.record(culler, &input, slots, layout.as_deref(), device.wgpu_device()) {
                    commands.entity(entity).insert(stats);
                }
            }
            None => match culler.view(method, &targets) {
                Ok(view) => {
                    let mut v = HrocView { view: Mutex::new(view), key, steps: Mutex::default(), bind_group: None, bound: None };
                    v.record(culler, &input, slots, layout.as_deref(), device.wgpu_device());
                    commands.entity(entity).insert(v);
                }
                Err(e) => bevy_log::error!("hroc-bevy: {e}"),
            },
        }
    }
}
