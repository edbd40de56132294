//! What the culler runs with on a device: how it bounds draws by a GPU
//! count, how it learns which objects a draw left visible, and whether it
//! may test boxes against a depth attachment it also samples; and the
//! features and limits a host requests for it.
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

/// How the culler learns which objects of a list the host drew visibly
/// (the methods that read it: `roc`, `ioc` and HROC).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Marks {
    /// The host's fragment shaders are declared `@early_depth_test(force)`
    /// and call `hroc_mark(object)` ([`crate::host::marks_wgsl`]): a mark means a
    /// fragment passed the depth test (`SHADER_EARLY_DEPTH_TEST`: Vulkan,
    /// GL 4.2+). The culler's own box tests mark the same way.
    EarlyZ,
    /// After every occluding list whose marks it reads, the culler reads
    /// the object-ID target ([`crate::ViewTargets::ids`]) and marks the
    /// objects that own a pixel (everywhere wgpu runs; DX12 and Metal have
    /// no forced early-Z). The ID target is then mandatory for those
    /// methods, and the host's shaders need no hroc snippet. The culler's
    /// box tests compare against the depth they load themselves.
    Ids,
    /// After every occluding list whose marks it reads, the culler
    /// rasterizes the boxes of the list's objects against the depth the
    /// list left (under forced early-Z where the device has it, else one
    /// pixel in 4 × 4), and marks those with a fragment at or in front of
    /// it (everywhere wgpu runs). The host's
    /// shaders need no hroc line and, for the marks, no ID target: for
    /// engines whose depth prepass has no fragment stage and whose
    /// materials belong to their users. A box may pass where its object is
    /// hidden, and an object seen only between the pixels tested is not
    /// marked; every method that reads marks takes both (BENCHMARKS.md,
    /// "Marks from boxes", measures C/R and cost against the host's
    /// marks). The culler's own box tests use forced early-Z where the
    /// device has it, else compare against the depth they load. Never
    /// picked by
    /// [`Capabilities::of`]: ask for it in
    /// [`crate::CullerDesc::capabilities`].
    Boxes,
}

/// What the culler runs with: picked from the device
/// ([`Capabilities::of`]), or asked for ([`crate::CullerDesc::capabilities`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Capabilities {
    /// How lists are drawn up to the GPU's count.
    pub draw_count: DrawCount,
    /// How the host's draws mark their objects.
    pub marks: Marks,
    /// A depth attachment may be read-only while the same texture is
    /// sampled (wgpu's `READ_ONLY_DEPTH_STENCIL`: every backend but GL).
    /// With [`Marks::EarlyZ`] the box tests (`roc`, `ioc`, HROC) rasterize
    /// against the attached depth under forced early-Z; HROC's rays sample
    /// that depth too, so without read-only depth HROC attaches its blocks'
    /// occlusion map and loads a copy (with test blocks above one pixel,
    /// [`crate::MethodOptions::hroc_test_scale`]), or else compares
    /// depth itself; and HROC's rounds are refused. With [`Marks::Ids`] the
    /// box tests bind no depth attachment and compare each fragment
    /// against the depth they load, as the attachment's test would.
    pub read_only_depth: bool,
}

impl Capabilities {
    /// Everything: the indirect count, early-Z marks and read-only depth
    /// attachments (Vulkan).
    pub const FULL: Capabilities = Capabilities { draw_count: DrawCount::Indirect, marks: Marks::EarlyZ, read_only_depth: true };
    /// What every backend has: an emulated count, ID marks, no read-only
    /// depth attachments.
    pub const PORTABLE: Capabilities = Capabilities { draw_count: DrawCount::Emulated, marks: Marks::Ids, read_only_depth: false };

    /// The most that `device` allows.
    pub fn of(device: &wgpu::Device) -> Capabilities {
        let features = device.features();
        Capabilities {
            draw_count: if features.contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT) { DrawCount::Indirect } else { DrawCount::Emulated },
            marks: if features.contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST) { Marks::EarlyZ } else { Marks::Ids },
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
        if self.marks == Marks::EarlyZ {
            f |= wgpu::Features::SHADER_EARLY_DEPTH_TEST;
        }
        f
    }

    /// True when the culler's box tests rasterize against the attached
    /// depth under forced early-Z; false when they load it and compare.
    /// Tests that also sample the depth they are attached to (HROC's rays)
    /// need read-only depth attachments besides; the others (`roc`, `ioc`)
    /// only early-Z. Early-Z is there with early-Z marks, and with marks
    /// from boxes where `device` has it (the host's shaders do not use it,
    /// the culler's may).
    pub(crate) fn attached_box_tests(self, device: &wgpu::Device, samples_depth: bool) -> bool {
        let early_z = match self.marks {
            Marks::EarlyZ => true,
            Marks::Boxes => device.features().contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST),
            Marks::Ids => false,
        };
        early_z && (self.read_only_depth || !samples_depth)
    }
}

/// The device features every culler needs: object `i` is drawn with
/// `first_instance = i` from an indirect command. GLES and WebGL lack it.
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::INDIRECT_FIRST_INSTANCE;

/// The features of [`Capabilities::FULL`].
pub const FULL_FEATURES: wgpu::Features = REQUIRED_FEATURES.union(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT).union(wgpu::Features::SHADER_EARLY_DEPTH_TEST);

/// The features to request from `adapter` for a culler: [`FULL_FEATURES`]
/// where the adapter has them, else the most it has, and `TIMESTAMP_QUERY`
/// where it has it (`auto` times its frames with it); always
/// [`REQUIRED_FEATURES`] (the device request fails without them).
pub fn features(adapter: &wgpu::Adapter) -> wgpu::Features {
    (adapter.features() & (FULL_FEATURES | wgpu::Features::TIMESTAMP_QUERY)) | REQUIRED_FEATURES
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
