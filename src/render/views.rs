//! Pictures of a frame: colour, object IDs, overdraw heat map.

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::{DrawList, Renderer};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum View {
    Color,
    Overdraw,
    Id,
}

/// A distinct colour per object id (0 = background stays black).
fn id_color(id: u32) -> [u8; 4] {
    if id == 0 {
        return [0, 0, 0, 255];
    }
    let h = id.wrapping_mul(0x9E37_79B1).rotate_left(13).wrapping_mul(0x85EB_CA77);
    [(h >> 24) as u8 | 0x30, (h >> 16) as u8 | 0x30, (h >> 8) as u8 | 0x30, 255]
}

/// Black → blue → green → yellow → red → white as overdraw grows 0 → 8+.
pub fn heat(v: f32) -> [u8; 4] {
    const RAMP: [[f32; 3]; 6] = [[0.0, 0.0, 0.0], [0.0, 0.2, 1.0], [0.0, 0.9, 0.3], [1.0, 0.9, 0.0], [1.0, 0.1, 0.0], [1.0, 1.0, 1.0]];
    let x = (v / 8.0).clamp(0.0, 1.0) * (RAMP.len() - 1) as f32;
    let i = (x.floor() as usize).min(RAMP.len() - 2);
    let t = x - i as f32;
    let c: Vec<u8> = (0..3).map(|k| ((RAMP[i][k] * (1.0 - t) + RAMP[i + 1][k] * t) * 255.0) as u8).collect();
    [c[0], c[1], c[2], 255]
}

/// RGBA8 pixels of `view` for what the renderer's targets hold now;
/// `lists` are the frame's draw lists (for the overdraw view).
pub fn capture(gpu: &Gpu, r: &Renderer, view: View, lists: &[DrawList]) -> Result<Vec<[u8; 4]>> {
    Ok(match view {
        View::Color => gpu.read_texture(&r.targets.color, wgpu::TextureAspect::All)?,
        View::Id => gpu.read_texture::<u32>(&r.targets.id, wgpu::TextureAspect::All)?.into_iter().map(id_color).collect(),
        View::Overdraw => r.overdraw(gpu, lists)?.into_iter().map(heat).collect(),
    })
}

pub fn save_png(path: &Path, width: u32, height: u32, pixels: &[[u8; 4]]) -> Result<()> {
    let img = image::RgbaImage::from_raw(width, height, bytemuck::cast_slice(pixels).to_vec()).ok_or_else(|| Error::Arg("image size mismatch".into()))?;
    img.save(path).map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}
