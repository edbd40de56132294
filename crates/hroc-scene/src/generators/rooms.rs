//! `rooms`: a grid of furnished rooms whose walls have doorways (the IOC
//! poster's RM). Walls hide everything but the current room and glimpses
//! through doors; the path walks from room to room through the doorways.

use glam::{Quat, Vec3};
use std::f32::consts::FRAC_PI_2;

use super::shapes::{block, box_at, cylinder, frustum, icosphere, lathe, Part};
use super::{trs, walk_path, Builder, Clearance};
use crate::{Aabb, CameraPath};

const WALL_H: f32 = 3.0;
const WALL_T: f32 = 0.2;
const DOOR_W: f32 = 1.2;
const DOOR_H: f32 = 2.2;
const EYE: f32 = 1.7;
/// Objects per room on average (floor, wall pieces, furniture).
const PER_ROOM: f32 = 21.0;

struct Furniture {
    mesh: u32,
    weight: f32,
    against_wall: bool,
    /// Height of a top others can stand on (0: none).
    surface: f32,
    colors: &'static [[f32; 3]],
}

const WOOD: &[[f32; 3]] = &[[0.45, 0.3, 0.18], [0.6, 0.42, 0.25], [0.3, 0.2, 0.12], [0.75, 0.6, 0.42]];
const FABRIC: &[[f32; 3]] = &[[0.55, 0.15, 0.15], [0.2, 0.3, 0.55], [0.3, 0.5, 0.3], [0.7, 0.65, 0.5], [0.35, 0.35, 0.38]];
const PAINT: &[[f32; 3]] = &[[0.9, 0.9, 0.88], [0.25, 0.25, 0.28], [0.85, 0.8, 0.6], [0.6, 0.75, 0.8]];
const PLANT: &[[f32; 3]] = &[[0.2, 0.5, 0.2], [0.3, 0.6, 0.25], [0.15, 0.4, 0.2]];
const DECOR: &[[f32; 3]] = &[[0.8, 0.3, 0.2], [0.2, 0.45, 0.7], [0.9, 0.8, 0.3], [0.5, 0.2, 0.5], [0.9, 0.9, 0.9]];

fn legs(w: f32, d: f32, h: f32, t: f32) -> Part {
    let mut p = Part::new();
    for (sx, sz) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        p.append(&block(t, h, t).at(Vec3::new(sx * (w - t) * 0.5, 0.0, sz * (d - t) * 0.5)));
    }
    p
}

fn table() -> Part {
    block(1.4, 0.05, 0.8).at(Vec3::Y * 0.72).with(legs(1.3, 0.7, 0.72, 0.06))
}

fn chair() -> Part {
    block(0.45, 0.05, 0.45).at(Vec3::Y * 0.43).with(legs(0.45, 0.45, 0.43, 0.04)).with(box_at(Vec3::new(0.0, 0.75, -0.2), Vec3::new(0.45, 0.6, 0.05)))
}

fn bed() -> Part {
    block(1.6, 0.35, 2.0)
        .with(block(1.5, 0.2, 1.85).at(Vec3::new(0.0, 0.35, 0.05)))
        .with(box_at(Vec3::new(0.0, 0.5, -0.96), Vec3::new(1.6, 1.0, 0.08)))
        .with(box_at(Vec3::new(0.0, 0.6, -0.7), Vec3::new(1.0, 0.12, 0.35)))
}

fn wardrobe() -> Part {
    block(1.2, 2.0, 0.6).with(box_at(Vec3::new(-0.05, 1.0, 0.31), Vec3::new(0.03, 0.3, 0.03))).with(box_at(Vec3::new(0.05, 1.0, 0.31), Vec3::new(0.03, 0.3, 0.03)))
}

fn bookshelf() -> Part {
    let mut p = box_at(Vec3::new(0.0, 1.0, -0.16), Vec3::new(1.0, 2.0, 0.03));
    for x in [-0.49, 0.49] {
        p.append(&box_at(Vec3::new(x, 1.0, 0.0), Vec3::new(0.03, 2.0, 0.35)));
    }
    for i in 0..5 {
        p.append(&box_at(Vec3::new(0.0, 0.02 + i as f32 * 0.48, 0.0), Vec3::new(0.96, 0.03, 0.33)));
    }
    // Rows of books, one block per shelf.
    for i in 0..4 {
        p.append(&box_at(Vec3::new(0.0, 0.16 + i as f32 * 0.48, 0.0), Vec3::new(0.9, 0.26, 0.24)));
    }
    p
}

fn sofa() -> Part {
    block(2.0, 0.42, 0.9)
        .with(box_at(Vec3::new(0.0, 0.65, -0.35), Vec3::new(2.0, 0.5, 0.2)))
        .with(box_at(Vec3::new(-0.9, 0.55, 0.0), Vec3::new(0.2, 0.3, 0.9)))
        .with(box_at(Vec3::new(0.9, 0.55, 0.0), Vec3::new(0.2, 0.3, 0.9)))
}

fn floor_lamp() -> Part {
    cylinder(0.18, 0.03, 12).with(cylinder(0.02, 1.5, 6)).with(frustum(0.25, 0.14, 0.3, 12).at(Vec3::Y * 1.4))
}

fn plant() -> Part {
    frustum(0.16, 0.22, 0.4, 10).with(icosphere(1).scaled(Vec3::new(0.4, 0.5, 0.4)).at(Vec3::Y * 0.85))
}

fn round_table() -> Part {
    cylinder(0.55, 0.04, 20).at(Vec3::Y * 0.72).with(cylinder(0.05, 0.72, 8)).with(cylinder(0.3, 0.03, 12))
}

fn desk() -> Part {
    block(1.5, 0.04, 0.7)
        .at(Vec3::Y * 0.72)
        .with(block(0.45, 0.72, 0.66).at(Vec3::new(-0.5, 0.0, 0.0)))
        .with(block(0.04, 0.72, 0.66).at(Vec3::new(0.71, 0.0, 0.0)))
        .with(box_at(Vec3::new(0.0, 1.0, -0.25), Vec3::new(0.6, 0.38, 0.04)))
}

fn crate_() -> Part {
    block(0.6, 0.6, 0.6)
}

fn tv_stand() -> Part {
    block(1.6, 0.5, 0.45).with(box_at(Vec3::new(0.0, 0.85, -0.1), Vec3::new(1.3, 0.7, 0.06)))
}

fn vase() -> Part {
    lathe(&[[0.0, 0.0], [0.08, 0.0], [0.08, 0.0], [0.12, 0.1], [0.09, 0.25], [0.05, 0.32], [0.07, 0.38], [0.07, 0.38], [0.0, 0.38]], 12)
}

fn book_stack() -> Part {
    let mut p = Part::new();
    for (i, (w, d, a)) in [(0.3f32, 0.22f32, 0.1f32), (0.28, 0.2, -0.2), (0.25, 0.18, 0.35)].into_iter().enumerate() {
        p.append(&block(w, 0.05, d).rotated(Quat::from_rotation_y(a)).at(Vec3::Y * (i as f32 * 0.05)));
    }
    p
}

fn table_lamp() -> Part {
    cylinder(0.08, 0.03, 8).with(cylinder(0.015, 0.35, 6)).with(frustum(0.14, 0.08, 0.18, 10).at(Vec3::Y * 0.3))
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    let side = ((n as f32 / PER_ROOM).sqrt().round() as usize).max(1);
    let rng = &mut b.rng;
    // Grid lines with varied room sizes, centred on the origin.
    let lines = |rng: &mut super::rng::Rng| {
        let mut v = vec![0.0f32];
        for _ in 0..side {
            v.push(v.last().unwrap() + rng.range(5.5, 9.0));
        }
        let mid = v[side] * 0.5;
        v.iter().map(|x| x - mid).collect::<Vec<f32>>()
    };
    let xs = lines(rng);
    let zs = lines(rng);
    let room = |c: usize, r: usize| (Vec3::new(xs[c], 0.0, zs[r]), Vec3::new(xs[c + 1], WALL_H, zs[r + 1]));
    let centre = |c: usize, r: usize| {
        let (lo, hi) = room(c, r);
        (lo + hi) * 0.5
    };

    // Door offsets (centre along the wall) for walls between rooms:
    // vertical walls at x = xs[i] between (i-1, r) and (i, r); horizontal at z = zs[j].
    let mut door_v: Vec<Vec<Option<f32>>> = vec![vec![None; side]; side + 1];
    let mut door_h: Vec<Vec<Option<f32>>> = vec![vec![None; side]; side + 1];
    for line in door_v.iter_mut().take(side).skip(1) {
        for (r, door) in line.iter_mut().enumerate() {
            if !rng.chance(0.1) {
                *door = Some(rng.range(zs[r] + 0.9 + DOOR_W * 0.5, zs[r + 1] - 0.9 - DOOR_W * 0.5));
            }
        }
    }
    for line in door_h.iter_mut().take(side).skip(1) {
        for (c, door) in line.iter_mut().enumerate() {
            if !rng.chance(0.1) {
                *door = Some(rng.range(xs[c] + 0.9 + DOOR_W * 0.5, xs[c + 1] - 0.9 - DOOR_W * 0.5));
            }
        }
    }

    // Route through up to 8 rooms; the walls it crosses get doors.
    let route = super::grid_walk(rng, 0, side - 1, (side * side).min(8) - 1);
    let (c0, r0) = route[0];
    let jitter = rng.vec2(-1.0, 1.0);
    let mut eye_pts = vec![centre(c0, r0) + Vec3::new(jitter.x, 0.0, jitter.y)];
    for w in route.windows(2) {
        let ((ca, ra), (cb, rb)) = (w[0], w[1]);
        let (door, normal) = if ca != cb {
            let i = ca.max(cb);
            let z = *door_v[i][ra].get_or_insert_with(|| (zs[ra] + zs[ra + 1]) * 0.5);
            (Vec3::new(xs[i], 0.0, z), Vec3::X * (cb as f32 - ca as f32))
        } else {
            let j = ra.max(rb);
            let x = *door_h[j][ca].get_or_insert_with(|| (xs[ca] + xs[ca + 1]) * 0.5);
            (Vec3::new(x, 0.0, zs[j]), Vec3::Z * (rb as f32 - ra as f32))
        };
        eye_pts.push(door - normal * 1.0);
        eye_pts.push(door + normal * 1.0);
    }
    let (cl, rl) = *route.last().unwrap();
    eye_pts.push(centre(cl, rl));
    for p in &mut eye_pts {
        p.y = EYE;
    }
    let path = walk_path(eye_pts, 3.0, 21);
    let clear = Clearance::new(&[&path], 0.55, EYE - 0.05, 1.0);

    // Structure: floors, then walls (pieces split at doorways).
    let unit = b.mesh("unit-box", block(1.0, 1.0, 1.0));
    let floor_colors = [[0.55, 0.4, 0.25], [0.7, 0.7, 0.68], [0.4, 0.3, 0.25], [0.6, 0.55, 0.45]];
    for r in 0..side {
        for c in 0..side {
            let (lo, hi) = room(c, r);
            let color = b.rng.color(&floor_colors, 0.1);
            b.push(unit, trs(Vec3::new((lo.x + hi.x) * 0.5, -0.1, (lo.z + hi.z) * 0.5), 0.0, Vec3::new(hi.x - lo.x, 0.1, hi.z - lo.z)), color);
        }
    }
    let wall_color = [0.82, 0.8, 0.74];
    // A wall on the line at `w` (z = w when `along_x`, else x = w) from
    // `start` to `end`, with an optional doorway centred at `door`.
    let wall = |b: &mut Builder, along_x: bool, w: f32, start: f32, end: f32, door: Option<f32>| {
        let color = b.rng.tint(wall_color, 0.08);
        let piece = |b: &mut Builder, u0: f32, u1: f32, y0: f32, y1: f32| {
            let (c, len) = ((u0 + u1) * 0.5, u1 - u0);
            let (pos, size) = if along_x { (Vec3::new(c, y0, w), Vec3::new(len, y1 - y0, WALL_T)) } else { (Vec3::new(w, y0, c), Vec3::new(WALL_T, y1 - y0, len)) };
            b.push(unit, trs(pos, 0.0, size), color);
        };
        let (u0, u1) = (start - WALL_T * 0.5, end + WALL_T * 0.5);
        match door {
            Some(d) => {
                piece(b, u0, d - DOOR_W * 0.5, 0.0, WALL_H);
                piece(b, d + DOOR_W * 0.5, u1, 0.0, WALL_H);
                piece(b, d - DOOR_W * 0.5, d + DOOR_W * 0.5, DOOR_H, WALL_H);
            }
            None => piece(b, u0, u1, 0.0, WALL_H),
        }
    };
    for i in 0..=side {
        for r in 0..side {
            wall(b, false, xs[i], zs[r], zs[r + 1], door_v[i][r]);
        }
    }
    for j in 0..=side {
        for c in 0..side {
            wall(b, true, zs[j], xs[c], xs[c + 1], door_h[j][c]);
        }
    }

    // Keep-out zones in front of every doorway, so doors stay passable.
    // Per room: each zone is listed for the two rooms the door joins.
    let rooms = side * side;
    let mut door_zones: Vec<Vec<Aabb>> = vec![vec![]; rooms];
    for (i, col) in door_v.iter().enumerate() {
        for (r, d) in col.iter().enumerate() {
            let Some(d) = d else { continue };
            let zone = Aabb::new(Vec3::new(xs[i] - 1.0, 0.0, d - DOOR_W * 0.5 - 0.3), Vec3::new(xs[i] + 1.0, DOOR_H, d + DOOR_W * 0.5 + 0.3));
            door_zones[r * side + i - 1].push(zone);
            door_zones[r * side + i].push(zone);
        }
    }
    for (j, row) in door_h.iter().enumerate() {
        for (c, d) in row.iter().enumerate() {
            let Some(d) = d else { continue };
            let zone = Aabb::new(Vec3::new(d - DOOR_W * 0.5 - 0.3, 0.0, zs[j] - 1.0), Vec3::new(d + DOOR_W * 0.5 + 0.3, DOOR_H, zs[j] + 1.0));
            door_zones[(j - 1) * side + c].push(zone);
            door_zones[j * side + c].push(zone);
        }
    }

    let furniture = [
        Furniture { mesh: b.mesh("table", table()), weight: 1.0, against_wall: false, surface: 0.77, colors: WOOD },
        Furniture { mesh: b.mesh("chair", chair()), weight: 2.0, against_wall: false, surface: 0.0, colors: WOOD },
        Furniture { mesh: b.mesh("bed", bed()), weight: 0.4, against_wall: true, surface: 0.0, colors: FABRIC },
        Furniture { mesh: b.mesh("wardrobe", wardrobe()), weight: 0.6, against_wall: true, surface: 2.0, colors: WOOD },
        Furniture { mesh: b.mesh("bookshelf", bookshelf()), weight: 0.8, against_wall: true, surface: 1.95, colors: WOOD },
        Furniture { mesh: b.mesh("sofa", sofa()), weight: 0.5, against_wall: true, surface: 0.0, colors: FABRIC },
        Furniture { mesh: b.mesh("floor-lamp", floor_lamp()), weight: 0.6, against_wall: false, surface: 0.0, colors: PAINT },
        Furniture { mesh: b.mesh("plant", plant()), weight: 0.7, against_wall: false, surface: 0.0, colors: PLANT },
        Furniture { mesh: b.mesh("round-table", round_table()), weight: 0.5, against_wall: false, surface: 0.76, colors: WOOD },
        Furniture { mesh: b.mesh("desk", desk()), weight: 0.6, against_wall: true, surface: 0.76, colors: WOOD },
        Furniture { mesh: b.mesh("crate", crate_()), weight: 0.6, against_wall: false, surface: 0.6, colors: WOOD },
        Furniture { mesh: b.mesh("tv-stand", tv_stand()), weight: 0.3, against_wall: true, surface: 0.0, colors: PAINT },
    ];
    let decor = [b.mesh("vase", vase()), b.mesh("book-stack", book_stack()), b.mesh("table-lamp", table_lamp())];
    let weights: Vec<f32> = furniture.iter().map(|f| f.weight).collect();

    // Furniture: each piece goes into a random room, not into doorways,
    // other furniture or the path; a quarter are small things on tops.
    let mut placed: Vec<Vec<Aabb>> = vec![vec![]; rooms];
    let mut tops: Vec<Vec<(Vec3, f32)>> = vec![vec![]; rooms]; // (centre of top, radius)
    let mut failures = 0;
    while b.left() > 0 {
        let ri = b.rng.below(rooms);
        let (lo, hi) = room(ri % side, ri / side);
        let (lo, hi) = (lo + Vec3::splat(WALL_T * 0.5 + 0.05), hi - Vec3::splat(WALL_T * 0.5 + 0.05));
        if !tops[ri].is_empty() && b.rng.chance(0.25) {
            let (top, r) = *b.rng.pick(&tops[ri]);
            let mesh = *b.rng.pick(&decor);
            let off = b.rng.vec2(-r, r);
            let off = Vec3::new(off.x, 0.0, off.y);
            let color = b.rng.color(DECOR, 0.15);
            let yaw = b.rng.range(0.0, std::f32::consts::TAU);
            b.push(mesh, trs(top + off, yaw, Vec3::ONE), color);
            continue;
        }
        let f = &furniture[b.rng.weighted(&weights)];
        let mut best = None;
        for attempt in 0..24 {
            let (pos, yaw) = if f.against_wall {
                let side_i = b.rng.below(4);
                let size = b.scene.meshes[f.mesh as usize].bounds.extent();
                let depth = size.z * 0.5 + 0.02;
                let (x, z) = (b.rng.range(lo.x, hi.x), b.rng.range(lo.z, hi.z));
                match side_i {
                    0 => (Vec3::new(x, 0.0, lo.z + depth), 0.0),
                    1 => (Vec3::new(x, 0.0, hi.z - depth), std::f32::consts::PI),
                    2 => (Vec3::new(lo.x + depth, 0.0, z), FRAC_PI_2),
                    _ => (Vec3::new(hi.x - depth, 0.0, z), -FRAC_PI_2),
                }
            } else {
                let yaw = b.rng.below(4) as f32 * FRAC_PI_2 + b.rng.range(-0.2, 0.2);
                (Vec3::new(b.rng.range(lo.x, hi.x), 0.0, b.rng.range(lo.z, hi.z)), yaw)
            };
            let m = trs(pos, yaw, Vec3::ONE);
            let bx = b.bounds(f.mesh, &m);
            let inside = bx.min.x >= lo.x && bx.max.x <= hi.x && bx.min.z >= lo.z && bx.max.z <= hi.z;
            if !inside || clear.blocks(&bx) || door_zones[ri].iter().any(|z| z.overlaps(&bx)) {
                continue;
            }
            best = Some((m, bx));
            let shrunk = Aabb::new(bx.min + Vec3::splat(0.02), bx.max - Vec3::splat(0.02));
            if !placed[ri].iter().any(|o| o.overlaps(&shrunk)) || attempt == 23 {
                break;
            }
        }
        // No free spot in this room: try another; after many misses (tiny
        // scenes) take any spot, since the count must be exact.
        let (m, bx) = match best {
            Some(v) => v,
            None if failures < 200 => {
                failures += 1;
                continue;
            }
            None => {
                let m = trs(Vec3::new(b.rng.range(lo.x, hi.x), 0.0, b.rng.range(lo.z, hi.z)), 0.0, Vec3::ONE);
                (m, b.bounds(f.mesh, &m))
            }
        };
        failures = 0;
        let color = b.rng.color(f.colors, 0.12);
        b.push(f.mesh, m, color);
        placed[ri].push(bx);
        if f.surface > 0.0 {
            let c = bx.center();
            tops[ri].push((Vec3::new(c.x, f.surface, c.z), (bx.extent().x.min(bx.extent().z) * 0.5 - 0.15).max(0.0)));
        }
    }
    path
}
