//! GPU ordered compaction: `flags[i] != 0` (or `flags[i] == select`) selects command i; the survivors
//! are packed in order and their number written to a count buffer that the
//! multi-draw-indirect-count reads (HROC §4.1, the prefix-sum packing of Lee's thesis).
//! Lists of at most one block (2,048 items) are packed by one workgroup in
//! one dispatch; longer ones in three (block sums, their scan, scatter).

use crate::contract::DrawList;
use crate::gpu::shape::{EncoderShape, PassShape};
use crate::gpu::{dispatch_size, Gpu, PassCount};
use crate::layout::{CompactParams, DrawCommand};

const WG: u32 = 256;
/// Items per thread (`ITEMS` in `compact.wgsl`): a workgroup packs a block of `WG * ITEMS`.
const ITEMS: u32 = 8;

/// Ordered stream compaction of `n` flagged draw commands: block sums, one scan, scatter.
pub struct Compactor {
    n: u32,
    blocks: u32,
    params: wgpu::Buffer,
    block_sums: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    block_sum: wgpu::ComputePipeline,
    scan_blocks: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    /// The whole compaction of a single block.
    one_block: wgpu::ComputePipeline,
}

/// A compaction bound to its buffers, ready to record.
pub struct CompactJob {
    bind: wgpu::BindGroup,
}

impl Compactor {
    /// A compactor for lists of `n` items.
    pub fn new(gpu: &Gpu, n: u32) -> Self {
        let blocks = n.div_ceil(WG * ITEMS).max(1);
        let params = gpu.buffer_init("compact params", bytemuck::bytes_of(&CompactParams { n, blocks, select: 0, _pad: 0 }), wgpu::BufferUsages::UNIFORM);
        let block_sums = gpu.buffer("block sums", blocks as u64 * 4, wgpu::BufferUsages::STORAGE);
        let layout = crate::reflect::Layout::Compact.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "compact", &layout);
        let module = gpu.shader("compact.wgsl", &crate::shaders::source("compact.wgsl"));
        Compactor {
            n,
            blocks,
            block_sum: gpu.compute_pipeline(&module, "block_sum", Some(&pl), &[]),
            scan_blocks: gpu.compute_pipeline(&module, "scan_blocks", Some(&pl), &[]),
            scatter: gpu.compute_pipeline(&module, "scatter", Some(&pl), &[]),
            one_block: gpu.compute_pipeline(&module, "compact_block", Some(&pl), &[]),
            params,
            block_sums,
            layout,
        }
    }

    /// Number of items (flags and commands) per list.
    pub fn len(&self) -> u32 {
        self.n
    }

    /// True when the lists have no items.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Binds flags (u32 per item), source commands, packed output and count.
    pub fn job(&self, gpu: &Gpu, flags: &wgpu::Buffer, src: &wgpu::Buffer, dst: &wgpu::Buffer, count: &wgpu::Buffer) -> CompactJob {
        CompactJob { bind: gpu.bind_buffers(&self.layout, &[&self.params, flags, src, dst, &self.block_sums, count]) }
    }

    /// Like [`Compactor::job`], selecting only the items whose flag equals `select` (not 0).
    pub fn job_selecting(&self, gpu: &Gpu, flags: &wgpu::Buffer, select: u32, src: &wgpu::Buffer, dst: &wgpu::Buffer, count: &wgpu::Buffer) -> CompactJob {
        let params = CompactParams { n: self.n, blocks: self.blocks, select, _pad: 0 };
        let params = gpu.buffer_init("compact params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
        CompactJob { bind: gpu.bind_buffers(&self.layout, &[&params, flags, src, dst, &self.block_sums, count]) }
    }

    /// A list of up to `len()` commands packed from `src` by `flags`, and
    /// the job that packs it (the usual V and U lists of a culler).
    pub fn packed_list(&self, gpu: &Gpu, label: &str, flags: &wgpu::Buffer, src: &wgpu::Buffer) -> (DrawList, CompactJob) {
        let list = self.list(gpu, label);
        let job = self.job(gpu, flags, src, &list.commands, &list.count);
        (list, job)
    }

    /// An empty list of up to `len()` commands, for a job to pack.
    pub fn list(&self, gpu: &Gpu, label: &str) -> DrawList {
        use wgpu::BufferUsages as U;
        DrawList {
            commands: gpu.buffer(label, self.n as u64 * std::mem::size_of::<DrawCommand>() as u64, U::STORAGE | U::INDIRECT | U::COPY_SRC),
            count: gpu.buffer(label, 4, U::STORAGE | U::INDIRECT | U::COPY_SRC),
            max_count: self.n,
        }
    }

    /// Binds `job` to each of the three pipelines with no work
    /// ([`crate::cull::CullMethod::warm`]).
    pub fn warm(&self, pass: &mut wgpu::ComputePass<'_>, job: &CompactJob) {
        pass.set_bind_group(0, &job.bind, &[]);
        for p in self.pipelines() {
            pass.set_pipeline(p);
            pass.counted_dispatch(0, 0, 0);
        }
    }

    /// The pipelines a compaction runs.
    fn pipelines(&self) -> Vec<&wgpu::ComputePipeline> {
        match self.blocks {
            1 => vec![&self.one_block],
            _ => vec![&self.block_sum, &self.scan_blocks, &self.scatter],
        }
    }

    /// Records the compaction of `job` (one compute pass), counted in `count`.
    pub fn record(&self, enc: &mut wgpu::CommandEncoder, count: &PassCount, job: &CompactJob) {
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("compact"), timestamp_writes: None });
        count.around(&mut pass, |pass| self.record_in(pass, job));
    }

    /// Records the compaction of `job` into an open compute pass: one
    /// dispatch for a single block, else three.
    pub fn record_in(&self, pass: &mut wgpu::ComputePass<'_>, job: &CompactJob) {
        pass.set_bind_group(0, &job.bind, &[]);
        if self.blocks == 1 {
            pass.set_pipeline(&self.one_block);
            pass.counted_dispatch(1, 1, 1);
            return;
        }
        let (x, y) = dispatch_size(self.blocks, 1);
        pass.set_pipeline(&self.block_sum);
        pass.counted_dispatch(x, y, 1);
        pass.set_pipeline(&self.scan_blocks);
        pass.counted_dispatch(1, 1, 1);
        pass.set_pipeline(&self.scatter);
        pass.counted_dispatch(x, y, 1);
    }
}
