//! `figures`: a dense field of low-poly geometric figures (the IOC poster's
//! GF): tens of thousands of small solids, so any ray at eye level crosses
//! many of them (very high depth complexity). The path comes in over the
//! field and then runs low along a winding lane through it.

use glam::{Quat, Vec3};
use std::f32::consts::TAU;

use super::rng::hsv;
use super::shapes::{block, box_at, cone, cylinder, icosphere, octahedron, prism, pyramid, tetrahedron, torus, Part};
use super::{trs, walk_path, Builder, Clearance};
use crate::CameraPath;

const CELL: f32 = 1.5;
const TILE: f32 = 24.0;

fn person() -> Part {
    block(0.5, 0.6, 0.3)
        .at(Vec3::Y * 0.8)
        .with(block(0.2, 0.8, 0.25).at(Vec3::X * -0.13))
        .with(block(0.2, 0.8, 0.25).at(Vec3::X * 0.13))
        .with(box_at(Vec3::new(-0.33, 1.1, 0.0), Vec3::new(0.14, 0.6, 0.16)))
        .with(box_at(Vec3::new(0.33, 1.1, 0.0), Vec3::new(0.14, 0.6, 0.16)))
        .with(icosphere(0).scaled(Vec3::splat(0.16)).at(Vec3::Y * 1.58))
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    let tiles_est = ((n as f32).sqrt() * CELL / TILE).ceil().powi(2) as usize;
    let figures = n.saturating_sub(tiles_est).max(1);
    let g = ((figures as f32 * 1.15).sqrt().ceil() as usize + 1).max(3);
    let half = g as f32 * CELL * 0.5;

    // Path: in over the field's edge at 6 m, down to 1.3 m, then a winding
    // low run through the field.
    let k = 24;
    let phase = b.rng.range(0.0, TAU);
    let pts: Vec<Vec3> = (0..=k)
        .map(|i| {
            let s = i as f32 / k as f32;
            let x = -half * 0.85 + 1.7 * half * s;
            let z = half * 0.3 * (phase + s * TAU * 1.1).sin();
            let y = if s < 0.25 { 6.0 - (6.0 - 1.3) * (s / 0.25) } else { 1.3 };
            Vec3::new(x, y, z)
        })
        .collect();
    let path = walk_path(pts, 6.0, 25);
    let clear = Clearance::new(&[&path], 1.0, 8.0, 1.0);

    let unit = b.mesh("ground-tile", block(1.0, 1.0, 1.0));
    let tiles = ((2.0 * half) / TILE).ceil().max(1.0) as usize;
    let tile = 2.0 * half / tiles as f32;
    for i in 0..tiles {
        for j in 0..tiles {
            let c = b.rng.tint([0.35, 0.36, 0.33], 0.05);
            b.push(unit, trs(Vec3::new(-half + (i as f32 + 0.5) * tile, -0.1, -half + (j as f32 + 0.5) * tile), 0.0, Vec3::new(tile, 0.1, tile)), c);
        }
    }

    // (mesh, weight, centred: lifted by half its height; tilt allowed)
    let shapes = [
        (b.mesh("cube", block(1.0, 1.0, 1.0)), 2.0, false),
        (b.mesh("tetrahedron", tetrahedron(0.6)), 1.0, true),
        (b.mesh("octahedron", octahedron(0.6)), 1.0, true),
        (b.mesh("pyramid", pyramid(4, 0.65, 1.0)), 1.2, false),
        (b.mesh("hex-prism", prism(6, 0.5, 1.0)), 1.0, false),
        (b.mesh("cylinder", cylinder(0.45, 1.0, 8)), 1.2, false),
        (b.mesh("cone", cone(0.5, 1.1, 8)), 1.0, false),
        (b.mesh("ico0", icosphere(0).scaled(Vec3::splat(0.55))), 1.0, true),
        (b.mesh("ico1", icosphere(1).scaled(Vec3::splat(0.55))), 0.8, true),
        (b.mesh("torus", torus(0.4, 0.14, 8, 6)), 0.6, true),
        (b.mesh("tri-prism", prism(3, 0.6, 1.0)), 0.8, false),
        (b.mesh("person", person()), 1.5, false),
        (b.mesh("obelisk", prism(4, 0.35, 4.0)), 0.15, false),
    ];
    let weights: Vec<f32> = shapes.iter().map(|s| s.1).collect();

    // One figure per cell of a jittered grid, cells in random order, lane
    // cells skipped; if the field runs out, further layers go on top.
    let mut cells: Vec<u32> = (0..(g * g) as u32).collect();
    b.rng.shuffle(&mut cells);
    let mut next = 0usize;
    while b.left() > 0 {
        let (cell, layer) = (cells[next % cells.len()] as usize, next / cells.len());
        next += 1;
        let (mesh, _, centred) = shapes[b.rng.weighted(&weights)];
        let scale = b.rng.range(0.55, 1.25);
        let stretch = Vec3::new(1.0, b.rng.range(0.7, 1.8), 1.0) * scale;
        let jitter = b.rng.vec2(-0.2, 0.2) * CELL;
        let rot =
            if centred { Quat::from_rotation_x(b.rng.range(0.0, TAU)) * Quat::from_rotation_z(b.rng.range(0.0, TAU)) } else { Quat::from_rotation_x(b.rng.range(-0.15, 0.15)) };
        let rot = Quat::from_rotation_y(b.rng.range(0.0, TAU)) * rot;
        let color = hsv(b.rng.f32(), b.rng.range(0.4, 0.9), b.rng.range(0.5, 0.95));
        let (x, z, y) = ((cell % g) as f32, (cell / g) as f32, layer as f32 * 2.0);
        let base = Vec3::new(-half + (x + 0.5) * CELL + jitter.x, y, -half + (z + 0.5) * CELL + jitter.y);
        let m = glam::Mat4::from_scale_rotation_translation(stretch, rot, base);
        let bx = b.bounds(mesh, &m);
        // Stand it on the ground.
        let m = glam::Mat4::from_translation(Vec3::Y * (base.y - bx.min.y)) * m;
        if clear.blocks(&b.bounds(mesh, &m)) && layer < 4 {
            continue;
        }
        b.push(mesh, m, color);
    }
    path
}
