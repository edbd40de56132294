//! Objects and triangles drawn per frame, counted on the GPU from every
//! list a view hands its host (`tally.wgsl`, one dispatch per list), and
//! read back without waiting: the totals are copied to a staging ring and
//! mapped at a later frame, tagged with the frame they describe
//! ([`crate::View::frame_stats`]).

use std::collections::HashMap;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

use crate::contract::DrawList;
use crate::gpu::{dispatch_size, Gpu};

/// Bytes per list's `max_count` in the limits buffer: the largest uniform
/// offset alignment wgpu allows a device.
const SLOT: u64 = 256;
/// Staging buffers in flight: counts arrive one to three frames late.
const RING: usize = 3;
/// Lists' limits per buffer: a frame with more lists takes more buffers.
const CHUNK: usize = 64;

/// Statistics every method shares, of one frame of one view, read back
/// without waiting ([`crate::View::frame_stats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Which frame: the number of [`crate::View::cull`] calls on the view
    /// before it (0 for its first).
    pub frame: u64,
    /// Draws of objects in the lists handed to the host (an object in two
    /// lists counts twice).
    pub objects: u32,
    /// Triangles of those draws (`index_count / 3` each).
    pub triangles: u32,
    /// The view culled the frame as after a camera cut.
    pub cut: bool,
    /// Mid-frame submits of the method.
    pub submits: u64,
    /// Mid-frame waits for the GPU.
    pub waits: u64,
    /// Bytes read back to the CPU, waited for or not.
    pub bytes_read: u64,
}

enum Slot {
    Free,
    /// Holds a frame's totals once the host submits that frame.
    Copied(FrameStats),
    /// Map requested: 0 pending, 1 mapped, 2 failed.
    Mapping(FrameStats, Arc<AtomicU8>),
}

/// Per-view counter of what its lists draw.
pub(crate) struct DrawTally {
    pipeline: wgpu::ComputePipeline,
    /// `[objects, triangles]` of the frame being recorded.
    totals: wgpu::Buffer,
    /// One `max_count` per list of the frame, `SLOT` bytes apart, `CHUNK`
    /// lists per buffer.
    limits: Vec<wgpu::Buffer>,
    /// `max_count` of this frame's lists, by slot; those from `written` on
    /// are not yet in `limits`.
    frame_limits: Vec<u32>,
    written: usize,
    /// Per (commands, count, slot): the tally's bindings.
    binds: HashMap<(wgpu::Buffer, wgpu::Buffer, u32), wgpu::BindGroup>,
    ring: Vec<(wgpu::Buffer, Slot)>,
    latest: Option<FrameStats>,
}

impl DrawTally {
    pub(crate) fn new(gpu: &Gpu) -> Self {
        let module = gpu.shader("tally.wgsl", &crate::shaders::source("tally.wgsl"));
        use wgpu::BufferUsages as U;
        DrawTally {
            pipeline: gpu.compute_pipeline(&module, "tally", None, &[]),
            totals: gpu.buffer("hroc tally", 8, U::STORAGE | U::COPY_SRC | U::COPY_DST),
            limits: Vec::new(),
            frame_limits: Vec::new(),
            written: 0,
            binds: HashMap::new(),
            ring: (0..RING).map(|_| (gpu.buffer("hroc tally staging", 8, U::MAP_READ | U::COPY_DST), Slot::Free)).collect(),
            latest: None,
        }
    }

    /// Starts a frame: maps the totals of earlier frames (whose encoders
    /// the host has submitted by now: the submit rule) and zeroes this
    /// frame's.
    pub(crate) fn begin(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder) {
        self.harvest(gpu);
        for (buf, slot) in self.ring.iter_mut() {
            if let Slot::Copied(stats) = *slot {
                let done = Arc::new(AtomicU8::new(0));
                let flag = done.clone();
                buf.slice(..).map_async(wgpu::MapMode::Read, move |r| flag.store(if r.is_ok() { 1 } else { 2 }, Ordering::Release));
                *slot = Slot::Mapping(stats, done);
            }
        }
        self.frame_limits.clear();
        self.written = 0;
        enc.clear_buffer(&self.totals, 0, None);
    }

    /// Counts what `list` draws, after the host recorded its draw.
    pub(crate) fn count(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, list: &DrawList) {
        let slot = self.frame_limits.len();
        self.frame_limits.push(list.max_count);
        if list.max_count == 0 {
            return;
        }
        if slot / CHUNK >= self.limits.len() {
            self.limits.push(gpu.buffer("hroc tally limits", CHUNK as u64 * SLOT, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST));
        }
        // Lists are mostly the same buffers every frame: a bounded cache.
        if self.binds.len() > 4 * CHUNK * self.limits.len() {
            self.binds.clear();
        }
        let key = (list.commands.clone(), list.count.clone(), slot as u32);
        let (pipeline, limits, totals) = (&self.pipeline, &self.limits[slot / CHUNK], &self.totals);
        let bind = self.binds.entry(key).or_insert_with(|| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hroc tally"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: list.commands.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: list.count.as_entire_binding() },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: limits, offset: (slot % CHUNK) as u64 * SLOT, size: wgpu::BufferSize::new(16) }),
                    },
                    wgpu::BindGroupEntry { binding: 3, resource: totals.as_entire_binding() },
                ],
            })
        });
        let (x, y) = dispatch_size(list.max_count, 64);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc tally"), timestamp_writes: None });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &*bind, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// Writes the limits of the lists counted since the last write: before
    /// every submit of the frame's work (a queue write lands with the next
    /// submit).
    pub(crate) fn write_limits(&mut self, gpu: &Gpu) {
        while self.written < self.frame_limits.len() {
            let (chunk, first) = (self.written / CHUNK, self.written % CHUNK);
            let end = self.frame_limits.len().min((chunk + 1) * CHUNK);
            // Lists with max_count 0 recorded no dispatch and may have no buffer.
            if let Some(buf) = self.limits.get(chunk) {
                let mut bytes = vec![0u8; (end - self.written) * SLOT as usize];
                for (k, &m) in self.frame_limits[self.written..end].iter().enumerate() {
                    bytes[k * SLOT as usize..k * SLOT as usize + 4].copy_from_slice(&m.to_le_bytes());
                }
                gpu.queue.write_buffer(buf, first as u64 * SLOT, &bytes);
            }
            self.written = end;
        }
    }

    /// Ends a frame: writes the last limits and copies the totals, with
    /// `stats` (the frame's number and CPU-side counts), to a free staging
    /// buffer (skipped when all are in flight).
    pub(crate) fn end(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, stats: FrameStats) {
        self.write_limits(gpu);
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| matches!(s, Slot::Free)) {
            enc.copy_buffer_to_buffer(&self.totals, 0, buf, 0, Some(8));
            *slot = Slot::Copied(stats);
        }
    }

    /// The newest frame whose totals have arrived, polling the device
    /// without waiting; `None` before the first arrives. A frame's totals
    /// are mapped when the next frame begins, so they arrive a frame or
    /// more after it.
    pub(crate) fn latest(&mut self, gpu: &Gpu) -> Option<FrameStats> {
        self.harvest(gpu);
        self.latest
    }

    /// Takes the totals that arrived, polling the device without waiting.
    fn harvest(&mut self, gpu: &Gpu) {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        for (buf, slot) in self.ring.iter_mut() {
            let Slot::Mapping(stats, done) = slot else { continue };
            match done.load(Ordering::Acquire) {
                0 => {}
                1 => {
                    let words = buf.slice(..).get_mapped_range().ok().map(|v| [0, 4].map(|o| bytemuck::pod_read_unaligned::<u32>(&v[o..o + 4])));
                    buf.unmap();
                    if let Some([objects, triangles]) = words {
                        let arrived = FrameStats { objects, triangles, ..*stats };
                        if self.latest.is_none_or(|l| l.frame < arrived.frame) {
                            self.latest = Some(arrived);
                        }
                    }
                    *slot = Slot::Free;
                }
                _ => *slot = Slot::Free,
            }
        }
    }
}
