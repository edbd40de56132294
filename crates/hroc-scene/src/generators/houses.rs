//! `houses`: a grid of hollow, furnished buildings that the path enters and
//! leaves. Outside, walls hide the interiors but for glimpses through open
//! doors; inside, the room's walls hide the town. Leaving is the hard moment for culling from last frame's
//! visibility: the frame before, the view was one room, whose walls now
//! stand behind the eye and hide nothing (a visible set that collapses).

use glam::Vec3;
use std::f32::consts::PI;

use super::shapes::block;
use super::{trs, walk_path, Builder, Clearance};
use crate::CameraPath;

/// Footprint of a building (square), street width, wall height and thickness.
const LOT: f32 = 12.0;
const STREET: f32 = 8.0;
const WALL_H: f32 = 5.0;
const WALL_T: f32 = 0.3;
const DOOR_W: f32 = 2.4;
const DOOR_H: f32 = 3.0;
const EYE: f32 = 1.7;
/// Objects per building on average: 8 of shell, the rest furniture.
const PER_HOUSE: usize = 36;

/// The buildings' grid: `g` × `g` lots, lot (i, j) centred at `centre(i, j)`.
fn centre(g: usize, i: usize, j: usize) -> Vec3 {
    let pitch = LOT + STREET;
    let half = (g as f32 - 1.0) * 0.5;
    Vec3::new((i as f32 - half) * pitch, 0.0, (j as f32 - half) * pitch)
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let g = ((b.n as f32 / PER_HOUSE as f32).sqrt().ceil() as usize).max(3);
    let pitch = LOT + STREET;
    let unit = b.mesh("unit block", block(1.0, 1.0, 1.0));

    // The path: along the street south of row j0 (doors face -z, onto the
    // street at z = c.z - pitch / 2), into the doors of two houses, round
    // each room and out again.
    let j0 = 1 + b.rng.below(g - 2);
    let street_z = centre(g, 0, j0).z - pitch * 0.5;
    let visits = [b.rng.below(g / 2), g / 2 + b.rng.below(g - g / 2)];
    let mut pts = vec![Vec3::new(centre(g, 0, j0).x - pitch * 0.5, EYE, street_z)];
    for &i in &visits {
        let c = centre(g, i, j0);
        let door_out = Vec3::new(c.x, EYE, street_z);
        let door_in = Vec3::new(c.x, EYE, c.z - LOT * 0.5 + 1.5);
        let inside = [Vec3::new(c.x - 3.0, EYE, c.z), Vec3::new(c.x, EYE, c.z + 3.0), Vec3::new(c.x + 3.0, EYE, c.z), door_in];
        pts.extend([door_out, door_in]);
        pts.extend(inside);
        pts.push(door_out);
    }
    pts.push(Vec3::new(centre(g, g - 1, j0).x + pitch * 0.5, EYE, street_z));
    let path = walk_path(pts, 2.5, 160);
    let clear = Clearance::new(&[&path], 1.0, EYE, 1.0);

    // Ground, then every house's shell: floor, three walls, the front wall
    // in three pieces round its door, and a roof.
    let ground = (g as f32 * pitch) + STREET;
    b.push(unit, trs(Vec3::new(0.0, -0.1, 0.0), 0.0, Vec3::new(ground, 0.1, ground)), [0.35, 0.35, 0.33]);
    let (l, t) = (LOT * 0.5, WALL_T);
    for i in 0..g {
        for j in 0..g {
            let c = centre(g, i, j);
            let wall = b.rng.color(&[[0.8, 0.75, 0.65], [0.7, 0.5, 0.4], [0.85, 0.85, 0.8], [0.6, 0.62, 0.58]], 0.05);
            let side = (LOT - DOOR_W) * 0.5;
            let pieces = [
                (Vec3::new(0.0, 0.0, l - t * 0.5), Vec3::new(LOT, WALL_H, t)),
                // Side walls between the front and back ones: no two faces meet in one plane.
                (Vec3::new(-l + t * 0.5, 0.0, 0.0), Vec3::new(t, WALL_H, LOT - 2.0 * t)),
                (Vec3::new(l - t * 0.5, 0.0, 0.0), Vec3::new(t, WALL_H, LOT - 2.0 * t)),
                (Vec3::new(-l + side * 0.5, 0.0, -l + t * 0.5), Vec3::new(side, WALL_H, t)),
                (Vec3::new(l - side * 0.5, 0.0, -l + t * 0.5), Vec3::new(side, WALL_H, t)),
                (Vec3::new(0.0, DOOR_H, -l + t * 0.5), Vec3::new(DOOR_W, WALL_H - DOOR_H, t)),
                (Vec3::new(0.0, WALL_H, 0.0), Vec3::new(LOT, t, LOT)),
                (Vec3::new(0.0, 0.0, 0.0), Vec3::new(LOT - 2.0 * t, 0.05, LOT - 2.0 * t)),
            ];
            for (k, (at, size)) in pieces.into_iter().enumerate() {
                let color = if k == 7 { [0.5, 0.4, 0.3] } else { wall };
                b.push(unit, trs(c + at, 0.0, size), color);
            }
        }
    }
    // Furniture, house by house, until the count is reached: crates,
    // tables and shelves on the floor, clear of the path.
    let mut misses = 0;
    let mut house = 0;
    while b.left() > 0 {
        let c = centre(g, house % g, (house / g) % g);
        house += 1;
        let (w, h, d) = match b.rng.below(3) {
            0 => (b.rng.range(0.5, 1.0), b.rng.range(0.5, 1.0), b.rng.range(0.5, 1.0)),
            1 => (b.rng.range(1.2, 2.0), 0.75, b.rng.range(0.7, 1.0)),
            _ => (b.rng.range(0.8, 1.6), b.rng.range(1.6, 2.4), 0.4),
        };
        // A piece's half-diagonal is at most 1.2: it stays clear of the walls.
        let inner = LOT * 0.5 - WALL_T - 1.2;
        let pos = c + Vec3::new(b.rng.range(-inner, inner), 0.05, b.rng.range(-inner, inner));
        let m = trs(pos, b.rng.range(0.0, PI), Vec3::new(w, h, d));
        if misses < 100 && clear.blocks(&b.bounds(unit, &m)) {
            misses += 1;
            continue;
        }
        misses = 0;
        let color = b.rng.color(&[[0.45, 0.3, 0.18], [0.6, 0.42, 0.25], [0.2, 0.3, 0.55], [0.55, 0.15, 0.15]], 0.1);
        b.push(unit, m, color);
    }
    path
}
