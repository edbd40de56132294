//! Per-stage shader invocations from pipeline-statistics queries: counts of
//! work that do not depend on how busy the machine is, to compare between
//! runs and between machines.
//!
//! A query must sit inside a pass, so each pass (or the host's draw, in
//! [`crate::Draw::record`]) brackets its commands with a [`PassCount`]
//! handed out by the frame; the count goes to the stage the frame was in.

use crate::gpu::shape::EncoderShape;
use std::ops::{Add, AddAssign};
use std::sync::{Arc, Mutex};

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::metrics::Stage;

/// What each query counts, in the order the resolved values come.
const TYPES: wgpu::PipelineStatisticsTypes = wgpu::PipelineStatisticsTypes::VERTEX_SHADER_INVOCATIONS
    .union(wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS)
    .union(wgpu::PipelineStatisticsTypes::COMPUTE_SHADER_INVOCATIONS);

/// Shader invocations of one stage of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Invocations {
    /// Vertex shader invocations (a device may count a shared vertex once).
    pub vertex: u64,
    /// Fragment shader invocations (helper lanes may count).
    pub fragment: u64,
    /// Compute shader invocations (threads, not workgroups).
    pub compute: u64,
}

impl Add for Invocations {
    type Output = Invocations;
    fn add(self, o: Invocations) -> Invocations {
        Invocations { vertex: self.vertex + o.vertex, fragment: self.fragment + o.fragment, compute: self.compute + o.compute }
    }
}

impl AddAssign for Invocations {
    fn add_assign(&mut self, o: Invocations) {
        *self = *self + o;
    }
}

/// A pass that can bracket its commands with a pipeline-statistics query.
pub trait CountedPass {
    /// Begins query `index` of `set`.
    fn begin_count(&mut self, set: &wgpu::QuerySet, index: u32);
    /// Ends the query begun last.
    fn end_count(&mut self);
}

impl CountedPass for wgpu::ComputePass<'_> {
    fn begin_count(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_count(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

impl CountedPass for wgpu::RenderPass<'_> {
    fn begin_count(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_count(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

/// The pipeline-statistics query of one pass, attributed to a stage, or
/// nothing when the view does not count. A slot of the query set is taken
/// only when the pass records ([`PassCount::around`]), so a pass that is
/// never recorded leaves no query unwritten.
#[derive(Clone, Debug, Default)]
pub struct PassCount(Option<(Slots, Stage)>);

/// A frame's query set and the stage of each slot taken so far.
#[derive(Clone, Debug)]
struct Slots {
    set: wgpu::QuerySet,
    capacity: u32,
    stages: Arc<Mutex<Vec<Stage>>>,
}

impl PassCount {
    /// Counts nothing.
    pub const NONE: PassCount = PassCount(None);

    /// Records `body` into `pass` inside a query of its own (uncounted once
    /// the frame's slots are used up).
    pub fn around<P: CountedPass>(&self, pass: &mut P, body: impl FnOnce(&mut P)) {
        let slot = self.0.as_ref().and_then(|(slots, stage)| {
            let mut taken = slots.stages.lock().unwrap_or_else(|p| p.into_inner());
            let i = taken.len() as u32;
            (i < slots.capacity).then(|| {
                taken.push(*stage);
                (&slots.set, i)
            })
        });
        if let Some((set, i)) = slot {
            pass.begin_count(set, i);
        }
        body(pass);
        if slot.is_some() {
            pass.end_count();
        }
    }
}

/// Pipeline-statistics queries of one view's frames.
pub struct InvocationCounter {
    slots: Slots,
    resolve: wgpu::Buffer,
    /// Slots resolved at the end of the last frame.
    resolved: Vec<Stage>,
}

impl InvocationCounter {
    /// Room for `capacity` counted passes per frame; later ones go uncounted.
    pub fn new(gpu: &Gpu, capacity: u32) -> Self {
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("pipeline statistics"), ty: wgpu::QueryType::PipelineStatistics(TYPES), count: capacity });
        let size = capacity as u64 * Self::VALUES * 8;
        let resolve = gpu.buffer("pipeline statistics", size, wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        InvocationCounter { slots: Slots { set, capacity, stages: Default::default() }, resolve, resolved: Vec::new() }
    }

    /// u64 values per query: one per counted type.
    const VALUES: u64 = TYPES.bits().count_ones() as u64;

    /// Forgets the last frame's slots.
    pub fn begin_frame(&mut self) {
        self.slots.stages.lock().unwrap_or_else(|p| p.into_inner()).clear();
        self.resolved.clear();
    }

    /// The query of the next pass, counted under `stage`.
    pub fn pass(&self, stage: Stage) -> PassCount {
        PassCount(Some((self.slots.clone(), stage)))
    }

    /// Resolves the frame's slots into `enc`.
    pub fn end(&mut self, enc: &mut wgpu::CommandEncoder) {
        self.resolved = self.slots.stages.lock().unwrap_or_else(|p| p.into_inner()).clone();
        let n = self.resolved.len() as u32;
        if n > 0 {
            enc.counted_resolve(&self.slots.set, 0..n, &self.resolve, 0);
        }
    }

    /// Invocations per stage, in first-use order; slots of one stage are summed.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<(Stage, Invocations)>> {
        let n = self.resolved.len() as u64;
        if n == 0 {
            return Ok(Vec::new());
        }
        let v: Vec<u64> = gpu.read(&self.resolve, 0, n * Self::VALUES)?;
        if v.len() as u64 != n * Self::VALUES {
            return Err(Error::Gpu("pipeline statistics read-back short".into()));
        }
        let mut out: Vec<(Stage, Invocations)> = Vec::new();
        for (stage, q) in self.resolved.iter().zip(v.chunks_exact(Self::VALUES as usize)) {
            // Resolved in the bit order of `TYPES`: vertex, fragment, compute.
            let inv = Invocations { vertex: q[0], fragment: q[1], compute: q[2] };
            match out.iter_mut().find(|(s, _)| s == stage) {
                Some(s) => s.1 += inv,
                None => out.push((*stage, inv)),
            }
        }
        Ok(out)
    }
}
