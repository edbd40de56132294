//! Visibility marks read from the object-ID target ([`Marks::Ids`]): where
//! a device has no forced early-Z (DX12, Metal), the host's fragment
//! shaders cannot mark their objects, so after each occluding list whose
//! marks a method reads, one compute pass marks every object that owns a
//! pixel of the ID target (`id_marks.wgsl`).
//!
//! The marks then mean "owns a pixel after this list, and is one of the
//! objects a given set holds" rather than "had a fragment pass the depth
//! test while drawn". Of the list's own objects this is a subset (one
//! overdrawn later in the frame, or by a later object of the same list, is
//! not marked), and every method that reads marks stays conservative with
//! it: an unmarked object is only left out of the next frame's occluders
//! and tested like any other (`roc`, `ioc`, HROC's O and D). Pixels the
//! list did not draw (never-culled objects, the host's own geometry with
//! IDs of its own) may hold any ID: where a mark would skip an object's
//! test (HROC's O), the set is the list's own objects, so no such pixel
//! marks an object that was neither drawn nor tested.
//!
//! [`Marks::Ids`]: crate::capabilities::Marks::Ids

use crate::gpu::shape::PassShape;
use std::sync::{Arc, Mutex};

use crate::gpu::Gpu;
use crate::reflect::{pipeline_layout, Layout};

/// The ID-marks pass, built once per culler: its pipeline per sample count
/// of the ID targets it reads, each built when first bound.
#[derive(Clone, Debug)]
pub struct IdMarks {
    pipelines: Arc<Mutex<Vec<(u32, wgpu::ComputePipeline, wgpu::BindGroupLayout)>>>,
    /// One u32 1 per object slot: the set that holds every object.
    everyone: wgpu::Buffer,
}

impl IdMarks {
    /// Builds the pass on `gpu`, for `slots` objects.
    pub fn new(gpu: &Gpu, slots: u32) -> IdMarks {
        let everyone = gpu.buffer_init("hroc every object", bytemuck::cast_slice(&vec![1u32; slots as usize]), wgpu::BufferUsages::STORAGE);
        IdMarks { pipelines: Default::default(), everyone }
    }

    /// The pass from `ids` (a view of an `R32Uint` or `Rg16Uint` target,
    /// `size` pixels of `samples` samples) into `marks`, of the objects
    /// `within` flags (u32 per object, nonzero: in the set), or of every
    /// object.
    pub fn bind(&self, gpu: &Gpu, ids: &wgpu::TextureView, (size, samples): ((u32, u32), u32), marks: &wgpu::Buffer, within: Option<&wgpu::Buffer>) -> IdPass {
        let mut built = self.pipelines.lock().unwrap_or_else(|p| p.into_inner());
        if !built.iter().any(|(n, ..)| *n == samples) {
            let module = gpu.shader("id_marks.wgsl", &crate::shaders::source_for("id_marks.wgsl", samples));
            let layout = Layout::IdMarks.create_for(gpu, samples);
            let pipeline = gpu.compute_pipeline(&module, "mark_ids", Some(&pipeline_layout(gpu, Layout::IdMarks.label(), &layout)), &[]);
            built.push((samples, pipeline, layout));
        }
        let (_, pipeline, layout) = built.iter().find(|(n, ..)| *n == samples).expect("built above");
        let within = within.unwrap_or(&self.everyone);
        let resources = [(0, wgpu::BindingResource::TextureView(ids)), (1, marks.as_entire_binding()), (2, within.as_entire_binding())];
        IdPass { pipeline: pipeline.clone(), bind: Layout::IdMarks.bind(gpu, layout, &resources), size }
    }
}

/// One method's ID-marks pass into one marks buffer.
#[derive(Clone, Debug)]
pub struct IdPass {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    size: (u32, u32),
}

impl IdPass {
    /// Records the pass: one thread per pixel of the ID target.
    pub fn record<'p>(&self, pass: &mut wgpu::ComputePass<'p>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.counted_dispatch(self.size.0.div_ceil(16), self.size.1.div_ceil(16), 1);
    }
}
