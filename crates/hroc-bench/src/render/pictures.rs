//! Pictures of a frame: colour, object IDs, overdraw heat map.

use crate::error::{Error, Result};
use crate::gpu::Headless;
use crate::render::{DrawList, Renderer};
use std::path::Path;

/// Which picture of a frame to show or save.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Picture {
    Color,
    Overdraw,
    Id,
    /// Colour, with the boxes the method tested drawn over it (Lee's thesis, Figures 2 and 9).
    Groups,
}

impl std::str::FromStr for Picture {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Picture, String> {
        Ok(match s {
            "color" => Picture::Color,
            "overdraw" => Picture::Overdraw,
            "id" => Picture::Id,
            "groups" => Picture::Groups,
            _ => return Err(format!("unknown picture '{s}' (expected color, overdraw, id or groups)")),
        })
    }
}

impl std::fmt::Display for Picture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Picture::Color => "color",
            Picture::Overdraw => "overdraw",
            Picture::Id => "id",
            Picture::Groups => "groups",
        })
    }
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
pub fn capture(gpu: &Headless, r: &Renderer, view: Picture, lists: &[DrawList]) -> Result<Vec<[u8; 4]>> {
    Ok(match view {
        Picture::Color => gpu.read_texture(&r.targets.color, wgpu::TextureAspect::All)?,
        Picture::Id => gpu.read_texture::<u32>(&r.targets.id, wgpu::TextureAspect::All)?.into_iter().map(id_color).collect(),
        Picture::Overdraw => r.overdraw(gpu, lists)?.into_iter().map(heat).collect(),
        Picture::Groups => return Err(Error::Options("the groups view needs the tested boxes: use draw_boxes".into())),
    })
}

pub fn save_png(path: &Path, width: u32, height: u32, pixels: &[[u8; 4]]) -> Result<()> {
    let img = image::RgbaImage::from_raw(width, height, bytemuck::cast_slice(pixels).to_vec()).ok_or_else(|| Error::Options("image size mismatch".into()))?;
    img.save(path).map_err(|e| Error::Write { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}

/// Draws the 12 edges of each box over `pixels` (clipped at the near plane).
pub fn draw_boxes(pixels: &mut [[u8; 4]], (w, h): (u32, u32), view_proj: &glam::Mat4, boxes: &[(crate::scene::Aabb, [u8; 4])]) {
    use glam::{Vec3, Vec4};
    const EDGES: [(usize, usize); 12] = [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
    for (b, color) in boxes {
        let corner = |c: usize| Vec3::new(if c & 1 != 0 { b.max.x } else { b.min.x }, if c & 2 != 0 { b.max.y } else { b.min.y }, if c & 4 != 0 { b.max.z } else { b.min.z });
        for (i, j) in EDGES {
            let (mut a, mut c) = (*view_proj * corner(i).extend(1.0), *view_proj * corner(j).extend(1.0));
            // Clip to z >= 0 (in front of the near plane).
            if a.z < 0.0 && c.z < 0.0 {
                continue;
            }
            let cut = |p: Vec4, q: Vec4| p + (q - p) * (p.z / (p.z - q.z));
            if a.z < 0.0 {
                a = cut(a, c);
            } else if c.z < 0.0 {
                c = cut(c, a);
            }
            let screen = |p: Vec4| ((p.x / p.w * 0.5 + 0.5) * w as f32, (0.5 - p.y / p.w * 0.5) * h as f32);
            let ((x0, y0), (x1, y1)) = (screen(a), screen(c));
            let steps = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as usize).clamp(1, 4 * (w + h) as usize);
            for s in 0..=steps {
                let t = s as f32 / steps as f32;
                let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
                if x >= 0.0 && y >= 0.0 && (x as u32) < w && (y as u32) < h {
                    pixels[(y as u32 * w + x as u32) as usize] = *color;
                }
            }
        }
    }
}
