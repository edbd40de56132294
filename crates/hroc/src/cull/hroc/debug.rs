//! HROC's per-frame counts (|V|, |O|, |G|, |U|, |D|, rays) and the
//! debug read-backs that tests and the benchmark use.

use super::*;
use crate::cull::DrawList;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::layout::DrawArgs;

/// Per-frame sizes of the paper's sets, read after the frame (untimed).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SetSizes {
    /// |V|: objects in the occluder list (last frame's visible set), drawn
    /// for the occlusion map. With occluder rounds, those of V hidden
    /// behind V's front list are not drawn there but tested as occludees.
    pub v: u32,
    /// |O|: effective occluders, objects of V with a fragment through early-Z (HROC §3.1).
    pub o: u32,
    /// |G|: occludee groups extracted from the BVH (HROC §3.2).
    pub g: u32,
    /// |U|: occludees, objects marked by the batch occlusion test (HROC §3.3).
    pub u: u32,
    /// |D|: occludees with a fragment through early-Z when drawn (HROC §3.4).
    pub d: u32,
    /// Occludees drawn in the rounds' front lists (0 with one round).
    pub front: u32,
    /// Rays cast by the batch occlusion test, one per group-box fragment that traverses.
    pub rays: u64,
    /// BVH nodes visited by those rays, summed over all rays.
    pub nodes_visited: u64,
}

/// Debug read-backs: the sets and ray counts of the last frame.
impl Hroc {
    /// Sizes of V, O, G, U, D and ray statistics of the last frame (reads
    /// back; call after the frame).
    pub fn set_sizes(&self, gpu: &Gpu) -> Result<SetSizes> {
        let sum = |b: &wgpu::Buffer| -> Result<u32> { Ok(gpu.read::<u32>(b, 0, self.n as u64)?.iter().filter(|&&x| x != 0).count() as u32) };
        let stats: Vec<u32> = gpu.read(&self.ray_stats, 0, STAT_SLOTS * 2)?;
        Ok(SetSizes {
            v: gpu.read::<u32>(&self.v_drawn.count, 0, 1)?[0],
            o: sum(&self.occluders)?,
            g: gpu.read::<u32>(&self.group_count, 0, 1)?[0],
            u: sum(&self.occludees)?,
            d: sum(&self.drawn)?,
            front: match &self.rounds {
                Some(r) => sum(&r.front)?,
                None => 0,
            },
            rays: stats.iter().step_by(2).map(|&x| x as u64).sum(),
            nodes_visited: stats.iter().skip(1).step_by(2).map(|&x| x as u64).sum(),
        })
    }

    /// Debug read-back for the CPU references: node states, groups (sorted),
    /// the O and U marks of the last frame, and the objects step 2 walked
    /// from and the candidates it collected.
    pub fn debug_state(&self, gpu: &Gpu) -> Result<DebugState> {
        let g = gpu.read::<u32>(&self.group_count, 0, 1)?[0];
        let mut groups: Vec<u32> = gpu.read::<DrawArgs>(&self.groups, 0, g as u64)?.iter().map(|d| d.first_instance).collect();
        groups.sort_unstable();
        let walk = gpu.read::<u32>(&self.walk, 2, 2)?;
        Ok(DebugState {
            walked: walk[0],
            candidates: walk[1],
            state: gpu.read(&self.state, 0, self.nodes.min(self.tree_nodes) as u64)?,
            groups,
            occluders: gpu.read::<u32>(&self.occluders, 0, self.n as u64)?.iter().map(|&x| x != 0).collect(),
            occludees: gpu.read::<u32>(&self.occludees, 0, self.n as u64)?.iter().map(|&x| x != 0).collect(),
        })
    }

    /// Debug read-back: next frame's V, per object, as the last frame's
    /// occluder filtering (or merge) left it.
    pub fn next_occluders(&self, gpu: &Gpu) -> Result<Vec<bool>> {
        Ok(gpu.read::<u32>(&self.visible, 0, self.n as u64)?.iter().map(|&x| x != 0).collect())
    }
}

impl Hroc {
    /// Pixels per side of the occlusion test's blocks in this view (1: per pixel).
    pub fn test_scale(&self) -> u32 {
        self.blocks.as_ref().map_or(1, |b| b.scale)
    }

    /// The stall-free variant's `max_count` estimates of V, G and U in the
    /// last frame; `None` for the other variants.
    pub fn estimates(&self) -> Option<[u32; 3]> {
        self.sf.as_ref().map(|sf| [sf.estimates[0], sf.estimates[1], sf.estimates[2]])
    }

    /// This frame's packed occluder list V (drawing it alone rebuilds the occlusion map).
    pub fn occluder_list(&self) -> &DrawList {
        &self.v_drawn
    }

    /// This frame's refill of V's holes (empty on seeded frames): the
    /// occlusion map is V's list and this one drawn.
    pub fn refill_list(&self) -> &DrawList {
        &self.refill_list
    }

    /// The front list of occludee round `k` (all rounds but the last), if any.
    pub fn front_list(&self, k: u32) -> Option<&DrawList> {
        self.rounds.as_ref()?.fronts.get(k as usize).map(|(l, _)| l)
    }

    /// Debug read-back of the last frame's rounds, with more than one: per
    /// object, the round it was drawn in front (k + 1, 0 if not), and
    /// whether the late test of `round` made it a candidate of the next.
    pub fn round_marks(&self, gpu: &Gpu, round: u32) -> Result<Option<(Vec<u32>, Vec<bool>)>> {
        let Some(r) = &self.rounds else { return Ok(None) };
        let front = gpu.read::<u32>(&r.front, 0, self.n as u64)?;
        let next = gpu.read::<u32>(&r.alive[round as usize % 2], 0, self.n as u64)?.iter().map(|&x| x == round + 2).collect();
        Ok(Some((front, next)))
    }
}

/// Last frame's GPU state, for comparison with the [`cpu`] references.
pub struct DebugState {
    /// Per-node state ([`cpu::NIL`], [`cpu::UNKNOWN`] or [`cpu::VISIBLE`]), node order.
    pub state: Vec<u32>,
    /// Group root nodes, sorted.
    pub groups: Vec<u32>,
    /// Per-object O marks (effective occluders), object order.
    pub occluders: Vec<bool>,
    /// Per-object U marks (occludees), object order.
    pub occludees: Vec<bool>,
    /// Objects step 2's walk ran from: the effective occluders (V's that
    /// drew, and the refill's).
    pub walked: u32,
    /// Nodes the walks left unknown first: the collection's candidates.
    pub candidates: u32,
}
