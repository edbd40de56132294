//! A headless Vulkan device with the features hroc needs, for the benchmark,
//! the CLI, the viewer and the tests: the "host" side opens its own device,
//! as any renderer would, and hands it to [`hroc::Culler`].

use crate::error::{Error, Result};

/// What the benchmark needs of a device: what every culler needs, and GPU
/// timestamps. It also asks for the rest of [`hroc::device::FULL_FEATURES`] and for
/// pipeline statistics where the adapter has them.
pub const FEATURES: wgpu::Features = hroc::device::REQUIRED_FEATURES.union(hroc::device::TIMESTAMP_FEATURES).union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// The graphics API a headless device runs on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Vulkan (lavapipe where there is no GPU).
    #[default]
    Vulkan,
    /// OpenGL through EGL, without a display (llvmpipe where there is no GPU).
    Gl,
}

impl Backend {
    /// The wgpu backend set of this one backend.
    pub fn wgpu(self) -> wgpu::Backends {
        match self {
            Backend::Vulkan => wgpu::Backends::VULKAN,
            Backend::Gl => wgpu::Backends::GL,
        }
    }

    fn hint(self) -> &'static str {
        match self {
            Backend::Vulkan => LAVAPIPE_HINT,
            Backend::Gl => LLVMPIPE_HINT,
        }
    }
}

impl std::str::FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Backend, String> {
        match s {
            "vulkan" => Ok(Backend::Vulkan),
            "gl" => Ok(Backend::Gl),
            _ => Err(format!("unknown backend '{s}' (expected vulkan or gl)")),
        }
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Backend::Vulkan => "vulkan",
            Backend::Gl => "gl",
        })
    }
}

/// What the culler runs with (`--tier`): a preset of [`hroc::device::Capabilities`],
/// or what wgpu 30 gives a backend, asked for on any device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tier {
    /// [`hroc::device::Capabilities::FULL`]: the indirect draw count, early-Z marks
    /// and read-only depth attachments (Vulkan).
    Full,
    /// What GL has: an emulated count, early-Z marks, no read-only depth
    /// attachments (box tests load depth).
    Gl,
    /// What DX12 has: the indirect count, ID marks (no forced early-Z),
    /// read-only depth attachments.
    Dx12,
    /// [`hroc::device::Capabilities::PORTABLE`]: what every backend has; for every
    /// method and option, what Metal runs (an emulated count, ID marks).
    Portable,
    /// An engine's: the full device, marks from boxes
    /// ([`hroc::device::Marks::Boxes`]: the host's shaders do not mark).
    Boxes,
}

impl Tier {
    /// Every tier, in `--tier` order.
    pub const ALL: [Tier; 5] = [Tier::Full, Tier::Gl, Tier::Dx12, Tier::Portable, Tier::Boxes];

    /// The capabilities of the tier.
    pub fn capabilities(self) -> hroc::device::Capabilities {
        use hroc::device::{Capabilities, DrawCount, Marks};
        match self {
            Tier::Full => Capabilities::FULL,
            Tier::Gl => Capabilities { draw_count: DrawCount::Emulated, marks: Marks::EarlyZ, read_only_depth: false },
            Tier::Dx12 => Capabilities { draw_count: DrawCount::Indirect, marks: Marks::Ids, read_only_depth: true },
            Tier::Portable => Capabilities::PORTABLE,
            Tier::Boxes => Capabilities { marks: Marks::Boxes, ..Capabilities::FULL },
        }
    }

    /// The tier's name.
    pub fn name(self) -> &'static str {
        match self {
            Tier::Full => "full",
            Tier::Gl => "gl",
            Tier::Dx12 => "dx12",
            Tier::Portable => "portable",
            Tier::Boxes => "boxes",
        }
    }
}

impl std::str::FromStr for Tier {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Tier, String> {
        Tier::ALL.into_iter().find(|t| t.name() == s).ok_or_else(|| format!("unknown tier '{s}' (expected full, gl, dx12, portable or boxes)"))
    }
}

impl std::fmt::Display for Tier {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How to get OpenGL on a machine without a display.
pub const LLVMPIPE_HINT: &str = "install Mesa's EGL and GL drivers (llvmpipe): sudo apt-get install -y libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri";

/// How to get a Vulkan device on a machine without a GPU.
pub const LAVAPIPE_HINT: &str = "install the Vulkan software driver (lavapipe): sudo apt-get install -y mesa-vulkan-drivers libvulkan1";

mod helpers;

/// An opened adapter and its device and queue, with the helpers the bench
/// records and reads back with (`helpers.rs`).
pub struct Headless {
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
    /// Its name, type and driver.
    pub info: wgpu::AdapterInfo,
    /// What the cullers made on this device run with: `None`, the most it
    /// allows (`--tier`).
    pub capabilities: Option<hroc::device::Capabilities>,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The first error the device reported, kept for [`Headless::check`].
    errors: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

fn rank(t: wgpu::DeviceType) -> u32 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

impl Headless {
    /// Opens the best Vulkan adapter that has every needed feature:
    /// a discrete GPU over an integrated one over a CPU device.
    pub fn new() -> Result<Headless> {
        Self::open(Backend::Vulkan)
    }

    /// As [`Headless::new`], on `backend`.
    pub fn open(backend: Backend) -> Result<Headless> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backend.wgpu();
        pollster::block_on(Self::new_async(&wgpu::Instance::new(desc), backend))
    }

    /// As [`Headless::new`], on the adapters of `instance`: a window's surface
    /// can only present what a device of its own instance renders (the viewer).
    pub fn with_instance(instance: &wgpu::Instance, backend: Backend) -> Result<Headless> {
        pollster::block_on(Self::new_async(instance, backend))
    }

    async fn new_async(instance: &wgpu::Instance, backend: Backend) -> Result<Headless> {
        let hint = backend.hint();
        let adapters = instance.enumerate_adapters(backend.wgpu()).await;
        if adapters.is_empty() {
            return Err(Error::NoAdapter(format!("no {backend} adapter found; {hint}")));
        }
        let mut names = Vec::new();
        let mut best: Option<wgpu::Adapter> = None;
        for a in adapters {
            let info = a.get_info();
            let missing = FEATURES - a.features();
            if !missing.is_empty() {
                names.push(format!("{} (lacks {missing:?})", info.name));
                continue;
            }
            if best.as_ref().is_none_or(|b| rank(info.device_type) < rank(b.get_info().device_type)) {
                best = Some(a);
            }
        }
        let Some(adapter) = best else {
            return Err(Error::NoAdapter(format!("no suitable {backend} adapter: {}; {hint}", names.join(", "))));
        };
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("hroc"),
                // The culler's full capabilities and pipeline statistics
                // (`--breakdown`'s counts) where the adapter has them.
                required_features: FEATURES | hroc::device::features(&adapter) | (adapter.features() & hroc::device::PIPELINE_STATISTICS_FEATURES),
                // The adapter's own limits: large scenes need large buffers.
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| Error::Device(format!("cannot open {}: {e}", info.name)))?;
        let gpu = Headless { adapter, info, capabilities: None, device, queue, errors: Default::default() };
        gpu.capture_errors();
        Ok(gpu)
    }

    /// Adapter name, type and driver, for tables and reports.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?}, {:?}, {})", self.info.name, self.info.device_type, self.info.backend, self.info.driver_info)
    }
}
