//! What the core crate's GPU tests share: a Vulkan device (lavapipe in CI)
//! and a depth target the culler can sample.

/// A device on the first Vulkan adapter, with `features` and the adapter's
/// own limits.
pub fn device(features: wgpu::Features) -> (wgpu::Device, wgpu::Queue) {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(async {
        let adapter = instance.request_adapter(&wgpu::RequestAdapterOptions::default()).await.expect("a Vulkan adapter: install lavapipe (scripts/ensure-vulkan.sh)");
        let desc = wgpu::DeviceDescriptor { required_features: features, required_limits: adapter.limits(), ..Default::default() };
        adapter.request_device(&desc).await.expect("a device with the features asked for")
    })
}

/// A `Depth32Float` target of `size` × `size`, drawn into and sampled.
pub fn depth_texture(device: &wgpu::Device, size: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth"),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}
