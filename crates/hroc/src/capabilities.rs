//! What the culler runs with on a device: how it bounds draws by a GPU
//! count, and whether fragment shaders can force early depth tests; and
//! the features and limits a host requests for it.
//!
//! In wgpu 30, `MULTI_DRAW_INDIRECT_COUNT` exists on Vulkan and DX12;
//! `SHADER_EARLY_DEPTH_TEST` on Vulkan and GL 4.2+ (naga's MSL and HLSL
//! back ends emit no early fragment tests); `INDIRECT_FIRST_INSTANCE` on
//! Vulkan, DX12, Metal and desktop GL 4.2+, not on GLES or WebGL.

/// How a list is drawn up to the count the GPU computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DrawCount {
    /// `multi_draw_indexed_indirect_count` reads the count
    /// (`MULTI_DRAW_INDIRECT_COUNT`: Vulkan, DX12).
    Indirect,
    /// `multi_draw_indexed_indirect` draws the list's bound, `max_count`
    /// commands; the culler gives the commands past the GPU's count
    /// `instance_count` 0 before each draw (everywhere wgpu runs; GL and
    /// Metal loop one driver call per command).
    Emulated,
}

/// What the culler runs with: picked from the device
/// ([`Capabilities::of`]), or asked for ([`crate::CullerDesc::capabilities`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Capabilities {
    /// How lists are drawn up to the GPU's count.
    pub draw_count: DrawCount,
    /// Fragment shaders may force early depth tests
    /// (`SHADER_EARLY_DEPTH_TEST`): what visibility marks need, the
    /// host's `hroc_mark` and the culler's own box tests. Without it, the
    /// methods that read marks (`roc` and HROC) are refused.
    pub early_z: bool,
    /// A depth attachment may be read-only while the same texture is
    /// sampled (wgpu's `READ_ONLY_DEPTH_STENCIL`: every backend but GL).
    /// Without it, HROC's occlusion test binds no depth attachment and
    /// compares each box fragment against the depth it loads, as the
    /// attachment's test would.
    pub read_only_depth: bool,
}

impl Capabilities {
    /// Everything: the indirect count and forced early-Z (Vulkan).
    pub const FULL: Capabilities = Capabilities { draw_count: DrawCount::Indirect, early_z: true, read_only_depth: true };
    /// What every backend has: an emulated count, no forced early-Z, no
    /// read-only depth attachments.
    pub const PORTABLE: Capabilities = Capabilities { draw_count: DrawCount::Emulated, early_z: false, read_only_depth: false };

    /// The most that `device` allows.
    pub fn of(device: &wgpu::Device) -> Capabilities {
        let features = device.features();
        Capabilities {
            draw_count: if features.contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT) { DrawCount::Indirect } else { DrawCount::Emulated },
            early_z: features.contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST),
            // wgpu: "The WebGL2 and GLES backends do not support RODS".
            read_only_depth: device.adapter_info().backend != wgpu::Backend::Gl,
        }
    }

    /// The device features these capabilities need.
    pub fn features(self) -> wgpu::Features {
        let mut f = REQUIRED_FEATURES;
        if self.draw_count == DrawCount::Indirect {
            f |= wgpu::Features::MULTI_DRAW_INDIRECT_COUNT;
        }
        if self.early_z {
            f |= wgpu::Features::SHADER_EARLY_DEPTH_TEST;
        }
        f
    }
}

/// The device features every culler needs: object `i` is drawn with
/// `first_instance = i` from an indirect command. GLES and WebGL lack it.
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::INDIRECT_FIRST_INSTANCE;

/// The features of [`Capabilities::FULL`].
pub const FULL_FEATURES: wgpu::Features = REQUIRED_FEATURES.union(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT).union(wgpu::Features::SHADER_EARLY_DEPTH_TEST);

/// The features to request from `adapter` for a culler: [`FULL_FEATURES`]
/// where the adapter has them, else the most it has; always
/// [`REQUIRED_FEATURES`] (the device request fails without them).
pub fn features(adapter: &wgpu::Adapter) -> wgpu::Features {
    (adapter.features() & FULL_FEATURES) | REQUIRED_FEATURES
}

/// The limits to request from `adapter` for a culler: wgpu's defaults,
/// with the storage buffers per stage, buffer sizes and bind groups the
/// adapter allows (scenes as large as it can hold); the adapter's own
/// limits where its limits are below wgpu's defaults (downlevel devices).
/// The culler checks what each method needs when it is asked for one.
pub fn limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    let a = adapter.limits();
    let wanted = wgpu::Limits {
        max_storage_buffers_per_shader_stage: a.max_storage_buffers_per_shader_stage,
        max_storage_buffer_binding_size: a.max_storage_buffer_binding_size,
        max_buffer_size: a.max_buffer_size,
        max_bind_groups: a.max_bind_groups,
        ..wgpu::Limits::default()
    };
    if wanted.check_limits(&a) {
        wanted
    } else {
        a
    }
}
