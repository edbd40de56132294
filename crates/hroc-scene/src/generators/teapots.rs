//! `teapots`: randomly placed, randomly turned teapots filling a volume (the
//! statistical occlusion-query paper's third scene). The path flies through
//! the volume; nearer teapots hide most of the farther ones.

use glam::{Mat4, Quat, Vec3};
use std::f32::consts::TAU;

use super::rng::hsv;
use super::shapes::teapot;
use super::{flight, walk_path, Builder, Clearance};
use crate::CameraPath;

const CELL: f32 = 2.4;

pub(super) fn build(b: &mut Builder) -> CameraPath {
    // A slab three times wider than high: long horizontal sight lines.
    let g = (((b.n as f32 * 1.12) * 3.0).cbrt().ceil() as usize).max(3);
    let gy = (g / 3).max(2);
    let half = Vec3::new(g as f32, gy as f32, g as f32) * CELL * 0.5;
    let pts = flight(&mut b.rng, half, 21);
    let path = walk_path(pts, 8.0, 25);
    let clear = Clearance::new(&[&path], 2.0, 2.0, 2.0);

    let meshes = [b.mesh("teapot-12", teapot(12)), b.mesh("teapot-8", teapot(8))];
    let mut cells: Vec<u32> = (0..(g * gy * g) as u32).collect();
    b.rng.shuffle(&mut cells);
    let mut next = 0usize;
    while b.left() > 0 {
        let (c, round) = (cells[next % cells.len()] as usize, next / cells.len());
        next += 1;
        let cell = Vec3::new((c % g) as f32, (c / g % gy) as f32, (c / (g * gy)) as f32);
        let pos = -half + (cell + Vec3::splat(0.5) + Vec3::new(b.rng.range(-0.25, 0.25), b.rng.range(-0.25, 0.25), b.rng.range(-0.25, 0.25))) * CELL;
        let rot = Quat::from_rotation_y(b.rng.range(0.0, TAU)) * Quat::from_rotation_x(b.rng.range(-0.8, 0.8)) * Quat::from_rotation_z(b.rng.range(-0.8, 0.8));
        let scale = b.rng.range(0.7, 1.1);
        // Centre the teapot (base at y = 0, about 1.5 tall) on its cell.
        let m = Mat4::from_scale_rotation_translation(Vec3::splat(scale), rot, pos) * Mat4::from_translation(Vec3::new(-0.3, -0.75, 0.0));
        let mesh = meshes[usize::from(b.rng.chance(0.5))];
        if round < 3 && clear.blocks(&b.bounds(mesh, &m)) {
            continue;
        }
        let color = hsv(b.rng.f32(), b.rng.range(0.3, 0.85), b.rng.range(0.55, 0.95));
        b.push(mesh, m, color);
    }
    path
}
