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
/// the frame. Only built when some object has a flag, so scenes without
/// flags pay nothing.
pub(crate) struct FlagSplit {
    pub(super) pipeline: wgpu::ComputePipeline,
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) deferred: wgpu::Buffer,
    /// Per list split this frame: its output commands and its bound.
    pub(super) pool: Vec<(wgpu::Buffer, wgpu::Buffer)>,
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
        FlagSplit { pipeline: gpu.compute_pipeline(&module, "split", Some(&pl), &[]), layout, deferred, pool: Vec::new(), used: 0, list, compactor, job }
    }

    pub(super) fn begin(&mut self, enc: &mut wgpu::CommandEncoder, objects: &SharedObjects) {
        self.used = 0;
        enc.counted_copy(&objects.always_deferred, 0, &self.deferred, 0, objects.count as u64 * 4);
    }

    pub(crate) fn split(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, bounds: &wgpu::Buffer, list: &DrawList, count: &PassCount) -> DrawList {
        use wgpu::BufferUsages as U;
        let need = (list.commands.size() / 20).max(1) * 20;
        if self.used == self.pool.len() {
            self.pool.push((gpu.buffer("hroc split list", need, U::STORAGE | U::INDIRECT | U::COPY_SRC), gpu.buffer("hroc split bound", 16, U::UNIFORM | U::COPY_DST)));
        } else if self.pool[self.used].0.size() < need {
            self.pool[self.used].0 = gpu.buffer("hroc split list", need, U::STORAGE | U::INDIRECT | U::COPY_SRC);
        }
        let (dst, bound) = self.pool[self.used].clone();
        self.used += 1;
        uploads.write(enc, &bound, 0, bytemuck::cast_slice(&[list.max_count, 0, 0, 0]));
        let bind = gpu.bind_buffers(&self.layout, &[bounds, &list.commands, &list.count, &dst, &self.deferred, &bound]);
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc flag split"), timestamp_writes: None });
        let (x, y) = dispatch_size(list.max_count, 256);
        count.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.counted_dispatch(x, y, 1);
        });
        drop(pass);
        DrawList { commands: dst, count: list.count.clone(), max_count: list.max_count }
    }

    /// Non-occluders the method drew this frame, plus the never-culled ones, packed.
    pub(super) fn finish(&mut self, enc: &mut wgpu::CommandEncoder, count: &PassCount) -> DrawList {
        self.compactor.record(enc, count, &self.job);
        self.list.clone()
    }
}
