//! A bench run's results, as the table and the JSON give them: one row
//! per method ([`MethodRow`]) in a [`BenchReport`].

use serde::Serialize;
use std::collections::BTreeMap;

use super::Projection;
use hroc::Method;

/// One row of the table. Later methods add fields; these names never change.
#[derive(Clone, Debug, Serialize)]
pub struct MethodRow {
    /// By its name in the JSON.
    #[serde(serialize_with = "method_name")]
    pub method: Method,
    pub ms_mean: f64,
    pub ms_p95: f64,
    /// Summed stage times; `None` without timestamps.
    pub gpu_ms_mean: Option<f64>,
    pub c_over_n: f64,
    pub c_over_r: f64,
    pub false_negatives: u64,
    /// The frames with a false negative or a missing pixel, each with its
    /// counts (frame, false negatives, missing pixels): where to look.
    pub missed_frames: Vec<(usize, u32, u32)>,
    pub missing_pixels: u64,
    /// `noc`'s stray fragments the method did not reproduce (`Check::stray_pixels`).
    pub stray_pixels: u64,
    /// Mean objects drawn per frame, over every view.
    pub drawn_mean: f64,
    /// Mean objects drawn per frame by each view: the camera's, then each
    /// shadow cascade's.
    pub drawn_per_view: Vec<f64>,
    /// Most objects the camera view drew in one timed frame (after the
    /// warm-up): a frame whose visible set collapsed.
    pub drawn_max: u64,
    /// Mean triangles drawn per frame, and their fraction of the scene's
    /// (of every view's scene, with shadow cascades).
    pub triangles_mean: f64,
    pub triangles_fraction: f64,
    /// Mean GPU ms per stage, in stage order (by name in the JSON).
    #[serde(serialize_with = "by_stage_name")]
    pub stages_ms: BTreeMap<hroc::stats::Stage, f64>,
    /// Mean shader invocations per frame and stage, from pipeline-statistics
    /// queries (with `--breakdown` on devices that have them): work that
    /// does not depend on how busy the machine is. Empty without them.
    #[serde(serialize_with = "by_stage_name")]
    pub invocations: BTreeMap<hroc::stats::Stage, InvocationsMean>,
    /// Mean per frame of the method's own statistics (HROC: V, O, G, U, D,
    /// rays, nodes_per_ray), by name in the JSON: the camera view's. Empty
    /// for methods without any.
    #[serde(serialize_with = "by_stat_name")]
    pub stats: BTreeMap<hroc::stats::Stat, f64>,
    /// Wall ms of every frame (warm-up frames included).
    pub frame_ms: Vec<f64>,
    /// Triangles drawn in every frame, by every view (warm-up frames
    /// included): with `vfc`'s, the frustum's count each frame.
    pub frame_triangles: Vec<u64>,
    /// Frames the camera view took as camera cuts.
    pub cut_frames: Vec<usize>,
    /// `auto`: the method that culled each frame of the camera view
    /// (empty for the other methods).
    #[serde(serialize_with = "method_names")]
    pub frame_methods: Vec<Method>,
}

impl MethodRow {
    /// `auto`: each method it ran and the share of frames it ran, most first.
    pub fn choices(&self) -> Vec<(Method, f64)> {
        let mut out: Vec<(Method, f64)> = Vec::new();
        for m in &self.frame_methods {
            match out.iter_mut().find(|(x, _)| x == m) {
                Some(e) => e.1 += 1.0,
                None => out.push((*m, 1.0)),
            }
        }
        out.iter_mut().for_each(|e| e.1 /= self.frame_methods.len() as f64);
        out.sort_by(|a, b| b.1.total_cmp(&a.1));
        out
    }

    /// Invocations per frame of the stages that do not draw scene
    /// geometry: the work of culling itself.
    pub fn culling_invocations(&self) -> InvocationsMean {
        self.invocations.iter().filter(|(stage, _)| !stage.draws_scene()).fold(InvocationsMean::default(), |a, (_, i)| InvocationsMean {
            vertex: a.vertex + i.vertex,
            fragment: a.fragment + i.fragment,
            compute: a.compute + i.compute,
        })
    }
}

/// Mean shader invocations per frame of one stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct InvocationsMean {
    pub vertex: f64,
    pub fragment: f64,
    pub compute: f64,
}

impl InvocationsMean {
    pub(super) fn of(sum: &hroc::stats::Invocations, frames: f64) -> Self {
        InvocationsMean { vertex: sum.vertex as f64 / frames, fragment: sum.fragment as f64 / frames, compute: sum.compute as f64 / frames }
    }
}

/// Serializes a per-stage map by stage name, in stage order.
fn by_stage_name<T: Serialize, S: serde::Serializer>(m: &BTreeMap<hroc::stats::Stage, T>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_map(m.iter().map(|(k, v)| (k.name(), v)))
}

/// Serializes a per-statistic map by statistic name, in declaration order.
fn by_stat_name<S: serde::Serializer>(m: &BTreeMap<hroc::stats::Stat, f64>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_map(m.iter().map(|(k, v)| (k.name(), v)))
}

#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub scene: String,
    pub objects: usize,
    pub triangles: u64,
    pub resolution: String,
    pub adapter: String,
    /// What the culler ran with: `full`, `portable`, or the two capabilities.
    #[serde(default)]
    pub capabilities: String,
    /// Every view's draws were validated ([`BenchOptions::validate`](super::BenchOptions::validate)),
    /// and no finding came.
    #[serde(default)]
    pub validated: bool,
    pub frames: usize,
    /// Frames per second of camera path: how far apart in time the frames
    /// are (the coherence a method can rely on).
    pub frames_per_second: f64,
    /// The camera path: `own` (the scene's), `hard`, `cuts`, or a file.
    pub path: String,
    /// Samples per pixel of the camera's targets.
    pub msaa: u32,
    /// Shadow cascades, each a view culled beside the camera's.
    pub shadow_cascades: u32,
    /// How the camera projects.
    pub projection: Projection,
    /// Frames at the start left out of the timing statistics (not of the checks).
    pub warmup_frames: usize,
    pub split: String,
    pub bvh_nodes: usize,
    pub bvh_build_ms: f64,
    /// Fraction of the objects moved every frame.
    pub moving: f64,
    /// Objects moved every frame.
    pub moved_objects: usize,
    /// Mean per-frame object update, ms: the culler's part
    /// (`Culler::set_bounds`: boxes, BVH refit or rebuild, uploads landed on
    /// the GPU), shared by every method of the run and untimed in their
    /// rows; the `object update` stage.
    pub update_ms_mean: f64,
    /// The CPU part of it, ms per frame.
    pub refit_ms_mean: f64,
    /// The bench host's own part, ms per frame: tight boxes from the new
    /// transforms, and the transforms uploaded.
    pub host_update_ms_mean: f64,
    /// BVH SAH cost after the last frame's refit over the cost as last
    /// built (1 for a static scene): how much the refit tree degraded.
    /// `None` with the GPU refit, whose boxes the CPU does not see.
    pub sah_growth: Option<f64>,
    /// Moving objects flagged DYNAMIC (tested alone, not refit).
    pub dynamic: bool,
    /// Where the BVH was refit (`cpu`, `gpu`).
    pub refit: String,
    /// Rebuilds of the BVH over the run.
    pub rebuilds: usize,
    pub rows: Vec<MethodRow>,
}

/// Methods by their names in the JSON rows.
fn method_names<S: serde::Serializer>(m: &[Method], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(m.iter().map(|m| m.name()))
}

/// A method by its name in the JSON rows.
fn method_name<S: serde::Serializer>(m: &Method, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(m.name())
}
