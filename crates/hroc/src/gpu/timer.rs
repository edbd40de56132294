//! Per-stage GPU time from timestamp queries: a frame is a sequence of
//! `mark(stage)` calls; a stage lasts from its mark to the next one.

use crate::error::{Error, Result};
use crate::gpu::shape::EncoderShape;
use crate::gpu::Gpu;
use crate::metrics::Stage;

/// Timestamps of one view's frame.
pub struct GpuTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    capacity: u32,
    /// The stage each stamp starts; `None` ends the frame.
    marks: Vec<Option<Stage>>,
    period_ns: f64,
}

impl GpuTimer {
    /// Room for `capacity` stamps per frame.
    pub fn new(gpu: &Gpu, capacity: u32) -> Self {
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("timestamps"), ty: wgpu::QueryType::Timestamp, count: capacity });
        let resolve = gpu.buffer("timestamps", capacity as u64 * 8, wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        GpuTimer { set, resolve, capacity, marks: Vec::new(), period_ns: gpu.queue.get_timestamp_period() as f64 }
    }

    /// Forgets the last frame's stamps.
    pub fn begin_frame(&mut self) {
        self.marks.clear();
    }

    fn stamp(&mut self, enc: &mut wgpu::CommandEncoder, mark: Option<Stage>) {
        let i = self.marks.len() as u32;
        if i < self.capacity {
            enc.counted_timestamp(&self.set, i);
            self.marks.push(mark);
        }
    }

    /// Starts `stage` (and ends the previous one) at this point of `enc`.
    pub fn mark(&mut self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        self.stamp(enc, Some(stage));
    }

    /// Ends the frame's last stage and resolves the stamps into `enc`.
    pub fn end(&mut self, enc: &mut wgpu::CommandEncoder) {
        self.stamp(enc, None);
        let n = self.marks.len() as u32;
        if n > 0 {
            enc.counted_resolve(&self.set, 0..n, &self.resolve, 0);
        }
    }

    /// Stage durations in ms, in mark order. Same stages are summed.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<(Stage, f64)>> {
        let n = self.marks.len();
        if n < 2 {
            return Ok(Vec::new());
        }
        let ticks: Vec<u64> = gpu.read(&self.resolve, 0, n as u64)?;
        if ticks.len() != n {
            return Err(Error::Gpu("timestamp read-back short".into()));
        }
        let mut out: Vec<(Stage, f64)> = Vec::new();
        for i in 0..n - 1 {
            let Some(stage) = self.marks[i] else { continue };
            let ms = ticks[i + 1].saturating_sub(ticks[i]) as f64 * self.period_ns / 1e6;
            match out.iter_mut().find(|(s, _)| *s == stage) {
                Some(s) => s.1 += ms,
                None => out.push((stage, ms)),
            }
        }
        Ok(out)
    }
}
