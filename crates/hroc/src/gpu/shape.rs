//! A frame's shape: the commands the culler records into it (passes,
//! dispatches, draws, clears, copies, queries), the objects it creates on
//! the device, its submits and map requests. They repeat from run to run,
//! so they compare methods where times are noisy, and serve as budgets.
//!
//! The culler records through counted calls (`EncoderShape`,
//! `PassShape`, `RenderShape`, `DeviceShape`, `QueueShape`); each adds to
//! the recording thread's tally, and a view takes the difference around
//! its frame ([`crate::tally::FrameStats::shape`]).

use std::cell::Cell;
use std::ops::{Range, Sub};

/// What the culler recorded in one frame of one view, the host's own
/// commands aside: its draw lists appear as `lists`, each one draw call
/// of the host (one render pass in a host that opens a pass per list).
/// The frame's statistics' own read-back (a copy or two and a map
/// request, recorded after the count is taken) is not in it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameShape {
    /// Compute passes the culler opened.
    pub compute_passes: u32,
    /// Render passes the culler opened (its box tests, its depth reductions).
    pub render_passes: u32,
    /// Dispatches with a workgroup count from the CPU.
    pub dispatches: u32,
    /// Dispatches with a workgroup count from a GPU buffer.
    pub indirect_dispatches: u32,
    /// Draw calls in the culler's own render passes.
    pub draws: u32,
    /// Draw lists handed to the host ([`crate::Draw`]).
    pub lists: u32,
    /// Buffer clears.
    pub clears: u32,
    /// Buffer-to-buffer copies, per-frame uploads among them.
    pub copies: u32,
    /// Timestamp and query writes.
    pub query_writes: u32,
    /// Query-set resolves.
    pub query_resolves: u32,
    /// Bind groups created while recording.
    pub bind_groups: u32,
    /// Buffers created while recording.
    pub buffers: u32,
    /// Submits of command buffers (mid-frame read-backs).
    pub submits: u32,
    /// Buffers mapped for reading, waited for or not.
    pub map_requests: u32,
}

impl FrameShape {
    /// Passes of both kinds.
    pub fn passes(&self) -> u32 {
        self.compute_passes + self.render_passes
    }
}

impl Sub for FrameShape {
    type Output = FrameShape;
    fn sub(self, o: FrameShape) -> FrameShape {
        FrameShape {
            compute_passes: self.compute_passes - o.compute_passes,
            render_passes: self.render_passes - o.render_passes,
            dispatches: self.dispatches - o.dispatches,
            indirect_dispatches: self.indirect_dispatches - o.indirect_dispatches,
            draws: self.draws - o.draws,
            lists: self.lists - o.lists,
            clears: self.clears - o.clears,
            copies: self.copies - o.copies,
            query_writes: self.query_writes - o.query_writes,
            query_resolves: self.query_resolves - o.query_resolves,
            bind_groups: self.bind_groups - o.bind_groups,
            buffers: self.buffers - o.buffers,
            submits: self.submits - o.submits,
            map_requests: self.map_requests - o.map_requests,
        }
    }
}

thread_local! {
    /// Everything this thread has recorded through the counted calls.
    static RECORDED: Cell<FrameShape> = Cell::new(FrameShape::default());
}

/// Adds to this thread's tally.
pub(crate) fn count(add: impl FnOnce(&mut FrameShape)) {
    RECORDED.with(|r| {
        let mut s = r.get();
        add(&mut s);
        r.set(s);
    });
}

/// This thread's tally so far (the difference of two is what was recorded between them).
pub(crate) fn recorded() -> FrameShape {
    RECORDED.with(Cell::get)
}

/// The encoder's commands, counted.
pub(crate) trait EncoderShape {
    fn counted_compute_pass<'e>(&'e mut self, desc: &wgpu::ComputePassDescriptor<'_>) -> wgpu::ComputePass<'e>;
    fn counted_render_pass<'e>(&'e mut self, desc: &wgpu::RenderPassDescriptor<'_>) -> wgpu::RenderPass<'e>;
    fn counted_clear(&mut self, buffer: &wgpu::Buffer, offset: u64, size: Option<u64>);
    fn counted_copy(&mut self, src: &wgpu::Buffer, src_offset: u64, dst: &wgpu::Buffer, dst_offset: u64, size: impl Into<Option<u64>>);
    fn counted_timestamp(&mut self, set: &wgpu::QuerySet, index: u32);
    fn counted_resolve(&mut self, set: &wgpu::QuerySet, range: Range<u32>, dst: &wgpu::Buffer, offset: u64);
}

impl EncoderShape for wgpu::CommandEncoder {
    fn counted_compute_pass<'e>(&'e mut self, desc: &wgpu::ComputePassDescriptor<'_>) -> wgpu::ComputePass<'e> {
        count(|s| s.compute_passes += 1);
        self.begin_compute_pass(desc)
    }
    fn counted_render_pass<'e>(&'e mut self, desc: &wgpu::RenderPassDescriptor<'_>) -> wgpu::RenderPass<'e> {
        count(|s| s.render_passes += 1);
        self.begin_render_pass(desc)
    }
    fn counted_clear(&mut self, buffer: &wgpu::Buffer, offset: u64, size: Option<u64>) {
        count(|s| s.clears += 1);
        self.clear_buffer(buffer, offset, size);
    }
    fn counted_copy(&mut self, src: &wgpu::Buffer, src_offset: u64, dst: &wgpu::Buffer, dst_offset: u64, size: impl Into<Option<u64>>) {
        count(|s| s.copies += 1);
        self.copy_buffer_to_buffer(src, src_offset, dst, dst_offset, size.into());
    }
    fn counted_timestamp(&mut self, set: &wgpu::QuerySet, index: u32) {
        count(|s| s.query_writes += 1);
        self.write_timestamp(set, index);
    }
    fn counted_resolve(&mut self, set: &wgpu::QuerySet, range: Range<u32>, dst: &wgpu::Buffer, offset: u64) {
        count(|s| s.query_resolves += 1);
        self.resolve_query_set(set, range, dst, offset);
    }
}

/// A compute pass's dispatches, counted.
pub(crate) trait PassShape {
    fn counted_dispatch(&mut self, x: u32, y: u32, z: u32);
    fn counted_dispatch_indirect(&mut self, args: &wgpu::Buffer, offset: u64);
}

impl PassShape for wgpu::ComputePass<'_> {
    fn counted_dispatch(&mut self, x: u32, y: u32, z: u32) {
        count(|s| s.dispatches += 1);
        self.dispatch_workgroups(x, y, z);
    }
    fn counted_dispatch_indirect(&mut self, args: &wgpu::Buffer, offset: u64) {
        count(|s| s.indirect_dispatches += 1);
        self.dispatch_workgroups_indirect(args, offset);
    }
}

/// Draws in the culler's own render passes, counted.
pub(crate) trait RenderShape {
    fn counted_draw(&mut self, vertices: Range<u32>, instances: Range<u32>);
    fn counted_draw_indirect(&mut self, args: &wgpu::Buffer, offset: u64);
    fn counted_multi_draw_indirect_count(&mut self, args: &wgpu::Buffer, offset: u64, count_buffer: &wgpu::Buffer, count_offset: u64, max_count: u32);
}

impl RenderShape for wgpu::RenderPass<'_> {
    fn counted_draw(&mut self, vertices: Range<u32>, instances: Range<u32>) {
        count(|s| s.draws += 1);
        self.draw(vertices, instances);
    }
    fn counted_draw_indirect(&mut self, args: &wgpu::Buffer, offset: u64) {
        count(|s| s.draws += 1);
        self.draw_indirect(args, offset);
    }
    fn counted_multi_draw_indirect_count(&mut self, args: &wgpu::Buffer, offset: u64, count_buffer: &wgpu::Buffer, count_offset: u64, max_count: u32) {
        count(|s| s.draws += 1);
        self.multi_draw_indirect_count(args, offset, count_buffer, count_offset, max_count);
    }
}

/// Objects the culler creates on the device, counted.
pub(crate) trait DeviceShape {
    fn counted_bind_group(&self, desc: &wgpu::BindGroupDescriptor<'_>) -> wgpu::BindGroup;
}

impl DeviceShape for wgpu::Device {
    fn counted_bind_group(&self, desc: &wgpu::BindGroupDescriptor<'_>) -> wgpu::BindGroup {
        count(|s| s.bind_groups += 1);
        self.create_bind_group(desc)
    }
}

/// Submits, counted.
pub(crate) trait QueueShape {
    fn counted_submit<I: IntoIterator<Item = wgpu::CommandBuffer>>(&self, buffers: I) -> wgpu::SubmissionIndex;
}

impl QueueShape for wgpu::Queue {
    fn counted_submit<I: IntoIterator<Item = wgpu::CommandBuffer>>(&self, buffers: I) -> wgpu::SubmissionIndex {
        count(|s| s.submits += 1);
        self.submit(buffers)
    }
}
