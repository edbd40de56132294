//! Frustum culling of a set of views in one compute pass
//! (`set_frustum.wgsl`): the views of a [`crate::Culler::cull_views`] call
//! that cull by their frustum alone this frame (`vfc`, and HROC where its
//! gate found that occlusion does not pay) are packed by one dispatch
//! each, of one workgroup, in a pass the set shares, in place of a pass of
//! their own with a frustum test, a three-dispatch compaction and a tally
//! each. The set's frame then costs one pass and a dispatch per such view,
//! however many views a light has, as Unreal Engine's instance culling
//! takes a frame's views as one packed array.
//!
//! One workgroup walks every object of its view in blocks of 2,048, so the
//! set packs views of at most [`SET_OBJECTS`] object slots; a culler with
//! more culls each view in its own frame.

use std::collections::HashMap;

use crate::contract::DrawList;
use crate::gpu::shape::PassShape;
use crate::gpu::Gpu;
use crate::reflect::{pipeline_layout, Layout};

/// Most object slots a set's workgroup walks (64 blocks of 2,048): past
/// them a view's own compaction, spread over many workgroups, is faster.
pub const SET_OBJECTS: u32 = 64 * 2048;

/// Bind groups kept for the views seen lately.
const BINDS: usize = 256;

/// The buffers one view's workgroup binds: its frame uniform, the
/// objects' boxes and commands, its list's commands and count, its tally.
type Key = [wgpu::Buffer; 6];

/// The set's pass and the bind groups of the views it has packed.
pub(crate) struct SetFrustum {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    binds: std::sync::Mutex<HashMap<Key, wgpu::BindGroup>>,
}

/// One view's part of a set's pass: the bind group of its workgroup.
#[derive(Clone)]
pub(crate) struct SetJob(wgpu::BindGroup);

impl SetFrustum {
    /// The pass; `zero_tail` with an emulated draw count (the lists'
    /// commands past their count are emptied by the pass).
    pub(crate) fn new(gpu: &Gpu, zero_tail: bool) -> Self {
        let module = gpu.shader("set_frustum.wgsl", &crate::shaders::source("set_frustum.wgsl"));
        let layout = Layout::SetFrustum.create(gpu);
        let pl = pipeline_layout(gpu, Layout::SetFrustum.label(), &layout);
        let pipeline = gpu.compute_pipeline(&module, "pack", Some(&pl), &[("ZERO_TAIL", if zero_tail { 1.0 } else { 0.0 })]);
        SetFrustum { pipeline, layout, binds: std::sync::Mutex::new(HashMap::new()) }
    }

    /// The job packing `list` (of at most `bounds`' objects) for the view
    /// of `frame`, its count and tally written in place.
    pub(crate) fn job(&self, gpu: &Gpu, frame: &wgpu::Buffer, bounds: &wgpu::Buffer, commands: &wgpu::Buffer, list: &DrawList, totals: &wgpu::Buffer) -> SetJob {
        let key: Key = [frame.clone(), bounds.clone(), commands.clone(), list.commands.clone(), list.count.clone(), totals.clone()];
        let mut binds = self.binds.lock().unwrap_or_else(|p| p.into_inner());
        if binds.len() > BINDS {
            binds.clear();
        }
        let bind = binds.entry(key).or_insert_with_key(|k| {
            let resources: Vec<(u32, wgpu::BindingResource)> = k.iter().enumerate().map(|(i, b)| (i as u32, b.as_entire_binding())).collect();
            Layout::SetFrustum.bind(gpu, &self.layout, &resources)
        });
        SetJob(bind.clone())
    }

    /// Records the set's pass: a workgroup for each job.
    pub(crate) fn record(&self, pass: &mut wgpu::ComputePass<'_>, jobs: &[SetJob]) {
        pass.set_pipeline(&self.pipeline);
        for SetJob(bind) in jobs {
            pass.set_bind_group(0, bind, &[]);
            pass.counted_dispatch(1, 1, 1);
        }
    }
}
