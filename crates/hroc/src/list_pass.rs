//! [`ListPass`]: a compute pass run on one draw list at a time, its threads
//! striding over the commands up to the list's bound: the zeroed tail of
//! an emulated draw count (`tail.wgsl`), the stamps of visibility as data
//! (`visibility.wgsl`).

use crate::gpu::shape::{EncoderShape, PassShape};
use std::collections::HashMap;

use crate::gpu::{dispatch_size, Gpu, Uploads};
use crate::reflect::{pipeline_layout, Layout};

/// Bind groups kept for the lists seen lately.
const BINDS: usize = 256;

/// Most threads a pass launches: each strides over the commands, so a list
/// of large capacity and few commands (a stall-free overflow list, hzb's
/// occludees at 256k objects) costs a few workgroups, not one thread per
/// slot.
const LIST_THREADS: u32 = 4096;

/// One pass over a list's commands: binding 0 the commands, 1 the GPU
/// count, 2 a uniform `(max_count, word, 0, 0)` written in the encoder
/// before each dispatch, and 3, for passes that have it, a buffer of the
/// pass's own.
pub(crate) struct ListPass {
    which: Layout,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    extra: Option<wgpu::Buffer>,
    /// Per (commands, count): the bindings; lists are mostly the same
    /// buffers every frame.
    binds: HashMap<(wgpu::Buffer, wgpu::Buffer), wgpu::BindGroup>,
}

impl ListPass {
    /// The pass `entry` of `pass` (WGSL workgroups of 64), bound by
    /// `which`, with `extra` at binding 3 and the override `constants`.
    pub(crate) fn new(gpu: &Gpu, which: Layout, (pass, entry): (&str, &str), extra: Option<wgpu::Buffer>, constants: &[(&str, f64)]) -> Self {
        let module = gpu.shader(pass, &crate::shaders::source(pass));
        let layout = which.create(gpu);
        let pipeline = gpu.compute_pipeline(&module, entry, Some(&pipeline_layout(gpu, which.label(), &layout)), constants);
        let params = gpu.buffer(which.label(), 16, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        ListPass { which, pipeline, layout, params, extra, binds: HashMap::new() }
    }

    /// Records the pass over the commands `[0, max_count)` of a list of
    /// `DrawCommand`s whose GPU count is in `count`, with `word` for the
    /// pass in its uniform.
    pub(crate) fn record(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        uploads: &mut Uploads,
        (commands, count, max_count): (&wgpu::Buffer, &wgpu::Buffer, u32),
        word: u32,
    ) {
        if max_count == 0 {
            return;
        }
        uploads.write(enc, &self.params, 0, bytemuck::cast_slice(&[max_count, word, 0, 0]));
        if self.binds.len() > BINDS {
            self.binds.clear();
        }
        let (which, layout, params, extra) = (self.which, &self.layout, &self.params, &self.extra);
        let bind = self.binds.entry((commands.clone(), count.clone())).or_insert_with(|| {
            let mut resources = vec![(0, commands.as_entire_binding()), (1, count.as_entire_binding()), (2, params.as_entire_binding())];
            resources.extend(extra.iter().map(|b| (3, b.as_entire_binding())));
            which.bind(gpu, layout, &resources)
        });
        let (x, y) = dispatch_size(max_count.min(LIST_THREADS), 64);
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.which.label()), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &*bind, &[]);
        pass.counted_dispatch(x, y, 1);
    }
}
