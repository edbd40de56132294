//! A headless Vulkan device with the features hroc needs, for the benchmark,
//! the CLI, the viewer and the tests: the "host" side opens its own device,
//! as any renderer would, and hands it to [`hroc::Culler`].

use std::ops::Deref;

use crate::error::{Error, Result};

/// What the benchmark asks of a device: the culler's features and GPU timestamps.
pub const FEATURES: wgpu::Features = hroc::REQUIRED_FEATURES.union(hroc::TIMESTAMP_FEATURES).union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// How to get a Vulkan device on a machine without a GPU.
pub const LAVAPIPE_HINT: &str = "install the Vulkan software driver (lavapipe): sudo apt-get install -y mesa-vulkan-drivers libvulkan1";

/// An opened adapter and device; derefs to [`hroc::testing::gpu::Gpu`]'s helpers.
pub struct Headless {
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
    /// Its name, type and driver.
    pub info: wgpu::AdapterInfo,
    base: hroc::testing::gpu::Gpu,
}

impl Deref for Headless {
    type Target = hroc::testing::gpu::Gpu;
    fn deref(&self) -> &hroc::testing::gpu::Gpu {
        &self.base
    }
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
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = wgpu::Backends::VULKAN;
        Self::with_instance(&wgpu::Instance::new(desc))
    }

    /// As [`Headless::new`], on the adapters of `instance`: a window's surface
    /// can only present what a device of its own instance renders (the viewer).
    pub fn with_instance(instance: &wgpu::Instance) -> Result<Headless> {
        pollster::block_on(Self::new_async(instance))
    }

    async fn new_async(instance: &wgpu::Instance) -> Result<Headless> {
        let adapters = instance.enumerate_adapters(wgpu::Backends::VULKAN).await;
        if adapters.is_empty() {
            return Err(Error::NoAdapter(format!("no Vulkan adapter found; {LAVAPIPE_HINT}")));
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
            return Err(Error::NoAdapter(format!("no suitable Vulkan adapter: {}; {LAVAPIPE_HINT}", names.join(", "))));
        };
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("hroc"),
                // Pipeline statistics where the adapter has them (`--breakdown`'s counts).
                required_features: FEATURES | (adapter.features() & hroc::PIPELINE_STATISTICS_FEATURES),
                // The adapter's own limits: large scenes need large buffers.
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| Error::Gpu(format!("cannot open {}: {e}", info.name)))?;
        let base = hroc::testing::gpu::Gpu::from_device(&device, &queue);
        base.capture_errors();
        Ok(Headless { adapter, info, base })
    }

    /// Adapter name, type and driver, for tables and reports.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?}, {})", self.info.name, self.info.device_type, self.info.driver_info)
    }
}
