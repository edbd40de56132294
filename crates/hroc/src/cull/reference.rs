//! `ref`: the ideal culler. Per frame it draws exactly the objects that own
//! a pixel in `noc`'s ID target; like the paper's REF the list is prepared
//! before the frame (outside the timed region) and multi-drawn in one batch.

use super::{CullMethod, Frame, Method, MethodContext, Stage};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::shape::QueueShape;
use crate::gpu::Gpu;
use crate::layout::DrawCommand;

/// `ref`'s facts: the benchmark's ideal.
pub(crate) const FACTS: Facts = Facts { name: "ref", description: "ideal: draw exactly the objects visible in noc's ID target", benchmark_only: true, ..Facts::GPU };

/// The `ref` method: draws the list set by `set_oracle` (`noc`'s ID image).
pub struct Reference {
    all: Vec<DrawCommand>,
    list: DrawList,
}

impl Reference {
    /// Reads back every object's draw command; the list holds nothing until `set_oracle`.
    pub fn new(cx: &MethodContext) -> Result<Self> {
        let n = cx.object_count;
        use wgpu::BufferUsages as U;
        let all = cx.gpu.read(cx.commands, 0, n as u64)?;
        Ok(Reference {
            all,
            list: DrawList {
                commands: cx.gpu.buffer("ref commands", n as u64 * 20, U::STORAGE | U::INDIRECT | U::COPY_SRC | U::COPY_DST),
                count: cx.gpu.buffer("ref count", 4, U::STORAGE | U::INDIRECT | U::COPY_SRC | U::COPY_DST),
                max_count: n,
            },
        })
    }
}

impl CullMethod for Reference {
    fn method(&self) -> Method {
        Method::Ref
    }

    fn set_oracle(&mut self, gpu: &Gpu, visible: &[u32]) -> Result<()> {
        let packed: Vec<DrawCommand> = visible.iter().map(|&o| self.all[o as usize]).collect();
        if !packed.is_empty() {
            gpu.queue.write_buffer(&self.list.commands, 0, bytemuck::cast_slice(&packed));
        }
        gpu.queue.write_buffer(&self.list.count, 0, bytemuck::bytes_of(&(packed.len() as u32)));
        gpu.queue.counted_submit([]);
        gpu.wait()
    }
    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage(Stage::Draw);
        f.draw(Phase::Visible, &self.list, None);
        Ok(())
    }
}
