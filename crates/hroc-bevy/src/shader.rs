//! The preprocessing shaders: Bevy's own `mesh_preprocess.wesl`, taken
//! from its asset at run time (not copied here), with its Hi-Z test
//! replaced by a read of hroc's visibility. Everything else Bevy's shader
//! does (frustum and visibility-range culling, previous transforms, the
//! late work list, the output slots) stays as Bevy wrote it.

use bevy_asset::{AssetServer, Assets, Handle};
use bevy_ecs::prelude::*;
use bevy_shader::{Shader, Source};

/// Where Bevy's mesh preprocessing shader lives.
const BEVY_PREPROCESS: &str = "embedded://bevy_pbr/render/mesh_preprocess.wesl";

/// The line of Bevy's shader that decides an instance is occluded.
const OCCLUSION_TEST: &str = "if (max_depth_ndc < occluder_depth_ndc) {";
/// The line after which the shader's bindings end.
const LAST_BINDING: &str = "var<immediate> immediates: Immediates;";

/// hroc's bindings and test, added to Bevy's shader. An instance whose
/// object hroc does not know yet (spawned this frame) is drawn early.
fn hroc_lines(early: bool) -> String {
    format!(
        "\n// hroc (crates/hroc-bevy): the occlusion test reads hroc's visibility.\n\
         @group(1) @binding(0) var<storage> hroc_visibility: array<u32>;\n\
         @group(1) @binding(1) var<storage> hroc_slot_of_input: array<u32>;\n\
         const HROC_EARLY: bool = {early};\n\
         fn hroc_draws(input_index: u32) -> bool {{\n\
         \x20   var slot = 0xffffffffu;\n\
         \x20   if (input_index < arrayLength(&hroc_slot_of_input)) {{ slot = hroc_slot_of_input[input_index]; }}\n\
         \x20   if (slot == 0xffffffffu || {header}u + slot >= arrayLength(&hroc_visibility)) {{ return HROC_EARLY; }}\n\
         \x20   let s = hroc_visibility[{header}u + slot];\n\
         \x20   if (HROC_EARLY) {{ return s == hroc_visibility[0] || s == hroc_visibility[1] || s == hroc_visibility[2]; }}\n\
         \x20   return s == hroc_visibility[3];\n\
         }}\n",
        header = hroc::device::VISIBILITY_HEADER,
    )
}

/// Bevy's shader `source` with hroc's test in place of its Hi-Z test, for
/// the early or the late phase; `None` when the shader is not the one this
/// was written against (Bevy 0.20.1).
pub fn patch(source: &str, early: bool) -> Option<String> {
    if source.matches(OCCLUSION_TEST).count() != 1 || source.matches(LAST_BINDING).count() != 1 {
        return None;
    }
    let source = source.replace(LAST_BINDING, &format!("{LAST_BINDING}\n{}", hroc_lines(early)));
    let source = source.replace(OCCLUSION_TEST, "if (!hroc_draws(input_index)) {");
    // Our shader is not in Bevy's package: name it.
    Some(source.replace("package::", "bevy_pbr::"))
}

/// The two patched shaders, once Bevy's has loaded.
#[derive(Resource, Clone, Default)]
pub struct HrocShaders {
    /// Bevy's shader, kept loaded.
    pub bevy: Option<Handle<Shader>>,
    pub early: Option<Handle<Shader>>,
    pub late: Option<Handle<Shader>>,
    /// Bevy's shader did not have the lines patched (another Bevy version).
    pub unpatchable: bool,
}

/// Main world: loads Bevy's shader by its path and, once it is there,
/// adds the early and late patched shaders.
pub fn make_shaders(mut shaders: ResMut<HrocShaders>, server: Res<AssetServer>, mut assets: ResMut<Assets<Shader>>) {
    if shaders.early.is_some() || shaders.unpatchable {
        return;
    }
    let bevy = shaders.bevy.get_or_insert_with(|| server.load(BEVY_PREPROCESS)).clone();
    let Some(source) = assets.get(&bevy).and_then(|s| match &s.source {
        Source::Wesl(text) | Source::Wgsl(text) => Some(text.to_string()),
        Source::SpirV(_) => None,
    }) else {
        return;
    };
    match (patch(&source, true), patch(&source, false)) {
        (Some(early), Some(late)) => {
            shaders.early = Some(assets.add(Shader::from_wesl(early, "embedded://hroc_bevy/preprocess_early.wesl")));
            shaders.late = Some(assets.add(Shader::from_wesl(late, "embedded://hroc_bevy/preprocess_late.wesl")));
        }
        _ => {
            bevy_log::error!("hroc-bevy: Bevy's mesh_preprocess.wesl is not the one of Bevy 0.20.1; culling falls back to Bevy's");
            shaders.unpatchable = true;
        }
    }
}

impl bevy_render::extract_resource::ExtractResource<bevy_render::RenderApp> for HrocShaders {
    type Source = HrocShaders;

    fn extract_resource(source: &HrocShaders) -> HrocShaders {
        source.clone()
    }
}
