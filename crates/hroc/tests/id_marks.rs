//! The ID-marks pass (`Marks::Ids`) against its CPU reference: from an
//! object-ID image with every kind of value (background 0, IDs in range,
//! IDs past the marks buffer, which a host's bug could write), the GPU
//! marks exactly the objects whose `index + 1` appears (of those a set
//! holds, when given one), and nothing else.

use hroc::testing::gpu::Gpu;
use hroc::testing::id_marks::IdMarks;

mod common;

/// What the pass must mark: object `i` when some pixel holds `i + 1` and
/// `within` holds `i` (every object without it).
fn cpu_marks(ids: &[u32], objects: usize, within: Option<&[u32]>) -> Vec<u32> {
    let mut marks = vec![0u32; objects];
    for &id in ids {
        if id != 0 && (id as usize) <= objects && within.is_none_or(|w| w[id as usize - 1] != 0) {
            marks[id as usize - 1] = 1;
        }
    }
    marks
}

#[test]
fn id_marks_match_the_cpu_reference() {
    let (device, queue) = common::device(hroc::REQUIRED_FEATURES);
    let gpu = Gpu::from_device(&device, &queue);
    let pass = IdMarks::new(&gpu, 3000);
    // A xorshift: values below `n`.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut below = |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    for (w, h, objects) in [(37u32, 23u32, 50usize), (64, 64, 3000), (1, 1, 1)] {
        let ids: Vec<u32> = (0..w * h)
            .map(|_| match below(4) {
                0 => 0,
                1 => objects as u32 + 1 + below(10) as u32,
                _ => 1 + below(objects as u64 / 2 + 1) as u32,
            })
            .collect();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ids"),
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&ids),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: None },
            texture.size(),
        );
        // Every object, then every third one.
        let third: Vec<u32> = (0..objects as u32).map(|i| (i % 3 == 0) as u32).collect();
        let within = gpu.buffer_init("within", bytemuck::cast_slice(&third), wgpu::BufferUsages::STORAGE);
        for set in [None, Some(&third[..])] {
            let marks = gpu.buffer("marks", objects as u64 * 4, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
            let bound = pass.bind(&gpu, &texture.create_view(&Default::default()), ((w, h), 1), &marks, set.map(|_| &within));
            let mut enc = gpu.encoder("id marks");
            bound.record(&mut enc.begin_compute_pass(&Default::default()));
            queue.submit([enc.finish()]);
            let got: Vec<u32> = gpu.read(&marks, 0, objects as u64).unwrap();
            let want = cpu_marks(&ids, objects, set);
            assert!(want.contains(&1), "the image marks something");
            assert_eq!(got, want, "{w}x{h}, {objects} objects, within {}", set.is_some());
        }
    }
}
