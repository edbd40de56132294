//! Bind-group layouts derived from the WGSL: naga's reflection of each
//! pass gives every binding of a group its type (uniform, storage read or
//! read-write, texture kind) and the stages whose entry points use it, so
//! no layout is typed beside the shader it describes.

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

/// The bind-group layout of `group` that `passes` declare: one entry per
/// binding any of their entry points uses, visible to those entry points'
/// stages.
///
/// Preconditions (programming errors, checked by the tests that create
/// every pipeline): every pass and entry point exists; the passes parse and
/// validate; a binding shared by several entry points has one type in all
/// of them.
pub fn layout(gpu: &Gpu, label: &str, passes: &[Pass], group: u32) -> wgpu::BindGroupLayout {
    let entries = entries(passes, group);
    gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries })
}

/// A pipeline layout of one bind group, [`layout`]'s.
pub fn pipeline_layout(gpu: &Gpu, label: &str, layout: &wgpu::BindGroupLayout) -> wgpu::PipelineLayout {
    gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some(label), bind_group_layouts: &[Some(layout)], immediate_size: 0 })
}

/// [`layout`]'s entries, in binding order.
pub fn entries(passes: &[Pass], group: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut merged: BTreeMap<u32, (wgpu::BindingType, wgpu::ShaderStages, String)> = BTreeMap::new();
    for &(name, entry_points) in passes {
        let reflected = reflect(name);
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

/// The bindings of each entry point of pass `name`, reflected once per
/// process.
fn reflect(name: &str) -> EntryPoints {
    static CACHE: OnceLock<Mutex<HashMap<String, EntryPoints>>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some(b) = cache.lock().unwrap_or_else(|p| p.into_inner()).get(name) {
        return b.clone();
    }
    let source = shaders::source(name);
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
    cache.lock().unwrap_or_else(|p| p.into_inner()).insert(name.to_string(), reflected.clone());
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
