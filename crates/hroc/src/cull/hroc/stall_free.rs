//! Stall-free counters (HROC §6: "counter read-back stalls the pipeline").
//! CR reads each count back mid-frame to bound `max_count`; here the
//! bound is an estimate from earlier frames' counts, copied to a staging
//! ring, mapped once the frame's encoder is submitted and done, and read
//! without waiting, plus a margin. Whatever the estimate
//! misses goes to a second indirect-count draw whose count, count −
//! estimate (at least 0), the GPU computes (`overflow.wgsl`): nothing is
//! dropped, so culling stays exactly as conservative as NA.

use crate::cull::DrawList;
use crate::cull::Frame;
use crate::gpu::shape::{EncoderShape, PassShape};
use crate::gpu::{dispatch_size, Gpu, Readback};

/// The counted lists of an HROC frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Counted {
    /// The occluder list V (§3.1).
    V,
    /// The occludee groups G (§3.2).
    G,
    /// The occludee list U (§3.4), or with rounds the last round's list.
    U,
    /// With occluder rounds: V's front list.
    OccluderFront,
    /// With occluder rounds: V's other objects still in front of it.
    OccluderRest,
    /// The front list of occludee round k (all rounds but the last).
    Front(u32),
}

impl Counted {
    /// Index of the list among [`StallFree::new`]'s.
    pub fn index(self) -> usize {
        match self {
            Counted::V => 0,
            Counted::G => 1,
            Counted::U => 2,
            Counted::OccluderFront => 3,
            Counted::OccluderRest => 4,
            Counted::Front(k) => 5 + k as usize,
        }
    }
}

/// Lists of at most this many commands are drawn to their capacity, with
/// no estimate: an indirect-count draw stops at the GPU's count, and an
/// overflow list's dispatch and second draw cost more than the slots a
/// bound saves there (on lavapipe about 0.33 ms a frame at 100 objects,
/// the SF of `hroc` against `hroc-of`, BENCHMARKS.md).
pub const MIN_CAPACITY: u32 = 4096;

/// Estimate = last known count × `MARGIN` + `SLACK`: a quarter more absorbs
/// the frame-to-frame growth of a walk; the slack covers small sets.
const MARGIN: f64 = 1.25;
const SLACK: u32 = 16;
/// Staging buffers in flight: a count arrives one to three frames late.
const RING: usize = 3;
/// Most threads of an overflow pass (`overflow.wgsl`): they stride over
/// what overflowed, so a list of large capacity costs a few workgroups.
const OVERFLOW_THREADS: u32 = 4096;

/// The dispatch that fills one overflow list ([`StallFree::overflow`]).
pub struct Spill {
    job: usize,
    workgroups: (u32, u32),
}

struct Job {
    params: wgpu::Buffer,
    bind: wgpu::BindGroup,
    /// The overflow list: commands [estimate, count) at offset 0.
    list: DrawList,
    stride: u32,
    capacity: u32,
}

/// Per-view state of the stall-free variant.
pub struct StallFree {
    pipeline: wgpu::ComputePipeline,
    /// In [`Counted::index`] order; `None` for a list this view has not.
    jobs: Vec<Option<Job>>,
    ring: Vec<(wgpu::Buffer, Readback<()>)>,
    /// Last counts read back without waiting, in [`Counted::index`] order.
    known: Option<Vec<u32>>,
    /// This frame's estimates, in [`Counted::index`] order.
    pub estimates: Vec<u32>,
}

impl StallFree {
    /// `lists`: (commands, count, capacity, u32 words per command) in
    /// [`Counted::index`] order: V, G, U (or the last occludee round's
    /// list), V's two occluder-round lists (`None` without occluder
    /// rounds: nothing is allocated, copied or read back for them), and the
    /// occludee rounds' front lists.
    /// Lists of at most [`MIN_CAPACITY`] commands get no estimate; `None`
    /// when no list is larger.
    pub fn new(gpu: &Gpu, lists: &[Option<(&wgpu::Buffer, &wgpu::Buffer, u32, u32)>]) -> Option<Self> {
        if lists.iter().flatten().all(|l| l.2 <= MIN_CAPACITY) {
            return None;
        }
        let layout = crate::reflect::Layout::Overflow.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "hroc overflow", &layout);
        let module = gpu.shader("overflow.wgsl", &crate::shaders::source("overflow.wgsl"));
        use wgpu::BufferUsages as U;
        let jobs: Vec<Option<Job>> = lists
            .iter()
            .map(|l| {
                let &(commands, count, capacity, stride) = l.as_ref().filter(|l| l.2 > MIN_CAPACITY)?;
                let params = gpu.buffer("hroc overflow params", 16, U::UNIFORM | U::COPY_DST);
                let list = DrawList {
                    // The groups' overflow is drawn from the groups buffer at an offset: no copy.
                    commands: gpu.buffer("hroc overflow list", (capacity.max(1) as u64) * 4 * stride.max(1) as u64, U::STORAGE | U::INDIRECT | U::COPY_SRC),
                    count: gpu.buffer("hroc overflow count", 4, U::STORAGE | U::INDIRECT | U::COPY_SRC),
                    max_count: 0,
                };
                let bind = gpu.bind_buffers(&layout, &[&params, commands, count, &list.commands, &list.count]);
                Some(Job { params, bind, list, stride, capacity })
            })
            .collect();
        let bytes = (lists.len() as u64 * 4).next_multiple_of(16);
        let ring = (0..RING).map(|_| (gpu.buffer("hroc counts staging", bytes, U::MAP_READ | U::COPY_DST), Readback::Free)).collect();
        Some(StallFree {
            pipeline: gpu.compute_pipeline(&module, "overflow", Some(&pl), &[]),
            jobs,
            ring,
            known: None,
            estimates: lists.iter().map(|l| l.map_or(0, |l| l.2)).collect(),
        })
    }

    /// Starts a frame: takes the counts that arrived (polling, never
    /// waiting) and sets this frame's estimates. Returns the bytes read
    /// back.
    pub fn begin(&mut self, gpu: &Gpu) -> u64 {
        let mut bytes = 0;
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let n = self.jobs.len();
        for (buf, slot) in self.ring.iter_mut() {
            if let Some(c) = slot.take(buf, |(), v| v[..n * 4].chunks_exact(4).map(bytemuck::pod_read_unaligned::<u32>).collect::<Vec<u32>>()) {
                bytes += self.jobs.iter().flatten().count() as u64 * 4;
                self.known = Some(c);
            }
        }
        for (k, job) in self.jobs.iter().enumerate() {
            let Some(job) = job else { continue };
            self.estimates[k] = match &self.known {
                Some(c) => ((c[k] as f64 * MARGIN).ceil() as u32).saturating_add(SLACK).min(job.capacity),
                None => job.capacity,
            };
        }
        bytes
    }

    /// This frame's estimate of `which`'s count; `None` for a list the view
    /// has not (the caller then draws up to the capacity).
    pub fn estimate(&self, which: Counted) -> Option<u32> {
        self.jobs.get(which.index())?.as_ref()?;
        Some(self.estimates[which.index()])
    }

    /// Prepares the overflow of `which` and returns its list (commands
    /// [estimate, count) at offset 0, or for G only the count) with the
    /// dispatch that fills it ([`StallFree::record`], in a compute pass
    /// after the list's count is final and before it is drawn); `None`
    /// when the estimate is the capacity and nothing can overflow, or the
    /// view has no such list.
    pub fn overflow(&self, f: &mut Frame, which: Counted) -> Option<(DrawList, Spill)> {
        let k = which.index();
        let job = self.jobs.get(k)?.as_ref()?;
        let est = self.estimates[k];
        if est >= job.capacity {
            return None;
        }
        f.write(&job.params, 0, bytemuck::cast_slice(&[est, job.stride, job.capacity, 0]));
        let threads = if job.stride > 0 { (job.capacity - est).min(OVERFLOW_THREADS) } else { 1 };
        Some((DrawList { max_count: job.capacity - est, ..job.list.clone() }, Spill { job: k, workgroups: dispatch_size(threads, 256) }))
    }

    /// Records the dispatch that fills an overflow list into an open compute pass.
    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>, spill: &Spill) {
        let Some(job) = self.jobs[spill.job].as_ref() else { return };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &job.bind, &[]);
        pass.counted_dispatch(spill.workgroups.0, spill.workgroups.1, 1);
    }

    /// Ends a frame: copies the counts (in [`Counted::index`] order, `None`
    /// where [`StallFree::new`] had no list) to a free staging buffer,
    /// mapped once `enc` is submitted (skipped when all are in flight).
    pub fn end(&mut self, enc: &mut wgpu::CommandEncoder, counts: &[Option<&wgpu::Buffer>]) {
        if let Some((buf, slot)) = self.ring.iter_mut().find(|(_, s)| s.is_free()) {
            for (k, c) in counts.iter().enumerate().filter_map(|(k, c)| Some((k, (*c)?))).filter(|(k, _)| self.jobs.get(*k).is_some_and(Option::is_some)) {
                enc.counted_copy(c, 0, buf, k as u64 * 4, Some(4));
            }
            *slot = Readback::request(enc, buf, ());
        }
    }
}
