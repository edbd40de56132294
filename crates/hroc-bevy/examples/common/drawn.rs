//! What Bevy's main opaque pass drew, whichever culls: the instances of
//! its indirect draws (the app's `RenderDebugFlags` must allow copies from
//! the indirect parameters).

use bevy::core_pipeline::core_3d::Opaque3d;
use bevy::ecs::world::World;
use bevy::render::batching::gpu_preprocessing::IndirectParametersBuffers;
use bevy::render::renderer::{RenderDevice, RenderQueue};

/// Objects the main opaque pass of the last frame drew, read back with a
/// wait (render world, after the frame was submitted).
pub fn drawn(render: &World) -> u64 {
    let device = render.resource::<RenderDevice>().wgpu_device().clone();
    let queue: wgpu::Queue = (**render.resource::<RenderQueue>()).clone();
    let buffers = render.resource::<IndirectParametersBuffers>();
    let Some(phase) = buffers.get(&std::any::TypeId::of::<Opaque3d>()) else { return 0 };
    let mut total = 0;
    // Indexed commands: 5 u32 (instance_count second); non-indexed: 4.
    for (sets, data, stride) in [(phase.indexed.batch_sets_buffer(), phase.indexed.data_buffer(), 5), (phase.non_indexed.batch_sets_buffer(), phase.non_indexed.data_buffer(), 4)] {
        let (Some(sets), Some(data)) = (sets, data) else { continue };
        let (Ok(sets), Ok(data)) = (hroc_readback::read::<u32>(&device, &queue, sets, 0, sets.size() / 4), hroc_readback::read::<u32>(&device, &queue, data, 0, data.size() / 4))
        else {
            continue;
        };
        for set in sets.chunks_exact(2) {
            let (count, base) = (set[0] as usize, set[1] as usize);
            for c in base..base + count {
                total += data.get(c * stride + 1).copied().unwrap_or(0) as u64;
            }
        }
    }
    total
}
