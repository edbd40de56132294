//! Objects and triangles drawn per frame, counted on the GPU from every
//! list a view hands its host (`tally.wgsl`: at the end of the frame, one
//! compute pass, one dispatch per three lists), and
//! `auto`'s frame GPU time (timestamps before the candidate's first pass
//! and after the frame's last, where the device has `TIMESTAMP_QUERY`, in
//! the frames `auto` asks to time), read back without waiting: the
//! totals are copied to a staging ring, mapped once the frame's encoder is
//! submitted and done, and tagged with the frame they describe
//! ([`crate::View::frame_stats`]).

use crate::gpu::shape::{EncoderShape, PassShape};
use std::collections::HashMap;

use crate::contract::DrawList;
use crate::gpu::{dispatch_size, Gpu, PassCount, Readback, Uploads};
use crate::reflect::{pipeline_layout, Layout};

/// Staging buffers in flight: counts arrive one to three frames late.
const RING: usize = 3;

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
    /// Command slots of the lists handed to the host (their `max_count`
    /// summed): what an emulated draw count walks.
    pub command_slots: u64,
    /// Passes over the object-ID target that marked what a list drew
    /// ([`crate::capabilities::Marks::Ids`]).
    pub id_passes: u64,
    /// What the culler recorded in the frame: passes, dispatches, draws,
    /// clears, copies, queries, objects created, submits and maps.
    pub shape: crate::gpu::FrameShape,
    /// CPU nanoseconds spent recording the frame: [`crate::View::cull`],
    /// the host's draw callbacks included.
    pub record_ns: u64,
    /// GPU nanoseconds from the frame's first pass to its last, the host's
    /// draws included, for the frames a view of [`crate::Method::Auto`]
    /// times (it chooses by them); `None` for other views and frames, where
    /// the device has no `TIMESTAMP_QUERY`, and when the stamps came back
    /// out of order. (On an H200 the two stamps, their resolve and copy
    /// cost 0.04 ms a frame, 5 % of a 0.8 ms frame: `auto` times every
    /// frame only while it probes or has just switched.)
    pub gpu_ns: Option<u64>,
}

/// Bytes of a staging buffer: objects and triangles (u32 each), then the
/// frame's first and last timestamps (u64 each).
const STAGED: u64 = 24;

/// Lists one dispatch of `tally.wgsl` counts.
const LISTS: usize = 3;

/// Most threads a dispatch launches: they stride over the commands, so a
/// list of large capacity and few commands costs a few workgroups.
const TALLY_THREADS: u32 = 4096;

/// Bind groups kept for the triples of lists seen lately (lists are mostly
/// the same buffers every frame).
const BINDS: usize = 256;

/// The lists of one dispatch: (commands, count) of each.
type Batch = Vec<(wgpu::Buffer, wgpu::Buffer)>;

/// Per-view counter of what its lists draw, and of its frames' GPU time.
pub(crate) struct DrawTally {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// One `(max_count × 3, 0)` uniform per dispatch of a frame.
    limits: Vec<wgpu::Buffer>,
    binds: HashMap<Batch, wgpu::BindGroup>,
    /// The lists handed to the host this frame, counted at its end.
    pending: Vec<DrawList>,
    /// `[objects, triangles]` of the frame being recorded.
    totals: wgpu::Buffer,
    /// The frame's first and last timestamps, and where they resolve.
    clock: Option<FrameClock>,
    /// The frame being recorded was stamped at its start.
    clocked: bool,
    ring: Vec<(wgpu::Buffer, Readback<FrameStats>)>,
    latest: Option<FrameStats>,
    /// The newest frame that arrived with its GPU time.
    latest_timed: Option<FrameStats>,
}

/// Two timestamps a frame, written by empty compute passes (pass
/// timestamps need only `TIMESTAMP_QUERY`, which Metal, DX12, Vulkan and
/// GL with `ARB_timer_query` have).
struct FrameClock {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    period_ns: f64,
}

impl FrameClock {
    fn stamp(&self, enc: &mut wgpu::CommandEncoder, index: u32) {
        let writes = wgpu::ComputePassTimestampWrites { query_set: &self.set, beginning_of_pass_write_index: Some(index), end_of_pass_write_index: None };
        enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc frame clock"), timestamp_writes: Some(writes) });
    }
}

impl DrawTally {
    /// A tally; `timed` adds the frame clock (where the device has timestamps).
    pub(crate) fn new(gpu: &Gpu, timed: bool) -> Self {
        use wgpu::BufferUsages as U;
        let totals = gpu.buffer("hroc tally", 8, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        let clock = (timed && gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)).then(|| FrameClock {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("hroc frame clock"), ty: wgpu::QueryType::Timestamp, count: 2 }),
            resolve: gpu.buffer("hroc frame clock", 16, U::QUERY_RESOLVE | U::COPY_SRC),
            period_ns: gpu.queue.get_timestamp_period() as f64,
        });
        let module = gpu.shader("tally.wgsl", &crate::shaders::source("tally.wgsl"));
        let layout = Layout::Tally.create(gpu);
        let pipeline = gpu.compute_pipeline(&module, "tally", Some(&pipeline_layout(gpu, Layout::Tally.label(), &layout)), &[]);
        DrawTally {
            pipeline,
            layout,
            limits: Vec::new(),
            binds: HashMap::new(),
            pending: Vec::new(),
            totals,
            clock,
            clocked: false,
            ring: (0..RING).map(|_| (gpu.buffer("hroc tally staging", STAGED, U::MAP_READ | U::COPY_DST), Readback::Free)).collect(),
            latest: None,
            latest_timed: None,
        }
    }

    /// Starts a frame: takes the totals of earlier frames that arrived and
    /// zeroes this frame's (`clear`; else a set's pass writes them,
    /// [`crate::Culler::cull_views`]).
    pub(crate) fn begin(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, clear: bool) {
        self.harvest(gpu);
        if clear {
            enc.counted_clear(&self.totals, 0, None);
        }
        self.pending.clear();
        self.clocked = false;
    }

    /// Zeroes this frame's totals: a set wrote them for a list the view
    /// did not draw.
    pub(crate) fn clear(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.totals, 0, None);
    }

    /// The frame's `[objects, triangles]`, which a set's pass writes.
    pub(crate) fn totals(&self) -> &wgpu::Buffer {
        &self.totals
    }

    /// Times the frame being recorded from here to its end (where the
    /// tally has a clock; once a frame).
    pub(crate) fn start_clock(&mut self, enc: &mut wgpu::CommandEncoder) {
        if let Some(c) = self.clock.as_ref().filter(|_| !self.clocked) {
            c.stamp(enc, 0);
            self.clocked = true;
        }
    }

    /// Counts what `list` draws, at the end of the frame ([`DrawTally::record`]):
    /// the list must keep its commands and count until then.
    pub(crate) fn count(&mut self, list: &DrawList) {
        if list.max_count > 0 {
            self.pending.push(list.clone());
        }
    }

    /// Records the count of the frame's lists: one compute pass, a
    /// dispatch per [`LISTS`] lists (a slot without a list binds the
    /// first list with a bound of 0).
    pub(crate) fn record(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, uploads: &mut Uploads, count: &PassCount) {
        if self.pending.is_empty() {
            return;
        }
        let batches: Vec<&[DrawList]> = self.pending.chunks(LISTS).collect();
        while self.limits.len() < batches.len() {
            self.limits.push(gpu.buffer("hroc tally limits", 16, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST));
        }
        if self.binds.len() > BINDS {
            self.binds.clear();
        }
        let mut dispatches = Vec::with_capacity(batches.len());
        for (k, lists) in batches.iter().enumerate() {
            let mut limit = [0u32; 4];
            let mut key: Batch = Vec::with_capacity(LISTS);
            for (slot, bound) in limit.iter_mut().take(LISTS).enumerate() {
                let l = lists.get(slot).unwrap_or(&lists[0]);
                *bound = lists.get(slot).map_or(0, |l| l.max_count);
                key.push((l.commands.clone(), l.count.clone()));
            }
            uploads.write(enc, &self.limits[k], 0, bytemuck::cast_slice(&limit));
            let threads = lists.iter().map(|l| l.max_count).max().unwrap_or(0).min(TALLY_THREADS);
            let (layout, totals, limits) = (&self.layout, &self.totals, &self.limits[k]);
            let bind = self
                .binds
                .entry(key.iter().cloned().chain([(limits.clone(), limits.clone())]).collect())
                .or_insert_with(|| {
                    let mut resources = vec![(2, limits.as_entire_binding()), (3, totals.as_entire_binding())];
                    for (slot, (c, n)) in key.iter().enumerate() {
                        let at = [0, 4, 6][slot];
                        resources.extend([(at, c.as_entire_binding()), (at + 1, n.as_entire_binding())]);
                    }
                    Layout::Tally.bind(gpu, layout, &resources)
                })
                .clone();
            dispatches.push((bind, dispatch_size(threads, 64)));
        }
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc tally"), timestamp_writes: None });
        count.around(&mut pass, |pass| {
            pass.set_pipeline(&self.pipeline);
            for (bind, (x, y)) in &dispatches {
                pass.set_bind_group(0, bind, &[]);
                pass.counted_dispatch(*x, *y, 1);
            }
        });
        self.pending.clear();
    }

    /// Ends a frame: copies the totals, with `stats` (the frame's number
    /// and CPU-side counts), to a free staging buffer mapped when `enc` is
    /// submitted (skipped when all are in flight).
    pub(crate) fn end(&mut self, enc: &mut wgpu::CommandEncoder, stats: FrameStats) {
        let clock = self.clock.as_ref().filter(|_| std::mem::take(&mut self.clocked));
        if let Some(c) = clock {
            c.stamp(enc, 1);
            enc.counted_resolve(&c.set, 0..2, &c.resolve, 0);
        }
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| s.is_free()) {
            enc.counted_copy(&self.totals, 0, buf, 0, Some(8));
            if let Some(c) = clock {
                enc.counted_copy(&c.resolve, 0, buf, 8, Some(16));
            }
            // `Some` marks a timed frame until its stamps arrive.
            *slot = Readback::request(enc, buf, FrameStats { gpu_ns: clock.map(|_| 0), ..stats });
        }
    }

    /// The newest frame whose totals have arrived, polling the device
    /// without waiting; `None` before the first arrives. A frame's totals
    /// are mapped once its encoder is submitted and done.
    pub(crate) fn latest(&mut self, gpu: &Gpu) -> Option<FrameStats> {
        self.harvest(gpu);
        self.latest
    }

    /// The newest frame that arrived with its GPU time
    /// ([`DrawTally::start_clock`]), polling the device without waiting.
    pub(crate) fn latest_timed(&mut self, gpu: &Gpu) -> Option<FrameStats> {
        self.harvest(gpu);
        self.latest_timed
    }

    /// Takes the totals that arrived, polling the device without waiting.
    fn harvest(&mut self, gpu: &Gpu) {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let period_ns = self.clock.as_ref().map(|c| c.period_ns);
        for (buf, slot) in self.ring.iter_mut() {
            let words = |stats: FrameStats, v: &[u8]| {
                let tick = |at: usize| bytemuck::pod_read_unaligned::<u64>(&v[at..at + 8]);
                FrameStats {
                    objects: bytemuck::pod_read_unaligned(&v[0..4]),
                    triangles: bytemuck::pod_read_unaligned(&v[4..8]),
                    gpu_ns: stats.gpu_ns.and(period_ns).and_then(|p| tick(16).checked_sub(tick(8)).filter(|&t| t > 0).map(|t| (t as f64 * p) as u64)),
                    ..stats
                }
            };
            if let Some(arrived) = slot.take(buf, words) {
                if self.latest.is_none_or(|l| l.frame < arrived.frame) {
                    self.latest = Some(arrived);
                }
                if arrived.gpu_ns.is_some() && self.latest_timed.is_none_or(|l| l.frame < arrived.frame) {
                    self.latest_timed = Some(arrived);
                }
            }
        }
    }
}
