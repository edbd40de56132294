//! Shader modules, layouts and pipelines made once per culler and shared
//! by its views.
//!
//! Every view's method builds the same few dozen pipelines from the same
//! WGSL, layouts and constants. Made per view, a light's views cost an
//! engine the compile of each of them whenever one is made or retargeted
//! (a point light's six faces, each time the engine reallocates its
//! shadow maps): on lavapipe, which compiles each pipeline with LLVM,
//! that was three fifths of a frame with four point lights. Here each is
//! made the first time it is asked for and handed out again after, keyed
//! by what makes it: a module by its label and source, a bind-group
//! layout by its entries, a pipeline by its module, entry points,
//! layout, constants and fixed-function state. A cached module, layout
//! or pipeline is the same object, so layouts made from equal entries
//! are one and bind groups of one view's pipeline bind the next's.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Override constants as a key: names and bits.
pub type Constants = Vec<(String, u64)>;

/// What makes a compute pipeline.
#[derive(PartialEq, Eq, Hash)]
struct ComputeKey {
    module: wgpu::ShaderModule,
    entry: String,
    layout: Option<wgpu::PipelineLayout>,
    constants: Constants,
}

/// What makes one of the culler's render pipelines (every one draws
/// without vertex buffers, in one primitive state per label).
#[derive(PartialEq, Eq, Hash)]
pub struct RenderKey {
    /// The pipeline's label.
    pub label: String,
    /// Its layout.
    pub layout: wgpu::PipelineLayout,
    /// The module of both its stages.
    pub module: wgpu::ShaderModule,
    /// Vertex and fragment entry points.
    pub entries: (String, Option<String>),
    /// Override constants ([`constants_key`]).
    pub constants: Constants,
    /// The depth attachment's format, test, constant bias and writes.
    pub depth: Option<(wgpu::TextureFormat, wgpu::CompareFunction, i32, bool)>,
    /// Samples per pixel.
    pub samples: u32,
    /// Color targets' formats.
    pub targets: Vec<wgpu::TextureFormat>,
}

#[derive(Default)]
struct Maps {
    modules: HashMap<(String, String), wgpu::ShaderModule>,
    bind_layouts: HashMap<(String, Vec<wgpu::BindGroupLayoutEntry>), wgpu::BindGroupLayout>,
    pipeline_layouts: HashMap<(String, wgpu::BindGroupLayout), wgpu::PipelineLayout>,
    compute: HashMap<ComputeKey, wgpu::ComputePipeline>,
    render: HashMap<RenderKey, wgpu::RenderPipeline>,
}

/// The culler's objects made once (cheap clones share them).
#[derive(Clone, Default)]
pub struct Cache(Arc<Mutex<Maps>>);

impl std::fmt::Debug for Cache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let m = self.maps();
        f.debug_struct("Cache").field("modules", &m.modules.len()).field("compute", &m.compute.len()).field("render", &m.render.len()).finish()
    }
}

/// `constants` as a key.
pub fn constants_key(constants: &[(&str, f64)]) -> Constants {
    constants.iter().map(|&(n, v)| (n.to_owned(), v.to_bits())).collect()
}

impl Cache {
    fn maps(&self) -> std::sync::MutexGuard<'_, Maps> {
        // (A panic while the lock was held left whole entries or none.)
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The module of `label` and `source`, made by `make` the first time.
    pub fn module(&self, label: &str, source: &str, make: impl FnOnce() -> wgpu::ShaderModule) -> wgpu::ShaderModule {
        let key = (label.to_owned(), source.to_owned());
        if let Some(m) = self.maps().modules.get(&key) {
            return m.clone();
        }
        let m = make();
        self.maps().modules.entry(key).or_insert(m).clone()
    }

    /// The bind-group layout of `label` and `entries`.
    pub fn bind_layout(&self, label: &str, entries: &[wgpu::BindGroupLayoutEntry], make: impl FnOnce() -> wgpu::BindGroupLayout) -> wgpu::BindGroupLayout {
        let key = (label.to_owned(), entries.to_vec());
        if let Some(l) = self.maps().bind_layouts.get(&key) {
            return l.clone();
        }
        let l = make();
        self.maps().bind_layouts.entry(key).or_insert(l).clone()
    }

    /// The pipeline layout of `label` holding `layout` alone.
    pub fn pipeline_layout(&self, label: &str, layout: &wgpu::BindGroupLayout, make: impl FnOnce() -> wgpu::PipelineLayout) -> wgpu::PipelineLayout {
        let key = (label.to_owned(), layout.clone());
        if let Some(l) = self.maps().pipeline_layouts.get(&key) {
            return l.clone();
        }
        let l = make();
        self.maps().pipeline_layouts.entry(key).or_insert(l).clone()
    }

    /// The compute pipeline of `module` at `entry` with `layout` and `constants`.
    pub fn compute(
        &self,
        module: &wgpu::ShaderModule,
        entry: &str,
        layout: Option<&wgpu::PipelineLayout>,
        constants: &[(&str, f64)],
        make: impl FnOnce() -> wgpu::ComputePipeline,
    ) -> wgpu::ComputePipeline {
        let key = ComputeKey { module: module.clone(), entry: entry.to_owned(), layout: layout.cloned(), constants: constants_key(constants) };
        if let Some(p) = self.maps().compute.get(&key) {
            return p.clone();
        }
        let p = make();
        self.maps().compute.entry(key).or_insert(p).clone()
    }

    /// The render pipeline `key` names.
    pub fn render(&self, key: RenderKey, make: impl FnOnce() -> wgpu::RenderPipeline) -> wgpu::RenderPipeline {
        if let Some(p) = self.maps().render.get(&key) {
            return p.clone();
        }
        let p = make();
        self.maps().render.entry(key).or_insert(p).clone()
    }

    /// Modules, compute and render pipelines made so far.
    pub fn counts(&self) -> (usize, usize, usize) {
        let m = self.maps();
        (m.modules.len(), m.compute.len(), m.render.len())
    }
}
