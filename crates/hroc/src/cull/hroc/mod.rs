//! `hroc`: Hierarchical Raster Occlusion Culling (Lee et al. 2021;
//! Lee's thesis). One frame, as the paper's Figure 2:
//! 0. after a camera cut, V = the objects a coarse grid of rays meets
//!    first (`hroc_seed.wgsl`);
//! 1. occlusion map — draw V (last frame's visible set, packed in object
//!    order) with forced early-Z; fragments mark the effective occluders O
//!    (with ID marks, [`crate::capabilities::Marks::Ids`], O is what owns a pixel of the
//!    ID target after the draw: fewer objects, so more are tested);
//!    where V's depth leaves cells of the seed's grid at the far plane,
//!    their rays' first hits are drawn too (`refill_holes`: no collapse
//!    when V occludes little, as when the eye leaves a building);
//!    With [`MethodOptions::hroc_occluder_rounds`](super::MethodOptions),
//!    in one front-to-back round (as step 4's below): V's objects hidden
//!    behind V's nearest are left for the test as occludees;
//! 2. occludee groups — BVH walk up from every occluder, one thread per
//!    object of V; the siblings a walk leaves unknown are the groups
//!    (`hroc_groups.wgsl`);
//! 3. batch occlusion test — rasterize group boxes, cast rays in their
//!    subtrees (`hroc_test.wgsl`); marked objects are the occludees U.
//!    A leaf whose object has an oriented box is entered only where the
//!    ray is inside that box too;
//!    With [`MethodOptions::hroc_test_scale`](super::MethodOptions) above 1
//!    the test runs on blocks of pixels against their farthest depth;
//! 4. occludee rendering — draw U with early-Z; passing objects are D.
//!    With [`MethodOptions::hroc_rounds`](super::MethodOptions) above 1, in
//!    front-to-back rounds: each draws the occludees whose box is nearest
//!    at some block and tests the rest again against the depth it left
//!    (`rounds_init`, `front_depth_vs`, `front_fs`, `late_fs`);
//! 5. next V = O ∪ D, or with OF the objects that own a pixel
//!    (`hroc_next.wgsl`).
//!
//! CR reads back |V|, |G|, |U| for `max_count` instead of N.
//!
//! The frame's own passes, as a GPU profiler shows them (a steady frame,
//! one occludee round): `hroc compact` (V, and with SF its overflow) → the
//! host draws V → `hroc groups` (the refill's rays, the walk, the objects
//! alone, the collection, with SF G's overflow) → the host draws the
//! refill → `hroc occlusion test` (with blocks, its first draw reduces the
//! host's depth to them) → `hroc compact` (U) → the host draws U → `hroc
//! occluder filtering` (or `hroc next occluders`), whose threads also
//! record the cells the depth covers and reset step 2's counts and launch,
//! so no clear or copy prepares the next frame's walk, and which packs the
//! next frame's V (so the frame opens with the host's draw of V; not after
//! a cut, a change of the objects' commands, nor where V's list has a
//! stall-free estimate or occluder rounds).

mod blocks;
pub mod cpu;
mod debug;
pub mod gate;
mod rounds;
mod setup;
pub mod stall_free;

use crate::cull::facts::Facts;
use crate::gpu::shape::{EncoderShape, PassShape, RenderShape};
pub use blocks::test_scale;
use blocks::{Blocks, BLOCK_FORMAT};
pub use debug::{DebugState, SetSizes};
use rounds::{Rounds, RoundsOf};

use super::{Counters, CullMethod, Frame, Method, MethodContext, Seed, Stage, Stat};
use crate::capabilities::DrawCount;
use crate::compact::{CompactJob, Compactor};
use crate::contract::Phase;
use crate::cull::{DrawList, MarkTarget};
use crate::error::{Error, Result};
use crate::gpu::{dispatch_size, Gpu};
use crate::reflect::Layout;
use crate::shaders::{source_for as shader_source_for, BoxDepth, BoxTarget};
use gate::{Gate, Next, Pays, Plan};
use stall_free::{Counted, Spill, StallFree};

/// The facts of HROC's variant `v`: it reads marks, IDs with OF, and
/// submits mid-frame with counter read-back.
pub(crate) const fn facts(v: Variant) -> Facts {
    use super::Counters::{Capacity, ReadBack, StallFree};
    let (name, description) = match (v.counters, v.of) {
        (Capacity, false) => ("hroc-na", "HROC without accelerations"),
        (ReadBack, false) => ("hroc-cr", "HROC with counter read-back"),
        (Capacity, true) => ("hroc-of", "HROC with occluder filtering"),
        (ReadBack, true) => ("hroc-cr+of", "HROC with counter read-back and occluder filtering"),
        (StallFree, false) => ("hroc-sf", "HROC with stall-free counters (earlier frames' counts, GPU overflow draw)"),
        (StallFree, true) => ("hroc", "HROC, the default variant: stall-free counters and occluder filtering (also hroc-sf+of)"),
    };
    use Layout as L;
    Facts {
        name,
        description,
        needs_ids: v.of,
        submits_mid_frame: matches!(v.counters, ReadBack),
        reads_marks: true,
        layouts: &[L::HrocSeed, L::HrocWalk, L::HrocGroups, L::HrocNext, L::HrocTest, L::HrocRounds, L::HrocRoundsInit, L::HrocReduce, L::Overflow, L::Compact],
        ..Facts::GPU
    }
}

/// The deepest BVH HROC walks: its traversal stacks hold depth + 2
/// entries ([`crate::shaders::STACK`]).
pub const MAX_DEPTH: u32 = crate::shaders::STACK - 2;
/// V's rounds with [`MethodOptions::hroc_occluder_rounds`](super::MethodOptions):
/// its front list, then the rest still in front of the depth that left.
/// The stall-free counters count them as [`Counted::OccluderFront`] and
/// [`Counted::OccluderRest`], so the number is fixed.
pub const OCCLUDER_ROUNDS: u32 = 2;
/// Most occludee rounds: each costs a reduce, three box passes over U and
/// a compaction, and past four the rounds measured no further culling.
pub const MAX_ROUNDS: u32 = 4;
const STAT_SLOTS: u64 = crate::shaders::STAT_SLOTS as u64;

pub use super::Variant;

/// The `hroc` method (and its `-cr`/`-na` variants): per-view GPU state of the five steps above.
pub struct Hroc {
    variant: Variant,
    n: u32,
    /// Node capacity (buffer sizes, dispatches).
    nodes: u32,
    /// Nodes of the tree the last frame walked.
    tree_nodes: u32,
    /// Per-object flags: next frame's occluders V.
    visible: wgpu::Buffer,
    occluders: wgpu::Buffer,
    occludees: wgpu::Buffer,
    drawn: wgpu::Buffer,
    state: wgpu::Buffer,
    visited: wgpu::Buffer,
    group_count: wgpu::Buffer,
    /// Step 2's counts and candidates (`work` in `hroc_groups.wgsl`).
    walk: wgpu::Buffer,
    /// The collection's workgroups, which the walks write (a buffer cannot
    /// be both written and read as workgroups in one dispatch).
    collect_launch: wgpu::Buffer,
    /// [`COLLECT_LAUNCH`], copied to `collect_launch` when a frame stopped
    /// before step 5 reset it.
    collect_init: wgpu::Buffer,
    /// Step 2 ran and step 5 has not yet reset its counts.
    walk_open: bool,
    ray_stats: wgpu::Buffer,
    /// This frame's packed V (with a spare: next frame's, once step 5 packed it).
    v_list: DrawList,
    /// The list V was drawn from in the last frame (debugging).
    v_drawn: DrawList,
    /// Where step 5 packs the next frame's V, in its own pass, then swapped
    /// with `v_list` and `v_job`: where V's list has no stall-free estimate
    /// and no occluder rounds are bound to it.
    spare_v: Option<(DrawList, CompactJob)>,
    /// `v_list` was packed at the end of the last frame, from the commands
    /// of this version ([`crate::objects::SharedObjects::commands_version`]).
    v_packed: Option<u64>,
    u_list: DrawList,
    groups: wgpu::Buffer,
    compactor: Compactor,
    v_job: CompactJob,
    u_job: CompactJob,
    marks_o: MarkTarget,
    marks_d: MarkTarget,
    /// With marks from boxes (and no OF, no rounds): V's objects are all
    /// occluders O, and one box pass after U's draw marks V's and U's
    /// objects against the frame's final depth as D, alone next frame's V
    /// (one pass a frame, not one per list; V keeps what is in front).
    marks_at_end: bool,
    test_bind: wgpu::BindGroup,
    /// Step 2's passes: the walk up from the effective occluders, the
    /// objects tested alone, the collection of the groups.
    extract: Step,
    alone: Step,
    collect: Step,
    merge: Step,
    filter: Step,
    /// The filter counting what it changes, for the gate.
    probe: Option<Step>,
    /// The frame sized to what it saves in the view ([`gate`]): occlusion
    /// where it culls, OF where it changes the next V.
    gate: Option<Gate>,
    /// With the gate: the count of what occlusion culls (after the
    /// test), and the frames of frustum culling alone.
    measure: Option<Step>,
    frustum: Option<Step>,
    /// What the last frame ran.
    plan: Plan,
    /// Bytes read back by a plan made before the frame (`plan_set`).
    planned: Option<u64>,
    /// The seed's grid ([`seed_grid`]).
    grid: (u32, u32),
    /// One ID pixel read in every `filter_stride²` ([`MethodOptions::hroc_filter_stride`](super::MethodOptions)).
    filter_stride: u32,
    seed: Step,
    /// Step 1's refill of V where its depth left holes (against the cells
    /// the last frame covered, which step 5 records).
    refill: Step,
    refill_list: DrawList,
    boxes: wgpu::RenderPipeline,
    /// With an emulated draw count: the group boxes' instanced draw.
    group_args: Option<wgpu::Buffer>,
    /// What the batch test renders into: the depth, or without early-Z
    /// marks or read-only depth a colour target (`MANUAL_DEPTH`).
    test_target: BoxTarget,
    /// With a test scale above 1: the blocks' occlusion map and the pass that reduces the host's depth to it.
    blocks: Option<Blocks>,
    last: SetSizes,
    seed_mode: Seed,
    /// Seed V this frame (the first one, or after a cut).
    seed_next: bool,
    /// V was seeded in the last frame.
    seeded: bool,
    /// The stall-free variant's estimates and overflow passes.
    sf: Option<StallFree>,
    /// Front-to-back occludee rounds, when more than one.
    rounds: Option<Rounds>,
    /// V's front-to-back rounds, when asked for.
    occluder_rounds: Option<Rounds>,
}

/// The most cells of the occluder seed's ray grid (`hroc_seed.wgsl`):
/// 64 × 36 rays, one per 10 × 10 pixels at 640 × 360, each a BVH walk
/// that prunes behind its nearest hit: about as much work as the
/// occlusion test's rays over a few group boxes.
pub const SEED_GRID: (u32, u32) = (64, 36);

/// Pixels per side of a cell of the seed's grid, in views too small for
/// [`SEED_GRID`] at this spacing. At 64 × 36 pixels (2,304 cells at one
/// per pixel) the grid's texel loads and rays cost a tenth of the frame on
/// lavapipe; one cell per 3 × 3 pixels kept C/R within 0.002 of a cell
/// per pixel (BENCHMARKS.md).
pub const SEED_CELL_PX: u32 = 3;

/// The seed's grid for a view of `size` pixels: one cell per
/// [`SEED_CELL_PX`]² pixels, at most [`SEED_GRID`] (so a small view casts
/// few rays, and step 5 and the refill load few texels for it).
pub fn seed_grid(size: (u32, u32)) -> (u32, u32) {
    (size.0.div_ceil(SEED_CELL_PX).clamp(1, SEED_GRID.0), size.1.div_ceil(SEED_CELL_PX).clamp(1, SEED_GRID.1))
}

/// Occluder filtering's tile: each thread reads FILTER_TILE² of the pixels
/// it filters (`hroc_next.wgsl`), storing an object once per run of pixels
/// it owns.
const FILTER_TILE: u32 = 2;

/// The workgroups of a compute pass: a grid, or read from a buffer at an
/// offset (a count the frame's earlier passes wrote).
enum Launch<'b> {
    Grid(u32, u32),
    Indirect(&'b wgpu::Buffer, u64),
}

/// Step 2's counts and the collection's launch as step 5 leaves them for
/// the next frame (`hroc_next.wgsl`): no candidate, the root's workgroup.
const COLLECT_LAUNCH: [u32; 4] = [1, 1, 1, 0];

/// A compute pass of HROC's frame: its pipeline and bindings.
struct Step {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
}

impl Hroc {
    /// Records `steps` in order into one compute pass named `label` (wgpu
    /// orders each dispatch after the ones it depends on), then the
    /// compaction `pack`, then `spill`, an overflow list's fill, whose
    /// count the steps or the compaction made final.
    fn compute(&self, f: &mut Frame, label: &str, steps: &[(&Step, Launch)], pack: Option<&CompactJob>, spill: Option<&Spill>) {
        let (enc, q) = f.counted();
        let mut pass = enc.counted_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None });
        q.around(&mut pass, |pass| {
            Self::record_steps(pass, steps);
            if let Some(job) = pack {
                self.compactor.record_in(pass, job);
            }
            if let (Some(sf), Some(spill)) = (&self.sf, spill) {
                sf.record(pass, spill);
            }
        });
    }

    /// Records `steps` in order into an open compute pass.
    fn record_steps(pass: &mut wgpu::ComputePass<'_>, steps: &[(&Step, Launch)]) {
        for (step, launch) in steps {
            pass.set_pipeline(&step.pipeline);
            pass.set_bind_group(0, &step.bind, &[]);
            match *launch {
                Launch::Grid(x, y) => pass.counted_dispatch(x, y, 1),
                Launch::Indirect(args, offset) => pass.counted_dispatch_indirect(args, offset),
            }
        }
    }

    /// Records `steps`, then compacts `job`'s list and, with SF, fills the overflow of `which`
    /// (when it is drawn as it is) after it, in one compute pass; returns
    /// the overflow list.
    fn compact(&self, f: &mut Frame, steps: &[(&Step, Launch)], job: &CompactJob, which: Option<Counted>) -> Option<DrawList> {
        let spill = which.and_then(|w| self.sf.as_ref()?.overflow(f, w));
        self.compute(f, "hroc compact", steps, Some(job), spill.as_ref().map(|(_, s)| s));
        spill.map(|(list, _)| list)
    }

    /// `max_count` of a list: the read-back count with CR, the estimate
    /// with SF, else the capacity.
    fn max_count(&self, f: &mut Frame, which: Counted, count: &wgpu::Buffer, capacity: u32, resume: Stage) -> Result<u32> {
        match (self.variant.counters, &self.sf) {
            (Counters::ReadBack, _) => {
                f.stage(Stage::ReadBack);
                let c = f.read_u32(count, 1)?[0].min(capacity);
                f.stage(resume);
                Ok(c)
            }
            (Counters::StallFree, Some(sf)) => Ok(sf.estimate(which).unwrap_or(capacity)),
            _ => Ok(capacity),
        }
    }

    /// Hands `list` to the host, and with SF its overflow list `over`
    /// ([`Hroc::compact`]) after it. With ID marks, one pass over the ID
    /// target marks both lists (none without `marks`).
    fn draw_list(&self, f: &mut Frame, phase: Phase, list: &DrawList, over: Option<DrawList>, marks: Option<&MarkTarget>) {
        let lists: Vec<&DrawList> = [(list.max_count > 0).then_some(list), over.as_ref()].into_iter().flatten().collect();
        f.draw_all(phase, &lists, marks);
    }

    /// Step 2's counts and the collection's launch back at rest, as step 5
    /// leaves them.
    fn reset_walk(&self, enc: &mut wgpu::CommandEncoder) {
        enc.counted_clear(&self.walk, 0, Some(8));
        enc.counted_copy(&self.collect_init, 0, &self.collect_launch, 0, Some(16));
    }

    /// Where step 4's lists mark D: nowhere with occluder filtering and ID
    /// marks (OF reads the ID target itself, and D serves only the merge
    /// OF replaces; |D| is then not kept).
    fn d_marks(&self) -> Option<&MarkTarget> {
        match (&self.marks_d, self.variant.of) {
            (MarkTarget::Ids(_) | MarkTarget::Boxes(..), true) => None,
            (marks, _) => Some(marks),
        }
    }
}

impl CullMethod for Hroc {
    fn method(&self) -> Method {
        Method::Hroc(self.variant)
    }

    fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        let refreshes = self.refreshes().is_some();
        if let Some(g) = self.gate.as_mut() {
            g.reset(refreshes);
        }
        enc.counted_clear(&self.visible, 0, None);
        self.reset_walk(enc);
        self.planned = None;
        self.seed_next = true;
        self.v_packed = None;
    }

    fn visible_set(&self) -> Option<&wgpu::Buffer> {
        Some(&self.visible)
    }

    fn plan_set(&mut self, gpu: &Gpu) -> Option<DrawList> {
        self.plan_early(gpu)
    }

    fn planned_frame_needed(&self) -> bool {
        self.plan.refresh // (Before a probe: its depth makes V.)
    }

    fn take_over(&mut self, enc: &mut wgpu::CommandEncoder, visible: Option<&wgpu::Buffer>) {
        match visible {
            // V is the set handed over, as after an ordinary frame: no seed
            // (the refill still fills what its depth leaves open).
            Some(v) => {
                enc.counted_copy(v, 0, &self.visible, 0, v.size().min(self.visible.size()));
                self.seed_next = false;
                self.v_packed = None;
            }
            None => self.reset(enc),
        }
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        let (n, nodes) = (self.n, self.nodes);
        self.tree_nodes = f.uniform.node_count;
        let (ox, oy) = dispatch_size(n, 256);
        let cells = self.grid.0 * self.grid.1;
        if std::mem::take(&mut self.walk_open) {
            // A frame stopped between its walk and step 5, which resets it.
            self.reset_walk(f.encoder());
        }
        // What this frame runs, by what the view's last probe measured.
        self.plan_frame(f);
        if let (false, Some(frustum)) = (self.plan.occlusion, &self.frustum) {
            // (In a set of views, the set's pass packed U.)
            if !f.set_frustum(&self.frustum_list()) {
                self.frustum_frame(f, frustum);
            }
            self.refresh_occluders(f);
            // The next HROC frame packs V anew.
            self.v_packed = None;
            return Ok(());
        }
        if let (true, Some(g)) = (self.plan.probe, &self.gate) {
            g.begin_probe(f.encoder());
        }
        // 0. After a cut V is stale or empty: seed it from a ray grid.
        self.seeded = match self.seed_mode {
            Seed::Cuts | Seed::CutsOnly => std::mem::take(&mut self.seed_next),
            Seed::Always => true,
            Seed::Never => false,
        };
        if self.seeded {
            f.stage(Stage::Seed);
            self.compute(f, "hroc seed", &[(&self.seed, Launch::Grid(cells.div_ceil(64), 1))], None, None);
        }
        // 1. Occlusion map.
        f.stage(Stage::OcclusionMap);
        match self.marks_at_end {
            // O = V, which the seed (if any) has just written.
            true => f.encoder().counted_copy(&self.visible, 0, &self.occluders, 0, None),
            false => f.encoder().counted_clear(&self.occluders, 0, None),
        }
        if let Some(sf) = self.sf.as_mut() {
            let bytes = sf.begin(f.gpu);
            f.count_async_read(bytes);
        }
        // V's list (which instances the rounds' box passes when they draw
        // it), unless step 5 packed it from the same flags and commands.
        let packed = self.v_packed.take() == Some(f.objects.commands_version) && !self.seeded;
        let over = if packed { None } else { self.compact(f, &[], &self.v_job, self.occluder_rounds.is_none().then_some(Counted::V)) };
        if let Some(r) = &self.occluder_rounds {
            self.v_drawn = self.v_list.clone();
            r.clear(f.encoder());
            self.rounds(f, r, RoundsOf::Occluders)?;
        } else {
            self.v_list.max_count = self.max_count(f, Counted::V, &self.v_list.count, n, Stage::OcclusionMap)?;
            self.v_drawn = self.v_list.clone();
            let marks = (!self.marks_at_end).then_some(&self.marks_o);
            self.draw_list(f, Phase::Occluders, &self.v_list, over.clone(), marks);
        }
        // What the box pass at the end marks, besides U.
        let mut v_lists: Vec<DrawList> = match self.marks_at_end {
            true => [(self.v_list.max_count > 0).then(|| self.v_list.clone()), over].into_iter().flatten().collect(),
            false => Vec::new(),
        };
        // 1b and 2, one pass: where V left the map empty, the ray grid's
        // first hits join the occluders (not after a seed, which cast the
        // same rays; no collapse); the walk up from every effective
        // occluder; the objects tested alone; the groups collected.
        f.stage(Stage::GroupExtraction);
        // (Not in a stepwise frame: the refill would be a second early pass.)
        let refill = !self.seeded && self.seed_mode == Seed::Cuts && !f.stepwise();
        let enc = f.encoder();
        enc.counted_clear(&self.refill_list.count, 0, None);
        for b in [&self.state, &self.visited, &self.group_count, &self.occludees, &self.ray_stats] {
            enc.counted_clear(b, 0, None);
        }
        if let Some(r) = &self.rounds {
            r.clear(enc);
        }
        self.walk_open = true;
        let mut steps = Vec::with_capacity(4);
        if refill {
            steps.push((&self.refill, Launch::Grid(cells.div_ceil(64), 1)));
        }
        steps.push((&self.extract, Launch::Grid(ox, oy)));
        if f.objects.alone > 0 {
            steps.push((&self.alone, Launch::Grid(ox, oy)));
        }
        steps.push((&self.collect, Launch::Indirect(&self.collect_launch, 0)));
        // The group boxes are drawn up to |G| by the indirect count (from a
        // bound: the capacity, CR's read-back or SF's estimate and its
        // overflow), or as one instanced draw of |G| instances.
        let spill = match &self.group_args {
            Some(_) => None,
            None => self.sf.as_ref().and_then(|sf| sf.overflow(f, Counted::G)),
        };
        self.compute(f, "hroc groups", &steps, None, spill.as_ref().map(|(_, s)| s));
        let (max_groups, over) = match &self.group_args {
            Some(args) => {
                f.encoder().counted_copy(&self.group_count, 0, args, 4, Some(4));
                (nodes + n, None)
            }
            None => (self.max_count(f, Counted::G, &self.group_count, nodes + n, Stage::GroupExtraction)?, spill.map(|(list, _)| list)),
        };
        if refill {
            f.stage(Stage::OcclusionMap);
            f.draw(Phase::Occluders, &self.refill_list, None);
            if self.marks_at_end {
                v_lists.push(self.refill_list.clone());
            }
        }
        // 3. Batch occlusion test against the occlusion map (read-only depth).
        f.stage(Stage::OcclusionTest);
        if max_groups > 0 || over.is_some() {
            let targets = f.targets;
            // With blocks attached, the pass first reduces the host's depth to them.
            let reduce = self.blocks.as_ref().filter(|_| self.test_target.mode() == BoxDepth::Test);
            let (enc, q) = f.counted();
            let mut pass = match reduce {
                Some(b) => self.test_target.begin_writing(enc, "hroc occlusion test", b.attachment()),
                None => self.test_target.begin(enc, "hroc occlusion test", self.blocks.as_ref().map_or(&targets.depth_attachment, |b| &b.view)),
            };
            q.around(&mut pass, |pass| {
                if let Some(b) = reduce {
                    b.record_in(pass);
                }
                pass.set_pipeline(&self.boxes);
                pass.set_bind_group(0, &self.test_bind, &[]);
                match &self.group_args {
                    Some(args) => pass.counted_draw_indirect(args, 0),
                    None => {
                        pass.counted_multi_draw_indirect_count(&self.groups, 0, &self.group_count, 0, max_groups);
                        if let Some(over) = over {
                            // The groups past the estimate, from where the first draw stopped.
                            pass.counted_multi_draw_indirect_count(&self.groups, max_groups as u64 * 16, &over.count, 0, over.max_count);
                        }
                    }
                }
            });
        }
        // 4. Occludee rendering.
        f.stage(Stage::OccludeeRendering);
        f.encoder().counted_clear(&self.drawn, 0, None);
        // U's list instances the rounds' box passes when they draw it. A
        // probe counts what occlusion culls in the same pass.
        let measure = self.measure.as_ref().filter(|_| self.plan.probe).map(|m| (m, Launch::Grid(ox, oy)));
        let over = self.compact(f, measure.as_slice(), &self.u_job, self.rounds.is_none().then_some(Counted::U));
        if let Some(r) = &self.rounds {
            self.rounds(f, r, RoundsOf::Occludees)?;
        } else {
            self.u_list.max_count = self.max_count(f, Counted::U, &self.u_list.count, n, Stage::OccludeeRendering)?;
            match (&self.marks_d, self.marks_at_end) {
                (MarkTarget::Boxes(boxes, drawn), true) => {
                    self.draw_list(f, Phase::Occludees, &self.u_list, over.clone(), None);
                    // V's and U's objects against the final depth, in one pass.
                    let u_lists = [(self.u_list.max_count > 0).then_some(&self.u_list), over.as_ref()];
                    let lists: Vec<&DrawList> = v_lists.iter().chain(u_lists.into_iter().flatten()).collect();
                    boxes.record(f, &lists, drawn);
                }
                _ => self.draw_list(f, Phase::Occludees, &self.u_list, over, self.d_marks()),
            }
        }
        // 5. Next frame's occluders; the same threads record the cells the
        // depth covers (for the refill) and reset step 2's counts.
        f.stage(Stage::Filtering);
        let cover = self.covered_cells();
        // OF where it changes the result (`gate`).
        let next = self.plan.next;
        // With a spare list, the same pass packs the next frame's V.
        let (step, label, launch) = if next != Next::Merge {
            let (w, h) = f.size();
            f.encoder().counted_clear(&self.visible, 0, None);
            let s = self.filter_stride * FILTER_TILE;
            let x = w.div_ceil(s).div_ceil(16);
            let step = if next == Next::Probe { self.probe.as_ref().unwrap_or(&self.filter) } else { &self.filter };
            (step, "hroc occluder filtering", Launch::Grid(x, h.div_ceil(s).div_ceil(16).max(cover.div_ceil(x * 256))))
        } else {
            (&self.merge, "hroc next occluders", self.merge_launch())
        };
        self.compute(f, label, &[(step, launch)], self.spare_v.as_ref().map(|(_, job)| job), None);
        if let (true, Some(g)) = (self.plan.probe, self.gate.as_mut()) {
            g.end_probe(f.encoder);
        }
        if let Some(spare) = self.spare_v.as_mut() {
            std::mem::swap(&mut self.v_list, &mut spare.0);
            std::mem::swap(&mut self.v_job, &mut spare.1);
            self.v_packed = Some(f.objects.commands_version);
        }
        self.walk_open = false;
        if let Some(sf) = self.sf.as_mut() {
            let last = self.rounds.as_ref().map_or(&self.u_list, |r| &r.last.0);
            let v_rounds = self.occluder_rounds.as_ref().map(|r| (&r.fronts[0].0.count, &r.last.0.count));
            let mut counts = vec![Some(&self.v_drawn.count), Some(&self.group_count), Some(&last.count), v_rounds.map(|v| v.0), v_rounds.map(|v| v.1)];
            counts.extend(self.rounds.iter().flat_map(|r| r.fronts.iter().map(|(l, _)| Some(&l.count))));
            sf.end(f.encoder, &counts);
        }
        Ok(())
    }

    fn tested_nodes(&self, gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(Some(self.debug_state(gpu)?.groups))
    }

    fn stats(&mut self, gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        let c = self.set_sizes(gpu)?;
        self.last = c;
        Ok(vec![
            (Stat::V, c.v as f64),
            (Stat::O, c.o as f64),
            (Stat::G, c.g as f64),
            (Stat::U, c.u as f64),
            (Stat::Front, c.front as f64),
            (Stat::D, c.d as f64),
            (Stat::Rays, c.rays as f64),
            (Stat::NodesPerRay, if c.rays > 0 { c.nodes_visited as f64 / c.rays as f64 } else { 0.0 }),
            (Stat::Seeded, self.seeded as u32 as f64),
            (Stat::Filtered, (self.plan.occlusion && self.plan.next != Next::Merge) as u32 as f64),
            (Stat::Occlusion, self.plan.occlusion as u32 as f64),
        ])
    }
}
