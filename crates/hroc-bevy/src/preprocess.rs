//! The early and late mesh preprocessing of a frame, in place of Bevy's
//! `early_gpu_preprocess` and `late_gpu_preprocess` systems: the same
//! dispatches over Bevy's work items with Bevy's bind groups, where a view
//! culled by hroc runs the patched shader (`crate::shader`) with hroc's
//! visibility at group 1. Views hroc does not cull run Bevy's own
//! pipelines as Bevy would. The late pass also runs for a camera's
//! directional cascades culled by hroc, so their occludees reach Bevy's
//! late shadow pass, and for point and spot lights' views culled by hroc,
//! in their own `Core3d` runs. A view whose steps were not recorded this
//! frame draws everything early.

use bevy_ecs::prelude::*;
use bevy_pbr::{LightEntity, MeshInputUniform, MeshUniform, PhasePreprocessBindGroups, PreprocessBindGroups, PreprocessPipelines, SkipGpuPreprocess, ViewLightEntities};
use bevy_render::batching::gpu_preprocessing::{
    BatchedInstanceBuffers, GpuOcclusionCullingWorkItemBuffers, LatePreprocessWorkItemIndirectParameters, PreprocessWorkItemBuffers, UntypedPhaseBatchedInstanceBuffers,
};
use bevy_render::occlusion_culling::OcclusionCulling;
use bevy_render::render_resource::{BindGroupLayoutDescriptor, CachedComputePipelineId, ComputePipelineDescriptor, PipelineCache};
use bevy_render::renderer::{RenderContext, ViewQuery};
use bevy_render::view::{ExtractedView, NoIndirectDrawing, ViewUniformOffset};

use crate::shader::HrocShaders;
use crate::views::HrocView;

/// Work items per workgroup of Bevy's preprocessing shader.
const WORKGROUP_SIZE: usize = 64;

impl HrocPipelines {
    /// Both patched pipelines compiled.
    pub fn compiled(&self, cache: &PipelineCache) -> bool {
        [self.early, self.late].iter().all(|id| id.is_some_and(|id| cache.get_compute_pipeline(id).is_some()))
    }
}

/// Group 1 of the patched shaders: hroc's visibility, and the map from
/// Bevy's input index to hroc's slot.
#[derive(Resource)]
pub struct HrocLayout {
    pub desc: BindGroupLayoutDescriptor,
    pub layout: wgpu::BindGroupLayout,
}

/// The patched pipelines, once queued, and group 1 for views hroc does
/// not cull: no visibility, so everything is drawn early.
#[derive(Resource, Default)]
pub struct HrocPipelines {
    pub early: Option<CachedComputePipelineId>,
    pub late: Option<CachedComputePipelineId>,
    pub everything_early: Option<wgpu::BindGroup>,
}

/// Render world: group 1's layout, and the two pipelines once the patched
/// shaders exist.
pub fn queue_pipelines(
    mut commands: Commands,
    layout: Option<Res<HrocLayout>>,
    mut pipelines: ResMut<HrocPipelines>,
    shaders: Res<HrocShaders>,
    bevy: Res<PreprocessPipelines>,
    cache: Res<PipelineCache>,
    device: Res<bevy_render::renderer::RenderDevice>,
) {
    let Some(layout) = layout else {
        let desc = BindGroupLayoutDescriptor::new("hroc visibility", &crate::views::bind_group_layout_entries());
        let layout = (*cache.get_bind_group_layout(&desc)).clone();
        commands.insert_resource(HrocLayout { desc, layout });
        return;
    };
    if pipelines.everything_early.is_none() {
        let device = device.wgpu_device();
        let empty = |label| {
            let b = device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: 16, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: true });
            b.slice(..).get_mapped_range_mut().unwrap().copy_from_slice(&[0xff; 16]);
            b.unmap();
            b
        };
        let (visibility, slots) = (empty("hroc no visibility"), empty("hroc no slots"));
        pipelines.everything_early = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hroc everything early"),
            layout: &layout.layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: visibility.as_entire_binding() }, wgpu::BindGroupEntry { binding: 1, resource: slots.as_entire_binding() }],
        }));
    }
    if pipelines.early.is_some() {
        return;
    }
    let (Some(early), Some(late)) = (shaders.early.clone(), shaders.late.clone()) else { return };
    let queue = |label: &'static str, shader, phase: &'static str, group0: &BindGroupLayoutDescriptor| {
        cache.queue_compute_pipeline(ComputePipelineDescriptor {
            label: Some(label.into()),
            layout: vec![group0.clone(), layout.desc.clone()],
            immediate_size: 4,
            shader,
            shader_defs: ["WRITE_INDIRECT_PARAMETERS_METADATA", "INDIRECT", "FRUSTUM_CULLING", "OCCLUSION_CULLING", phase].into_iter().map(Into::into).collect(),
            entry_point: None,
            zero_initialize_workgroup_memory: true,
            constants: Vec::new(),
        })
    };
    pipelines.early = Some(queue("hroc early mesh preprocessing", early, "EARLY_PHASE", &bevy.early_gpu_occlusion_culling_preprocess.bind_group_layout));
    pipelines.late = Some(queue("hroc late mesh preprocessing", late, "LATE_PHASE", &bevy.late_gpu_occlusion_culling_preprocess.bind_group_layout));
}

/// A camera's view and its directional cascades.
fn with_cascades(view: Entity, lights: Option<&ViewLightEntities>, light_query: &Query<&LightEntity>) -> Vec<Entity> {
    let mut all = vec![view];
    for &light in lights.map(|l| l.lights.as_slice()).unwrap_or_default() {
        if matches!(light_query.get(light), Ok(LightEntity::Directional { .. })) {
            all.push(light);
        }
    }
    all
}

/// Whether `view` is a point or spot light's view.
fn point_or_spot(light_query: &Query<&LightEntity>, view: Entity) -> bool {
    light_query.get(view).ok().and_then(crate::lights::point_or_spot).is_some()
}

type ViewItem<'a> = (&'a ExtractedView, Option<&'a PreprocessBindGroups>, Option<&'a ViewUniformOffset>, Has<NoIndirectDrawing>, Has<OcclusionCulling>, Option<&'a HrocView>);

/// What both dispatches read: the views, Bevy's work items and
/// pipelines, and ours.
#[derive(bevy_ecs::system::SystemParam)]
pub struct Dispatch<'w, 's> {
    views: Query<'w, 's, ViewItem<'static>, Without<SkipGpuPreprocess>>,
    light_query: Query<'w, 's, &'static LightEntity>,
    buffers: Res<'w, BatchedInstanceBuffers<MeshUniform, MeshInputUniform>>,
    cache: Res<'w, PipelineCache>,
    bevy: Res<'w, PreprocessPipelines>,
    ours: Res<'w, HrocPipelines>,
    frame: Res<'w, crate::views::HrocFrame>,
}

/// In place of Bevy's `early_gpu_preprocess`.
pub fn early_preprocess(current: ViewQuery<Option<&ViewLightEntities>, Without<SkipGpuPreprocess>>, d: Dispatch, mut ctx: RenderContext) {
    let Dispatch { views, light_query, buffers, cache, bevy, ours, frame } = d;
    let entity = current.entity();
    let all = with_cascades(entity, current.into_inner(), &light_query);
    let encoder = ctx.command_encoder();
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("early mesh preprocessing (hroc)"), timestamp_writes: None });
    for view_entity in all {
        let Ok((view, Some(bind_groups), Some(offset), no_indirect, occlusion, hroc)) = views.get(view_entity) else { continue };
        let hroc_group = hroc.filter(|h| h.recorded == frame.0).and_then(|h| h.bind_group.as_ref()).filter(|_| occlusion && !no_indirect);
        let (id, group1) = match (hroc_group, ours.early) {
            (Some(g), Some(id)) => (Some(id), Some(g)),
            _ if no_indirect => (bevy.direct_preprocess.pipeline_id, None),
            // A view hroc does not cull, or until the plugin's pipelines
            // compile, where Bevy's Hi-Z is still there: Bevy's test. A
            // culled camera's view before that: everything early.
            // (Bevy never builds a point or spot light view's Hi-Z.)
            _ if occlusion && (hroc.is_some() || point_or_spot(&light_query, view_entity)) && ours.early.is_some() && ours.everything_early.is_some() => {
                (ours.early, ours.everything_early.as_ref())
            }
            _ if occlusion => (bevy.early_gpu_occlusion_culling_preprocess.pipeline_id, None),
            _ => (bevy.gpu_frustum_culling_preprocess.pipeline_id, None),
        };
        let Some(pipeline) = id.and_then(|id| cache.get_compute_pipeline(id)) else { continue };
        pass.set_pipeline(pipeline);
        if let Some(g) = group1 {
            pass.set_bind_group(1, g, &[]);
        }
        let offsets = [offset.offset];
        for (phase, phase_buffers) in &buffers.phase_instance_buffers {
            let (Some(items), Some(groups)) = (phase_buffers.work_item_buffers.get(&view.retained_view_entity), bind_groups.get(phase)) else { continue };
            match (groups, items) {
                (PhasePreprocessBindGroups::Direct(group), PreprocessWorkItemBuffers::Direct(list)) => {
                    pass.set_bind_group(0, Some(&**group), &offsets);
                    dispatch(&mut pass, list.len());
                }
                (
                    PhasePreprocessBindGroups::IndirectFrustumCulling { indexed, non_indexed }
                    | PhasePreprocessBindGroups::IndirectOcclusionCulling { early_indexed: indexed, early_non_indexed: non_indexed, .. },
                    PreprocessWorkItemBuffers::Indirect { indexed: indexed_items, non_indexed: non_indexed_items, gpu_occlusion_culling },
                ) => {
                    let late = gpu_occlusion_culling.as_ref();
                    for (group, count, late_offset) in [
                        (indexed, indexed_items.len(), late.map(|l| l.late_indirect_parameters_indexed_offset)),
                        (non_indexed, non_indexed_items.len(), late.map(|l| l.late_indirect_parameters_non_indexed_offset)),
                    ] {
                        let Some(group) = group else { continue };
                        if let Some(o) = late_offset {
                            pass.set_immediates(0, bytemuck::bytes_of(&o));
                        }
                        pass.set_bind_group(0, Some(&**group), &offsets);
                        dispatch(&mut pass, count);
                    }
                }
                _ => {}
            }
        }
    }
}

fn dispatch(pass: &mut wgpu::ComputePass<'_>, items: usize) {
    let groups = items.div_ceil(WORKGROUP_SIZE);
    if groups > 0 {
        pass.dispatch_workgroups(groups as u32, 1, 1);
    }
}

/// In place of Bevy's `late_gpu_preprocess`, for the camera and, where
/// hroc culls them, its directional cascades.
pub fn late_preprocess(
    current: ViewQuery<Option<&ViewLightEntities>, Without<SkipGpuPreprocess>>,
    d: Dispatch,
    prepass: Query<(), With<bevy_core_pipeline::prepass::DepthPrepass>>,
    mut ctx: RenderContext,
) {
    let Dispatch { views, light_query, buffers, cache, bevy, ours, frame } = d;
    let camera = current.entity();
    let all = with_cascades(camera, current.into_inner(), &light_query);
    let encoder = ctx.command_encoder();
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("late mesh preprocessing (hroc)"), timestamp_writes: None });
    for view_entity in all {
        let Ok((view, Some(bind_groups), Some(offset), no_indirect, occlusion, hroc)) = views.get(view_entity) else { continue };
        if no_indirect || !occlusion {
            continue;
        }
        let hroc_group = hroc.filter(|h| h.recorded == frame.0).and_then(|h| h.bind_group.as_ref());
        let (id, group1) = match (hroc_group, ours.late) {
            (Some(g), Some(id)) => (Some(id), Some(g)),
            // A camera hroc does not cull: Bevy's late pass (a camera with a
            // depth prepass only, as Bevy runs it).
            _ if hroc.is_none() && view_entity == camera && prepass.contains(camera) => (bevy.late_gpu_occlusion_culling_preprocess.pipeline_id, None),
            _ => continue,
        };
        let Some(pipeline) = id.and_then(|id| cache.get_compute_pipeline(id)) else { continue };
        pass.set_pipeline(pipeline);
        if let Some(g) = group1 {
            pass.set_bind_group(1, g, &[]);
        }
        let offsets = [offset.offset];
        for (phase, phase_buffers) in &buffers.phase_instance_buffers {
            let UntypedPhaseBatchedInstanceBuffers { work_item_buffers, late_indexed_indirect_parameters_buffer, late_non_indexed_indirect_parameters_buffer, .. } = phase_buffers;
            let (
                Some(PreprocessWorkItemBuffers::Indirect {
                    gpu_occlusion_culling: Some(GpuOcclusionCullingWorkItemBuffers { late_indirect_parameters_indexed_offset, late_indirect_parameters_non_indexed_offset, .. }),
                    ..
                }),
                Some(PhasePreprocessBindGroups::IndirectOcclusionCulling { late_indexed, late_non_indexed, .. }),
                Some(indexed_args),
                Some(non_indexed_args),
            ) = (
                work_item_buffers.get(&view.retained_view_entity),
                bind_groups.get(phase),
                late_indexed_indirect_parameters_buffer.buffer(),
                late_non_indexed_indirect_parameters_buffer.buffer(),
            )
            else {
                continue;
            };
            let stride = size_of::<LatePreprocessWorkItemIndirectParameters>() as u64;
            for (group, late_offset, args) in
                [(late_indexed, *late_indirect_parameters_indexed_offset, indexed_args), (late_non_indexed, *late_indirect_parameters_non_indexed_offset, non_indexed_args)]
            {
                let Some(group) = group else { continue };
                pass.set_immediates(0, bytemuck::bytes_of(&late_offset));
                pass.set_bind_group(0, Some(&**group), &offsets);
                pass.dispatch_workgroups_indirect(args, late_offset as u64 * stride);
            }
        }
    }
}
