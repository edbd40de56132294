//! How the BVH follows moving objects: refit on the CPU or the GPU, and
//! the rebuild policy.

use super::*;
use crate::bvh::{Bvh, Split};
use crate::error::{Error, Result};
use crate::gpu::shape::{EncoderShape, PassShape, QueueShape};
use crate::gpu::{dispatch_size, Gpu};
use crate::shaders;

/// Where the BVH is refit after objects move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refit {
    /// On the CPU, then the boxes and nodes are uploaded (the default:
    /// measured cheaper here, see BENCHMARKS.md).
    #[default]
    Cpu,
    /// On the GPU: only the moved boxes are uploaded (`refit.wgsl`).
    Gpu,
}

/// How the BVH follows motion (HROC §6 names the static hierarchy as the
/// method's main limit). Static objects that move are refit into the tree;
/// [`ObjectFlags::DYNAMIC`] objects and objects added since the last build
/// are tested on their own (the paper's hybrid); a rebuild folds the
/// latter back in when the tree has degraded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionOptions {
    /// Where refits run.
    pub refit: Refit,
    /// Rebuild when the refit tree's SAH cost exceeds this multiple of its
    /// cost as built ([`Bvh::sah_cost`]); `f64::INFINITY` never does.
    pub rebuild_sah_growth: f64,
    /// Rebuild when more than this fraction of the live objects are out of
    /// step with the tree: static objects outside it (added since the last
    /// build, or turned static without a leaf), each a group of its own
    /// until then, plus frozen leaves (objects turned DYNAMIC or removed),
    /// which rays still walk into.
    pub rebuild_outside: f64,
}

impl Default for MotionOptions {
    fn default() -> Self {
        MotionOptions { refit: Refit::Cpu, rebuild_sah_growth: 2.0, rebuild_outside: 0.05 }
    }
}

/// What the last change of objects cost the culler ([`Culler::last_update`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateStats {
    /// CPU ms in the culler: boxes, refit or rebuild, uploads queued.
    pub cpu_ms: f64,
    /// True when the change rebuilt the BVH.
    pub rebuilt: bool,
    /// SAH cost of the tree over its cost as last built (1 when fresh);
    /// `None` after a GPU refit, whose boxes the CPU does not see.
    pub sah_growth: Option<f64>,
}

pub(super) fn check_motion(m: &MotionOptions) -> Result<()> {
    if m.rebuild_sah_growth.is_nan() || m.rebuild_sah_growth < 1.0 || !(0.0..=1.0).contains(&m.rebuild_outside) {
        return Err(Error::InvalidScene(format!("motion options {m:?}: rebuild_sah_growth must be at least 1 and rebuild_outside a fraction")));
    }
    Ok(())
}

/// The GPU refit's pipelines and scratch (`refit.wgsl`).
pub(super) struct GpuRefit {
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) clear: wgpu::ComputePipeline,
    pub(super) leaves: wgpu::ComputePipeline,
    pub(super) decode: wgpu::ComputePipeline,
    pub(super) params: wgpu::Buffer,
    pub(super) scratch: wgpu::Buffer,
    pub(super) no_host: wgpu::Buffer,
}

impl GpuRefit {
    pub(super) fn new(gpu: &Gpu, slots: u32) -> GpuRefit {
        use wgpu::BufferUsages as U;
        let layout = crate::reflect::Layout::Refit.create(gpu);
        let pl = crate::reflect::pipeline_layout(gpu, "hroc refit", &layout);
        let module = gpu.shader("refit.wgsl", &shaders::source("refit.wgsl"));
        GpuRefit {
            clear: gpu.compute_pipeline(&module, "clear", Some(&pl), &[]),
            leaves: gpu.compute_pipeline(&module, "leaves", Some(&pl), &[]),
            decode: gpu.compute_pipeline(&module, "decode", Some(&pl), &[]),
            layout,
            params: gpu.buffer("hroc refit params", 16, U::UNIFORM | U::COPY_DST),
            scratch: gpu.buffer("hroc refit scratch", node_capacity(slots) as u64 * 24, U::STORAGE),
            no_host: gpu.buffer("hroc refit no host boxes", 32, U::STORAGE),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn record(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        params: [u32; 4],
        host: Option<&wgpu::Buffer>,
        bounds: &wgpu::Buffer,
        nodes: &wgpu::Buffer,
        leaves: &wgpu::Buffer,
    ) {
        // Written before the submit that runs these passes.
        gpu.queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&params));
        let bind = gpu.bind_buffers(&self.layout, &[&self.params, host.unwrap_or(&self.no_host), bounds, nodes, leaves, &self.scratch]);
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some("hroc refit"), timestamp_writes: None });
        pass.set_bind_group(0, &bind, &[]);
        for (p, items) in [(&self.clear, params[1]), (&self.leaves, params[0]), (&self.decode, params[1])] {
            pass.set_pipeline(p);
            let (x, y) = dispatch_size(items.max(1), 256);
            pass.counted_dispatch(x, y, 1);
        }
    }
}

/// How the culler follows motion: the refit, the rebuild policy and the
/// GPU refit.
impl Culler {
    /// Changes how the BVH follows motion from the next change on.
    pub fn set_motion(&mut self, motion: MotionOptions) -> Result<()> {
        check_motion(&motion)?;
        self.motion = motion;
        Ok(())
    }

    /// The motion options in use.
    pub fn motion(&self) -> MotionOptions {
        self.motion
    }

    /// What the last change of objects cost ([`UpdateStats`]).
    pub fn last_update(&self) -> UpdateStats {
        self.last_update
    }

    /// After boxes, flags or slots changed: refit (or rebuild) and upload.
    pub(super) fn changed(&mut self, t: std::time::Instant) -> Result<()> {
        let mut rebuilt = false;
        let out_of_step = (0..self.objects.count as usize)
            .filter(|&i| {
                let static_live = self.live[i] && !self.is_dynamic(i);
                static_live != self.bvh_leaf(i).is_some()
            })
            .count();
        let live = self.live.iter().filter(|&&l| l).count().max(1);
        let mut growth = 1.0;
        if out_of_step as f64 > self.motion.rebuild_outside * live as f64 {
            self.rebuild_tree()?;
            rebuilt = true;
        } else if self.motion.refit == Refit::Gpu {
            // The GPU refits from the uploaded boxes; the CPU tree keeps its
            // boxes for nothing but the policy, so it is refit too only when
            // the policy needs it: never here (growth unknown).
            self.upload_bounds();
            let mut enc = self.gpu.device.create_command_encoder(&Default::default());
            self.refit_on_gpu(&mut enc, None);
            self.gpu.queue.counted_submit([enc.finish()]);
            self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, sah_growth: None };
            return Ok(());
        } else {
            self.refit_cpu();
            growth = self.sah_growth();
            if growth > self.motion.rebuild_sah_growth {
                self.rebuild_tree()?;
                (rebuilt, growth) = (true, 1.0);
            }
        }
        self.upload_bounds();
        if !rebuilt {
            self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        }
        self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt, sah_growth: Some(growth) };
        Ok(())
    }

    /// Refits the CPU tree: live static leaves take their boxes, the
    /// others stay frozen.
    pub(super) fn refit_cpu(&mut self) {
        let (boxes, live, flags) = (&self.boxes, &self.live, &self.objects.flags);
        self.bvh.refit_with(|o| {
            let o = o as usize;
            (live[o] && !flags[o].contains(ObjectFlags::DYNAMIC)).then_some(boxes[o])
        });
    }

    pub(super) fn sah_growth(&self) -> f64 {
        if self.built_cost > 0.0 {
            self.bvh.sah_cost() / self.built_cost
        } else {
            1.0
        }
    }

    /// Builds the tree over the live static objects and uploads it. A tree
    /// deeper than HROC's stacks is built again with equal-count splits.
    pub(super) fn rebuild_tree(&mut self) -> Result<()> {
        let members: Vec<u32> = (0..self.objects.count).filter(|&i| self.live[i as usize] && !self.is_dynamic(i as usize)).collect();
        let mut bvh = Bvh::build_subset(&self.boxes, &members, self.split);
        if bvh.depth() > crate::cull::hroc::MAX_DEPTH {
            bvh = Bvh::build_subset(&self.boxes, &members, Split::Eq);
        }
        self.built_cost = bvh.sah_cost();
        self.bvh = bvh;
        self.gpu.queue.write_buffer(&self.bvh_nodes, 0, bytemuck::cast_slice(&self.bvh.nodes));
        self.gpu.queue.write_buffer(&self.leaf_of_object, 0, bytemuck::cast_slice(&self.bvh.leaf_of_object));
        self.generation += 1;
        Ok(())
    }

    /// Records the GPU refit (`refit.wgsl`), from `host` boxes when given.
    pub(super) fn refit_on_gpu(&mut self, enc: &mut wgpu::CommandEncoder, host: Option<&wgpu::Buffer>) {
        let nodes = self.bvh.nodes.len() as u32;
        let r = self.gpu_refit.get_or_insert_with(|| GpuRefit::new(&self.gpu, self.objects.count));
        r.record(&self.gpu, enc, [self.objects.count, nodes, host.is_some() as u32, 0], host, &self.objects.bounds, &self.bvh_nodes, &self.leaf_of_object);
    }
}
