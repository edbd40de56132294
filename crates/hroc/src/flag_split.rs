//! [`FlagSplit`]: per-object flags applied to the lists a method hands
//! the host.

use crate::compact::Compactor;
use crate::contract::DrawList;
use crate::gpu::shape::{EncoderShape, PassShape};
use crate::gpu::{dispatch_size, Gpu, PassCount, Uploads};
use crate::objects::SharedObjects;
use crate::shaders;

/// Splits every list a method hands the host by object flags: commands of
/// flagged objects are emptied (instance_count 0, order kept); the
/// NOT_OCCLUDER ones are collected and handed back together at the end of
/// the frame; the CUTOUT ones go to a cutout list of the same slots,
/// handed right after the list. Only built when some object has a flag,
/// so scenes without flags pay nothing.
pub(crate) struct FlagSplit {
    pub(super) pipeline: wgpu::ComputePipeline,
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) deferred: wgpu::Buffer,
    /// Per list split this frame: its output commands, its parameters
    /// and its cutout list's commands.
    pub(super) pool: Vec<(wgpu::Buffer, wgpu::Buffer, wgpu::Buffer)>,
    /// Some object is CUTOUT this frame.
    pub(super) cutouts: bool,
    pub(super) used: usize,
    pub(super) compactor: Compactor,
    pub(super) list: DrawList,
    pub(super) job: crate::compact::CompactJob,
}

impl FlagSplit {
    pub(super) fn new(gpu: &Gpu, objects: &SharedObjects) -> Self {
        let n = objects.count;
        use wgpu::BufferUsages as U;
        let layout = crate::reflect::Layout::FlagSplit.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "hroc flag split", &layout);
        let module = gpu.shader("split.wgsl", &shaders::source("split.wgsl"));
        let deferred = gpu.buffer("hroc non-occluders", n as u64 * 4, U::STORAGE | U::COPY_DST);
        let compactor = Compactor::new(gpu, n);
        let (list, job) = compactor.packed_list(gpu, "hroc non-occluders list", &deferred, &objects.commands);
        FlagSplit { pipeline: gpu.compute_pipeline(&module, "split", Some(&pl), &[]), layout, deferred, pool: Vec::new(), used: 0, cutouts: false, list, compactor, job }
    }

    /// Begins a frame; `cutouts`: some object is CUTOUT.
    pub(super) fn begin(&mut self, enc: &mut wgpu::CommandEncoder, objects: &SharedObjects, cutouts: bool) {
        self.used = 0;
        self.cutouts = cutouts;
        enc.counted_copy(&objects.always_deferred, 0, &self.deferred, 0, objects.count as u64 * 4);
    }

    /// Splits `list`: the commands of objects with a flag of `empty`
    /// emptied, and with CUTOUT objects this frame, their cutout list.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn split(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        uploads: &mut Uploads,
        bounds: &wgpu::Buffer,
        list: &DrawList,
        count: &PassCount,
        empty: u32,
    ) -> (DrawList, Option<DrawList>) {
        use wgpu::BufferUsages as U;
        let need = (list.commands.size() / 20).max(1) * 20;
        let commands = |label| gpu.buffer(label, need, U::STORAGE | U::INDIRECT | U::COPY_SRC);
        if self.used == self.pool.len() {
            self.pool.push((commands("hroc split list"), gpu.buffer("hroc split bound", 16, U::UNIFORM | U::COPY_DST), commands("hroc cutout list")));
        } else if self.pool[self.used].0.size() < need {
            (self.pool[self.used].0, self.pool[self.used].2) = (commands("hroc split list"), commands("hroc cutout list"));
        }
        let (dst, bound, cut) = self.pool[self.used].clone();
        self.used += 1;
        uploads.write(enc, &bound, 0, bytemuck::cast_slice(&[list.max_count, empty, self.cutouts as u32, 0]));
        let bind = gpu.bind_buffers(&self.layout, &[bounds, &list.commands, &list.count, &dst, &self.deferred, &bound, &cut]);
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc flag split"), timestamp_writes: None });
        let (x, y) = dispatch_size(list.max_count, 256);
        count.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.counted_dispatch(x, y, 1);
        });
        drop(pass);
        let cutouts = self.cutouts.then(|| DrawList { commands: cut, count: list.count.clone(), max_count: list.max_count });
        (DrawList { commands: dst, count: list.count.clone(), max_count: list.max_count }, cutouts)
    }

    /// Non-occluders the method drew this frame, plus the never-culled ones, packed.
    pub(super) fn finish(&mut self, enc: &mut wgpu::CommandEncoder, count: &PassCount) -> DrawList {
        self.compactor.record(enc, count, &self.job);
        self.list.clone()
    }
}
