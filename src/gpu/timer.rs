//! Per-stage GPU time from timestamp queries: a frame is a sequence of
//! `mark(name)` calls; stage `name` lasts from its mark to the next one.

use crate::error::{Error, Result};
use crate::gpu::Gpu;

pub struct GpuTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    capacity: u32,
    names: Vec<&'static str>,
    period_ns: f64,
}

impl GpuTimer {
    pub fn new(gpu: &Gpu, capacity: u32) -> Self {
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("timestamps"), ty: wgpu::QueryType::Timestamp, count: capacity });
        let resolve = gpu.buffer("timestamps", capacity as u64 * 8, wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        GpuTimer { set, resolve, capacity, names: Vec::new(), period_ns: gpu.queue.get_timestamp_period() as f64 }
    }

    pub fn begin_frame(&mut self) {
        self.names.clear();
    }

    /// Starts stage `name` (and ends the previous one) at this point of `enc`.
    pub fn mark(&mut self, enc: &mut wgpu::CommandEncoder, name: &'static str) {
        let i = self.names.len() as u32;
        if i < self.capacity {
            enc.write_timestamp(&self.set, i);
            self.names.push(name);
        }
    }

    /// Resolves the frame's stamps into `enc` (call once, after the last mark).
    pub fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        let n = self.names.len() as u32;
        if n > 0 {
            enc.resolve_query_set(&self.set, 0..n, &self.resolve, 0);
        }
    }

    /// Stage durations in ms, in mark order (the last mark ends the frame and
    /// names no stage). Same-named stages are summed.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<(&'static str, f64)>> {
        let n = self.names.len();
        if n < 2 {
            return Ok(Vec::new());
        }
        let ticks: Vec<u64> = gpu.read(&self.resolve, 0, n as u64)?;
        if ticks.len() != n {
            return Err(Error::Gpu("timestamp read-back short".into()));
        }
        let mut out: Vec<(&'static str, f64)> = Vec::new();
        for i in 0..n - 1 {
            let ms = ticks[i + 1].saturating_sub(ticks[i]) as f64 * self.period_ns / 1e6;
            match out.iter_mut().find(|(name, _)| *name == self.names[i]) {
                Some(s) => s.1 += ms,
                None => out.push((self.names[i], ms)),
            }
        }
        Ok(out)
    }
}
