//! Bind-group layouts derived from the WGSL: naga's reflection of each
//! pass gives every binding of a group its type (uniform, storage read or
//! read-write, texture kind) and the stages whose entry points use it, so
//! no layout is typed beside the shader it describes.

use crate::gpu::shape::DeviceShape;
use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex, OnceLock};

use crate::gpu::Gpu;
use crate::shaders;

/// One entry point's bindings: (group, binding) → (type, its stage).
type Bindings = BTreeMap<(u32, u32), (wgpu::BindingType, wgpu::ShaderStages)>;

/// Each entry point of a pass, by name, with its bindings.
type EntryPoints = Arc<Vec<(String, Bindings)>>;

/// The entry points of a pass that one layout serves: the pass's name in
/// [`shaders::SHADERS`], and its entry points (all of them when empty).
pub type Pass<'a> = (&'a str, &'a [&'a str]);

/// Every bind-group layout the culler creates, each named after what it
/// binds, with the pass entry points it serves (all in group 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// Ordered compaction of flagged draw commands.
    Compact,
    /// The GPU refit of moving objects' boxes and the BVH.
    Refit,
    /// The split of flagged objects out of a method's lists.
    FlagSplit,
    /// The per-list count of objects and triangles drawn.
    Tally,
    /// The zeroed tail of a list drawn without a GPU count.
    Tail,
    /// The stamps of visibility as data.
    Visibility,
    /// ID marks: the objects owning a pixel of the ID target.
    IdMarks,
    /// `vfc`'s frustum test.
    Vfc,
    /// The frustum test and packing of a set of views.
    SetFrustum,
    /// The Hi-Z pyramid's build (`hzb`, `woc`).
    HiZBuild,
    /// The Hi-Z test of boxes (`hzb`, `woc`).
    HiZTest,
    /// `woc`'s warp of last frame's depth.
    WocWarp,
    /// ROC's raster box test.
    RocBoxes,
    /// ROC's selection and split of marked boxes.
    Roc,
    /// IOC's level-by-level traversal.
    Ioc,
    /// The query methods' box pass.
    QueryBoxes,
    /// HROC's ray grid: the seed of V after a cut (step 0), the refill of
    /// V's holes (step 1), and the cells the frame's depth covers.
    HrocSeed,
    /// HROC's step 2, the walk up the BVH from V's occluders.
    HrocWalk,
    /// HROC's step 2, the occludee groups: the walk's candidates and the
    /// objects tested alone.
    HrocGroups,
    /// HROC's step 5: the next V.
    HrocNext,
    /// What occlusion culls in a view, and frames of frustum culling alone.
    HrocYield,
    /// HROC's batch occlusion test (step 3).
    HrocTest,
    /// HROC's front-to-back rounds.
    HrocRounds,
    /// The first round's set-up: what the rounds bind, and the list's count.
    HrocRoundsInit,
    /// HROC's reduction of depth to blocks of pixels.
    HrocReduce,
    /// The stall-free counters' overflow lists.
    Overflow,
    /// Validation's pass over the host's depth and IDs.
    Validate,
    /// Validation's stamps of the objects a list draws.
    ValidateStamp,
    /// Validation's check of the objects a group marked.
    ValidateMarks,
    /// Validation's check, after a group's pixels, of the objects it
    /// marked that own none.
    ValidateLate,
}

const ROUNDS: &[&str] = &["front_vs", "round_vs", "front_fs", "late_fs"];

impl Layout {
    /// Every layout.
    pub const ALL: [Layout; 30] = [
        Layout::Compact,
        Layout::Refit,
        Layout::FlagSplit,
        Layout::Tally,
        Layout::Tail,
        Layout::Visibility,
        Layout::IdMarks,
        Layout::Vfc,
        Layout::SetFrustum,
        Layout::HiZBuild,
        Layout::HiZTest,
        Layout::WocWarp,
        Layout::RocBoxes,
        Layout::Roc,
        Layout::Ioc,
        Layout::QueryBoxes,
        Layout::HrocSeed,
        Layout::HrocWalk,
        Layout::HrocGroups,
        Layout::HrocNext,
        Layout::HrocYield,
        Layout::HrocTest,
        Layout::HrocRounds,
        Layout::HrocRoundsInit,
        Layout::HrocReduce,
        Layout::Overflow,
        Layout::Validate,
        Layout::ValidateStamp,
        Layout::ValidateMarks,
        Layout::ValidateLate,
    ];

    /// The label of the layout, its pipelines and bind groups.
    pub fn label(self) -> &'static str {
        match self {
            Layout::Compact => "compact",
            Layout::Refit => "hroc refit",
            Layout::FlagSplit => "hroc flag split",
            Layout::Tally => "hroc tally",
            Layout::Tail => "hroc emulated count",
            Layout::Visibility => "hroc visibility",
            Layout::IdMarks => "hroc id marks",
            Layout::Vfc => "vfc",
            Layout::SetFrustum => "hroc set frustum",
            Layout::HiZBuild => "hi-z build",
            Layout::HiZTest => "hi-z test",
            Layout::WocWarp => "woc warp",
            Layout::RocBoxes => "roc boxes",
            Layout::Roc => "roc",
            Layout::Ioc => "ioc",
            Layout::QueryBoxes => "query boxes",
            Layout::HrocSeed => "hroc seed",
            Layout::HrocWalk => "hroc walk",
            Layout::HrocGroups => "hroc groups",
            Layout::HrocNext => "hroc next occluders",
            Layout::HrocYield => "hroc occlusion yield",
            Layout::HrocTest => "hroc test",
            Layout::HrocRounds => "hroc rounds",
            Layout::HrocRoundsInit => "hroc rounds init",
            Layout::HrocReduce => "hroc reduce",
            Layout::Overflow => "hroc overflow",
            Layout::Validate => "hroc validation pixels",
            Layout::ValidateStamp => "hroc validation stamp",
            Layout::ValidateMarks => "hroc validation marks",
            Layout::ValidateLate => "hroc validation late marks",
        }
    }

    /// The entry points it serves.
    pub fn passes(self) -> &'static [Pass<'static>] {
        match self {
            Layout::Compact => &[("compact.wgsl", &[])],
            Layout::Refit => &[("refit.wgsl", &[])],
            Layout::FlagSplit => &[("split.wgsl", &[])],
            Layout::Tally => &[("tally.wgsl", &[])],
            Layout::Tail => &[("tail.wgsl", &[])],
            Layout::Visibility => &[("visibility.wgsl", &[])],
            Layout::IdMarks => &[("id_marks.wgsl", &[])],
            Layout::Vfc => &[("vfc.wgsl", &[])],
            Layout::SetFrustum => &[("set_frustum.wgsl", &[])],
            Layout::HiZBuild => &[("hzb_pyramid.wgsl", &[])],
            Layout::HiZTest => &[("hzb_test.wgsl", &[])],
            Layout::WocWarp => &[("woc_warp.wgsl", &[])],
            Layout::RocBoxes => &[("roc_boxes.wgsl", &["box_vs", "box_fs", "box_vs_sample", "box_fs_sample"])],
            Layout::Roc => &[("roc.wgsl", &[])],
            Layout::Ioc => &[("ioc.wgsl", &[])],
            // Binding 6 (object boxes) serves box_vs's objects tested alone,
            // which the queries never draw.
            Layout::QueryBoxes => &[("hroc_test.wgsl", &["box_vs"])],
            Layout::HrocSeed => &[("hroc_seed.wgsl", &[])],
            // Two layouts of one pass, each within 8 storage buffers.
            Layout::HrocWalk => &[("hroc_groups.wgsl", &["extract"])],
            Layout::HrocGroups => &[("hroc_groups.wgsl", &["alone", "collect"])],
            Layout::HrocNext => &[("hroc_next.wgsl", &[])],
            Layout::HrocYield => &[("hroc_yield.wgsl", &[])],
            Layout::HrocTest => &[("hroc_test.wgsl", &["box_vs", "group_vs", "box_fs"])],
            Layout::HrocRounds => &[("hroc_test.wgsl", ROUNDS)],
            Layout::HrocRoundsInit => &[("hroc_test.wgsl", ROUNDS), ("hroc_test.wgsl", &["rounds_init"])],
            Layout::HrocReduce => &[("hroc_test.wgsl", &["reduce_vs", "reduce_fs"])],
            Layout::Overflow => &[("overflow.wgsl", &[])],
            Layout::Validate => &[("validate.wgsl", &["check_pixels", "box_entries", "suspect"])],
            Layout::ValidateStamp => &[("validate.wgsl", &["stamp"])],
            Layout::ValidateMarks => &[("validate.wgsl", &["marks_of_group"])],
            Layout::ValidateLate => &[("validate.wgsl", &["late_marks"])],
        }
    }

    /// Its entries, in binding order ([`entries`]).
    pub fn entries(self) -> Vec<wgpu::BindGroupLayoutEntry> {
        self.entries_for(1)
    }

    /// Its entries for host targets of `samples` samples ([`entries_for`]).
    pub fn entries_for(self, samples: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
        entries_for(self.passes(), 0, samples)
    }

    /// Creates it on `gpu`'s device.
    pub fn create(self, gpu: &Gpu) -> wgpu::BindGroupLayout {
        self.create_for(gpu, 1)
    }

    /// Creates it for host targets of `samples` samples per pixel: the
    /// passes then load the host's depth and IDs as multisampled textures.
    pub fn create_for(self, gpu: &Gpu, samples: u32) -> wgpu::BindGroupLayout {
        let entries = self.entries_for(samples);
        gpu.cache.bind_layout(self.label(), &entries, || gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(self.label()), entries: &entries }))
    }

    /// A bind group of `layout` (created from this) holding, for each of
    /// its entries, the resource `resources` gives that binding (others
    /// are ignored). Panics when an entry has none (a programming error).
    pub fn bind(self, gpu: &Gpu, layout: &wgpu::BindGroupLayout, resources: &[(u32, wgpu::BindingResource)]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self
            .entries()
            .iter()
            .map(|e| {
                let resource = resources.iter().find(|(b, _)| *b == e.binding).unwrap_or_else(|| panic!("{self:?}: nothing for binding {}", e.binding)).1.clone();
                wgpu::BindGroupEntry { binding: e.binding, resource }
            })
            .collect();
        gpu.device.counted_bind_group(&wgpu::BindGroupDescriptor { label: Some(self.label()), layout, entries: &entries })
    }

    /// Its storage buffers in the stage that sees the most of them: what
    /// `max_storage_buffers_per_shader_stage` must allow.
    pub fn storage_buffers_per_stage(self) -> u32 {
        let entries = self.entries();
        [wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::COMPUTE]
            .iter()
            .map(|&stage| {
                entries.iter().filter(|e| e.visibility.contains(stage) && matches!(e.ty, wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { .. }, .. })).count()
                    as u32
            })
            .max()
            .unwrap_or(0)
    }
}

/// A pipeline layout of one bind group.
pub fn pipeline_layout(gpu: &Gpu, label: &str, layout: &wgpu::BindGroupLayout) -> wgpu::PipelineLayout {
    gpu.cache.pipeline_layout(label, layout, || {
        gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some(label), bind_group_layouts: &[Some(layout)], immediate_size: 0 })
    })
}

/// The bind-group layout entries of `group` that `passes` declare, in
/// binding order: one entry per binding any of their entry points uses,
/// visible to those entry points' stages.
///
/// Preconditions (programming errors, checked by the tests that create
/// every pipeline): every pass and entry point exists; the passes parse and
/// validate; a binding shared by several entry points has one type in all
/// of them.
pub fn entries(passes: &[Pass], group: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
    entries_for(passes, group, 1)
}

/// [`entries`] of the passes compiled for host targets of `samples`
/// samples per pixel ([`shaders::source_for`]).
pub fn entries_for(passes: &[Pass], group: u32, samples: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut merged: BTreeMap<u32, (wgpu::BindingType, wgpu::ShaderStages, String)> = BTreeMap::new();
    for &(name, entry_points) in passes {
        let reflected = reflect(name, samples > 1);
        let chosen: Vec<&(String, Bindings)> = if entry_points.is_empty() {
            reflected.iter().collect()
        } else {
            entry_points.iter().map(|ep| reflected.iter().find(|(n, _)| n == ep).unwrap_or_else(|| panic!("{name} has no entry point {ep}"))).collect()
        };
        for (ep, bindings) in chosen {
            for (&(g, binding), &(ty, stage)) in bindings {
                if g != group {
                    continue;
                }
                let e = merged.entry(binding).or_insert_with(|| (ty, wgpu::ShaderStages::empty(), format!("{name}::{ep}")));
                assert!(e.0 == ty, "binding {binding} of group {group}: {:?} in {}, {ty:?} in {name}::{ep}", e.0, e.2);
                e.1 |= stage;
            }
        }
    }
    merged.into_iter().map(|(binding, (ty, visibility, _))| wgpu::BindGroupLayoutEntry { binding, visibility, ty, count: None }).collect()
}

/// The bindings of each entry point of pass `name` (compiled for
/// multisampled host targets or not), reflected once per process.
fn reflect(name: &str, multisampled: bool) -> EntryPoints {
    static CACHE: OnceLock<Mutex<HashMap<(String, bool), EntryPoints>>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some(b) = cache.lock().unwrap_or_else(|p| p.into_inner()).get(&(name.to_string(), multisampled)) {
        return b.clone();
    }
    let source = shaders::source_for(name, if multisampled { 4 } else { 1 });
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    let mut reflected = Vec::new();
    for (i, ep) in module.entry_points.iter().enumerate() {
        let stage = match ep.stage {
            naga::ShaderStage::Vertex => wgpu::ShaderStages::VERTEX,
            naga::ShaderStage::Fragment => wgpu::ShaderStages::FRAGMENT,
            naga::ShaderStage::Compute => wgpu::ShaderStages::COMPUTE,
            other => panic!("{name}: unexpected stage {other:?}"),
        };
        let mut bindings = Bindings::new();
        for (handle, var) in module.global_variables.iter() {
            if let Some(rb) = &var.binding {
                if !info.get_entry_point(i)[handle].is_empty() {
                    bindings.insert((rb.group, rb.binding), (binding_type(name, &module, var), stage));
                }
            }
        }
        reflected.push((ep.name.clone(), bindings));
    }
    let reflected = Arc::new(reflected);
    cache.lock().unwrap_or_else(|p| p.into_inner()).insert((name.to_string(), multisampled), reflected.clone());
    reflected
}

/// The layout type of one global: buffers and 2D textures, what the passes
/// declare.
fn binding_type(name: &str, module: &naga::Module, var: &naga::GlobalVariable) -> wgpu::BindingType {
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    match var.space {
        naga::AddressSpace::Uniform => buffer(wgpu::BufferBindingType::Uniform),
        naga::AddressSpace::Storage { access } => buffer(wgpu::BufferBindingType::Storage { read_only: !access.contains(naga::StorageAccess::STORE) }),
        naga::AddressSpace::Handle => match module.types[var.ty].inner {
            naga::TypeInner::Image { dim: naga::ImageDimension::D2, arrayed: false, class } => {
                let (sample_type, multisampled) = match class {
                    naga::ImageClass::Depth { multi } => (wgpu::TextureSampleType::Depth, multi),
                    naga::ImageClass::Sampled { kind: naga::ScalarKind::Uint, multi } => (wgpu::TextureSampleType::Uint, multi),
                    naga::ImageClass::Sampled { kind: naga::ScalarKind::Sint, multi } => (wgpu::TextureSampleType::Sint, multi),
                    naga::ImageClass::Sampled { kind: naga::ScalarKind::Float, multi } => (wgpu::TextureSampleType::Float { filterable: false }, multi),
                    other => panic!("{name}: {:?}: unsupported image class {other:?}", var.name),
                };
                wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled }
            }
            ref other => panic!("{name}: {:?}: unsupported handle {other:?}", var.name),
        },
        other => panic!("{name}: {:?}: unsupported address space {other:?}", var.name),
    }
}
