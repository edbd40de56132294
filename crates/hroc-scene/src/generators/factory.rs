//! `factory` (HROC's FC): a wide hall of 20 m bays separated by 4 m aisles.
//! Bays hold pallet racks full of goods, machine parks, tank farms with
//! pipes, pallet yards or assembly lines; overhead pipe runs follow the
//! aisles. The path walks the aisles at eye level; racks, tanks, machines
//! and partition walls hide most bays from any aisle.

use glam::{Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, TAU};

use super::rng::Rng;
use super::shapes::{block, box_at, cylinder, lathe, rock, torus, uv_sphere, Part};
use super::{grid_walk, trs, walk_path, Builder, Clearance};
use crate::CameraPath;

const BAY: f32 = 20.0;
const AISLE: f32 = 4.0;
const PITCH: f32 = BAY + AISLE;
const HALL_H: f32 = 12.0;
const EYE: f32 = 1.7;
/// Objects per bay on average (structure plus goods).
const PER_BAY: f32 = 130.0;

const RACK_L: f32 = 2.7;
const RACK_D: f32 = 1.1;
const RACK_LEVELS: [f32; 3] = [0.15, 2.05, 3.95];

const PAINT: &[[f32; 3]] = &[[0.85, 0.6, 0.1], [0.2, 0.45, 0.7], [0.3, 0.55, 0.3], [0.7, 0.2, 0.15], [0.85, 0.85, 0.8]];
const CARDBOARD: &[[f32; 3]] = &[[0.65, 0.5, 0.32], [0.7, 0.58, 0.4], [0.55, 0.42, 0.28]];
const DRUM: &[[f32; 3]] = &[[0.15, 0.3, 0.6], [0.7, 0.15, 0.1], [0.2, 0.5, 0.25], [0.2, 0.2, 0.22], [0.85, 0.7, 0.1]];

fn rack() -> Part {
    let mut p = Part::new();
    for (x, z) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        p.append(&box_at(Vec3::new(x * (RACK_L * 0.5 - 0.05), 3.0, z * (RACK_D * 0.5 - 0.05)), Vec3::new(0.1, 6.0, 0.1)));
    }
    for y in RACK_LEVELS {
        for z in [-1.0, 1.0] {
            p.append(&box_at(Vec3::new(0.0, y - 0.06, z * (RACK_D * 0.5 - 0.05)), Vec3::new(RACK_L, 0.12, 0.08)));
        }
        p.append(&box_at(Vec3::new(0.0, y - 0.015, 0.0), Vec3::new(RACK_L - 0.1, 0.03, RACK_D - 0.1)));
    }
    p
}

fn pallet() -> Part {
    let mut p = block(1.2, 0.03, 1.0).at(Vec3::Y * 0.12);
    for x in [-0.5, 0.0, 0.5] {
        p.append(&block(0.12, 0.12, 1.0).at(Vec3::X * x));
    }
    p
}

fn pallet_boxes(h: f32) -> Part {
    pallet().with(block(1.1, h, 0.9).at(Vec3::Y * 0.15)).with(block(0.5, 0.3, 0.4).at(Vec3::new(0.25, 0.15 + h, 0.2)))
}

/// Drum with two rolling hoops (~120 triangles).
fn barrel() -> Part {
    lathe(&[[0.0, 0.0], [0.3, 0.0], [0.3, 0.0], [0.3, 0.3], [0.315, 0.33], [0.3, 0.36], [0.3, 0.9], [0.3, 0.9], [0.0, 0.9]], 12)
}

fn pallet_barrels() -> Part {
    let mut p = pallet();
    for (x, z) in [(-0.3, -0.25), (0.3, -0.25), (-0.3, 0.25), (0.3, 0.25)] {
        p.append(&cylinder(0.27, 0.8, 10).at(Vec3::new(x, 0.15, z)));
    }
    p
}

fn crate_() -> Part {
    let mut p = block(1.0, 1.0, 1.0);
    // Battens on two faces.
    for y in [0.15, 0.85] {
        p.append(&box_at(Vec3::new(0.0, y, 0.51), Vec3::new(1.0, 0.1, 0.03)));
        p.append(&box_at(Vec3::new(0.0, y, -0.51), Vec3::new(1.0, 0.1, 0.03)));
    }
    p
}

fn gas_bottles() -> Part {
    let bottle = lathe(&[[0.0, 0.0], [0.12, 0.0], [0.12, 0.0], [0.12, 1.2], [0.06, 1.35], [0.04, 1.45], [0.0, 1.45]], 8);
    let mut p = block(1.0, 0.05, 0.4);
    for i in 0..4 {
        p.append(&bottle.clone().at(Vec3::new(-0.36 + i as f32 * 0.24, 0.05, 0.0)));
    }
    p
}

fn sacks(rng: &mut Rng) -> Part {
    let mut p = pallet();
    for i in 0..6 {
        let (x, y) = ((i % 2) as f32 * 0.55 - 0.27, 0.25 + (i / 2) as f32 * 0.22);
        p.append(&rock(0, 0.1, rng).scaled(Vec3::new(0.27, 0.12, 0.45)).at(Vec3::new(x, y, 0.0)));
    }
    p
}

fn lathe_machine() -> Part {
    block(3.2, 0.9, 1.0)
        .with(box_at(Vec3::new(-1.3, 1.25, 0.0), Vec3::new(0.7, 0.7, 0.8)))
        .with(box_at(Vec3::new(1.2, 1.1, 0.0), Vec3::new(0.4, 0.4, 0.5)))
        .with(cylinder(0.25, 0.3, 16).rotated(Quat::from_rotation_z(-FRAC_PI_2)).at(Vec3::new(-0.95, 1.2, 0.0)))
        .with(cylinder(0.04, 1.9, 8).rotated(Quat::from_rotation_z(-FRAC_PI_2)).at(Vec3::new(-0.95, 1.2, 0.0)))
        .with(box_at(Vec3::new(-1.3, 1.4, 0.55), Vec3::new(0.4, 0.5, 0.1)))
}

fn press() -> Part {
    block(2.2, 0.6, 1.8)
        .with(box_at(Vec3::new(-0.9, 2.0, 0.0), Vec3::new(0.35, 2.8, 1.2)))
        .with(box_at(Vec3::new(0.9, 2.0, 0.0), Vec3::new(0.35, 2.8, 1.2)))
        .with(box_at(Vec3::new(0.0, 3.6, 0.0), Vec3::new(2.2, 0.8, 1.4)))
        .with(cylinder(0.3, 1.6, 16).at(Vec3::Y * 1.6))
        .with(box_at(Vec3::new(0.0, 1.4, 0.0), Vec3::new(1.3, 0.25, 1.1)))
}

fn cnc() -> Part {
    block(3.0, 2.4, 2.2)
        .with(box_at(Vec3::new(0.0, 1.5, 1.12), Vec3::new(1.6, 0.9, 0.05)))
        .with(box_at(Vec3::new(1.75, 1.2, 0.6), Vec3::new(0.4, 1.6, 0.5)))
        .with(block(3.2, 0.1, 2.4).at(Vec3::Y * 2.4))
}

fn robot() -> Part {
    let joint = || uv_sphere(0.22, 12, 6);
    cylinder(0.45, 0.4, 16)
        .with(cylinder(0.3, 0.5, 16).at(Vec3::Y * 0.4))
        .with(joint().at(Vec3::Y * 0.95))
        .with(cylinder(0.14, 1.3, 12).rotated(Quat::from_rotation_z(-0.5)).at(Vec3::Y * 0.95))
        .with(joint().at(Vec3::new(0.62, 2.09, 0.0)))
        .with(cylinder(0.11, 1.1, 12).rotated(Quat::from_rotation_z(-2.0)).at(Vec3::new(0.62, 2.09, 0.0)))
        .with(box_at(Vec3::new(1.6, 1.6, 0.0), Vec3::new(0.25, 0.2, 0.3)))
}

fn conveyor() -> Part {
    let mut p = box_at(Vec3::new(0.0, 0.85, 0.0), Vec3::new(6.0, 0.12, 1.0));
    for x in [-2.8, -1.0, 1.0, 2.8] {
        for z in [-0.45, 0.45] {
            p.append(&box_at(Vec3::new(x, 0.4, z), Vec3::new(0.08, 0.8, 0.08)));
        }
    }
    for i in 0..12 {
        p.append(&cylinder(0.05, 1.0, 8).rotated(Quat::from_rotation_x(FRAC_PI_2)).at(Vec3::new(-2.75 + i as f32 * 0.5, 0.96, -0.5)));
    }
    p
}

fn compressor() -> Part {
    block(2.4, 0.3, 1.4)
        .with(cylinder(0.6, 2.0, 20).rotated(Quat::from_rotation_z(FRAC_PI_2)).at(Vec3::new(1.0, 0.95, 0.0)))
        .with(box_at(Vec3::new(0.0, 1.9, 0.0), Vec3::new(1.2, 0.7, 0.9)))
        .with(torus(0.35, 0.05, 16, 6).rotated(Quat::from_rotation_x(FRAC_PI_2)).at(Vec3::new(-0.3, 1.9, 0.5)))
}

fn forklift() -> Part {
    let wheel = cylinder(0.28, 0.2, 10).at(Vec3::Y * -0.1).rotated(Quat::from_rotation_z(FRAC_PI_2));
    block(1.1, 1.0, 2.0)
        .with(box_at(Vec3::new(0.0, 1.6, -0.2), Vec3::new(1.0, 0.1, 1.2)))
        .with(box_at(Vec3::new(0.0, 1.5, 1.1), Vec3::new(0.9, 2.6, 0.12)))
        .with(box_at(Vec3::new(-0.25, 0.1, 1.7), Vec3::new(0.12, 0.06, 1.1)))
        .with(box_at(Vec3::new(0.25, 0.1, 1.7), Vec3::new(0.12, 0.06, 1.1)))
        .with(wheel.clone().at(Vec3::new(-0.58, 0.28, 0.6)))
        .with(wheel.clone().at(Vec3::new(0.58, 0.28, 0.6)))
        .with(wheel.clone().at(Vec3::new(-0.58, 0.28, -0.6)))
        .with(wheel.at(Vec3::new(0.58, 0.28, -0.6)))
}

/// Tank: lathed shell with a domed top and a base ring (unit radius, height 1 + dome).
fn tank() -> Part {
    let mut prof = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.05], [1.03, 0.07], [1.0, 0.09], [1.0, 0.5], [1.03, 0.52], [1.0, 0.54], [1.0, 1.0]];
    for i in 1..=6 {
        let a = i as f32 / 6.0 * FRAC_PI_2;
        prof.push([a.cos(), 1.0 + 0.3 * a.sin()]);
    }
    lathe(&prof, 32)
}

/// A place goods can go: base centre, yaw, and the height available.
struct Slot {
    pos: Vec3,
    yaw: f32,
    max_h: f32,
    floor: bool,
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    let side = ((n as f32 / PER_BAY).sqrt().round() as usize).max(1);
    let half = side as f32 * PITCH * 0.5;
    // Aisle centre lines at -half + i * PITCH (i = 0..=side); bay (i, j)
    // spans [line_i + AISLE / 2, line_i + AISLE / 2 + BAY].
    let line = |i: usize| -half + i as f32 * PITCH;

    // Path over aisle intersections, like a drive through a street grid.
    let (lo, hi) = if side >= 3 { (1, side - 1) } else { (0, side) };
    let inter = grid_walk(&mut b.rng, lo, hi, 6);
    // The outer aisles run along the hall walls: keep a metre off them.
    let at = |i: usize| line(i).clamp(-half + 1.0, half - 1.0);
    let pts: Vec<Vec3> = if inter.len() > 1 {
        inter.iter().map(|&(i, j)| Vec3::new(at(i), EYE, at(j))).collect()
    } else {
        // One bay: walk round it.
        let (a, c) = (at(0), at(side));
        vec![Vec3::new(a, EYE, a), Vec3::new(c, EYE, a), Vec3::new(c, EYE, c), Vec3::new(a, EYE, c)]
    };
    let path = walk_path(pts, 8.0, 25);
    let clear = Clearance::new(&[&path], 1.0, EYE, 1.0);

    let unit = b.mesh("unit-box", block(1.0, 1.0, 1.0));
    let rack_m = b.mesh("rack", rack());
    let pipe = b.mesh("pipe", cylinder(1.0, 1.0, 12).rotated(Quat::from_rotation_z(-FRAC_PI_2)));
    let tank_m = b.mesh("tank", tank());
    let machines = [b.mesh("lathe", lathe_machine()), b.mesh("press", press()), b.mesh("cnc", cnc()), b.mesh("compressor", compressor()), b.mesh("forklift", forklift())];
    let robot_m = b.mesh("robot", robot());
    let conveyor_m = b.mesh("conveyor", conveyor());
    let mut rr = Rng::new(b.rng.next_u64());
    // Goods: (mesh, height, weight on racks, weight on the floor, palette)
    let goods = [
        (b.mesh("pallet-boxes-low", pallet_boxes(0.7)), 0.95, 3.0, 2.0, CARDBOARD),
        (b.mesh("pallet-boxes-high", pallet_boxes(1.3)), 1.55, 2.0, 1.5, CARDBOARD),
        (b.mesh("pallet-barrels", pallet_barrels()), 0.96, 1.5, 1.5, DRUM),
        (b.mesh("crate", crate_()), 1.0, 1.0, 2.0, CARDBOARD),
        (b.mesh("barrel", barrel()), 0.9, 0.0, 3.0, DRUM),
        (b.mesh("gas-bottles", gas_bottles()), 1.5, 0.0, 0.7, PAINT),
        (b.mesh("sacks", sacks(&mut rr)), 0.95, 1.0, 1.0, CARDBOARD),
    ];

    // Floor, columns and outer walls.
    let floor_c = [0.45, 0.45, 0.43];
    for i in 0..side {
        for j in 0..side {
            let c = Vec3::new(line(i) + PITCH * 0.5, -0.1, line(j) + PITCH * 0.5);
            let color = b.rng.tint(floor_c, 0.04);
            b.push(unit, trs(c, 0.0, Vec3::new(PITCH, 0.1, PITCH)), color);
        }
    }
    for i in 0..side {
        for (c, size) in [
            (Vec3::new(line(i) + PITCH * 0.5, 0.0, -half - 0.2), Vec3::new(PITCH, HALL_H, 0.4)),
            (Vec3::new(line(i) + PITCH * 0.5, 0.0, half + 0.2), Vec3::new(PITCH, HALL_H, 0.4)),
            (Vec3::new(-half - 0.2, 0.0, line(i) + PITCH * 0.5), Vec3::new(0.4, HALL_H, PITCH)),
            (Vec3::new(half + 0.2, 0.0, line(i) + PITCH * 0.5), Vec3::new(0.4, HALL_H, PITCH)),
        ] {
            b.push(unit, trs(c, 0.0, size), [0.7, 0.68, 0.62]);
        }
    }

    // Bays.
    let mut slots: Vec<Slot> = vec![];
    for j in 0..side {
        for i in 0..side {
            let (x0, z0) = (line(i) + AISLE * 0.5, line(j) + AISLE * 0.5);
            let o = Vec3::new(x0, 0.0, z0);
            // Columns at two bay corners (the hall's roof grid).
            for (dx, dz) in [(0.3, 0.3), (BAY - 0.3, 0.3)] {
                b.push(unit, trs(o + Vec3::new(dx, 0.0, dz), 0.0, Vec3::new(0.5, HALL_H, 0.5)), [0.5, 0.5, 0.55]);
            }
            // A partition wall along some bay edges, with an opening.
            if b.rng.chance(0.3) {
                let gap = b.rng.range(3.0, 13.0);
                let c = b.rng.color(PAINT, 0.05);
                b.push(unit, trs(o + Vec3::new(gap * 0.5, 0.0, BAY - 0.1), 0.0, Vec3::new(gap, 4.0, 0.2)), c);
                b.push(unit, trs(o + Vec3::new((gap + 4.0 + BAY) * 0.5, 0.0, BAY - 0.1), 0.0, Vec3::new(BAY - gap - 4.0, 4.0, 0.2)), c);
            }
            match b.rng.weighted(&[0.35, 0.2, 0.15, 0.15, 0.15]) {
                0 => {
                    // Pallet racks: three back-to-back pairs of 7-unit lines.
                    for pair in 0..3 {
                        for (k, &dz) in [0.55, 1.75].iter().enumerate() {
                            let z = z0 + 1.2 + pair as f32 * 6.5 + dz;
                            let yaw = if k == 0 { 0.0 } else { std::f32::consts::PI };
                            let c = b.rng.color(&[[0.2, 0.35, 0.6], [0.85, 0.45, 0.1]], 0.05);
                            for u in 0..7 {
                                let x = x0 + 0.6 + RACK_L * (u as f32 + 0.5);
                                b.push(rack_m, trs(Vec3::new(x, 0.0, z), yaw, Vec3::ONE), c);
                                for (l, &y) in RACK_LEVELS.iter().enumerate() {
                                    let max_h = if l == 2 { 2.0 } else { 1.75 };
                                    for sx in [-0.67, 0.67] {
                                        slots.push(Slot { pos: Vec3::new(x + sx, y, z), yaw, max_h, floor: false });
                                    }
                                }
                            }
                        }
                    }
                }
                1 => {
                    // Machine park: 3 x 3 machines, goods beside them.
                    for (u, v) in (0..9).map(|k| (k % 3, k / 3)) {
                        let c = o + Vec3::new(3.4 + u as f32 * 6.6, 0.0, 3.4 + v as f32 * 6.6);
                        let mesh = *b.rng.pick(&machines);
                        let yaw = b.rng.below(4) as f32 * FRAC_PI_2;
                        let color = b.rng.color(PAINT, 0.08);
                        b.push(mesh, trs(c, yaw, Vec3::ONE), color);
                        for (dx, dz) in [(2.4, 2.4), (-2.4, 2.4), (2.4, -2.4)] {
                            slots.push(Slot { pos: c + Vec3::new(dx, 0.0, dz), yaw: b.rng.range(0.0, TAU), max_h: 6.0, floor: true });
                        }
                    }
                }
                2 => {
                    // Tank farm: 2 x 2 tanks joined by pipes, drums between.
                    let mut tops = vec![];
                    for (u, v) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let c = o + Vec3::new(5.0 + u as f32 * 10.0, 0.0, 5.0 + v as f32 * 10.0);
                        let (r, h) = (b.rng.range(2.5, 3.6), b.rng.range(5.0, 9.0));
                        let color = b.rng.color(&[[0.75, 0.75, 0.72], [0.55, 0.6, 0.62], [0.8, 0.75, 0.6]], 0.04);
                        b.push(tank_m, trs(c, 0.0, Vec3::new(r, h, r)), color);
                        tops.push(c);
                        for (dx, dz) in [(r + 0.9, 0.0), (0.0, r + 0.9), (-r - 0.9, 0.0)] {
                            slots.push(Slot { pos: c + Vec3::new(dx, 0.0, dz), yaw: b.rng.range(0.0, TAU), max_h: 6.0, floor: true });
                        }
                    }
                    let y = b.rng.range(3.0, 4.5);
                    let r = 0.25;
                    for (a, c) in [(0, 1), (2, 3)] {
                        // x-aligned pipe between the tank centres.
                        let (p0, p1) = (tops[a], tops[c]);
                        b.push(pipe, trs(Vec3::new(p0.x, y, p0.z), 0.0, Vec3::new(p1.x - p0.x, r, r)), [0.6, 0.3, 0.15]);
                    }
                    b.push(pipe, trs(Vec3::new(tops[0].x, y + 0.8, tops[0].z), -FRAC_PI_2, Vec3::new(tops[2].z - tops[0].z, r, r)), [0.6, 0.3, 0.15]);
                }
                3 => {
                    // Pallet yard: a grid of floor spots, a forklift lane down the middle.
                    for u in 0..12 {
                        for v in 0..11 {
                            if v == 5 {
                                continue;
                            }
                            let p = o + Vec3::new(1.0 + u as f32 * 1.6, 0.0, 1.2 + v as f32 * 1.6 + if v > 5 { 0.8 } else { 0.0 });
                            slots.push(Slot { pos: p, yaw: 0.0, max_h: 6.0, floor: true });
                        }
                    }
                    let c = b.rng.color(&[[0.9, 0.7, 0.1]], 0.05);
                    let x = b.rng.range(3.0, 17.0);
                    b.push(machines[4], trs(o + Vec3::new(x, 0.0, 10.0), FRAC_PI_2, Vec3::ONE), c);
                }
                _ => {
                    // Assembly: three conveyor lines with robots beside them.
                    for line_i in 0..3 {
                        let z = z0 + 3.5 + line_i as f32 * 6.5;
                        for u in 0..3 {
                            b.push(conveyor_m, trs(Vec3::new(x0 + 4.0 + u as f32 * 6.0, 0.0, z), 0.0, Vec3::ONE), [0.3, 0.3, 0.32]);
                            let side = if u % 2 == 0 { 1.6 } else { -1.6 };
                            let color = b.rng.color(&[[0.9, 0.5, 0.1], [0.9, 0.8, 0.2]], 0.05);
                            b.push(robot_m, trs(Vec3::new(x0 + 4.0 + u as f32 * 6.0, 0.0, z + side), if side > 0.0 { -FRAC_PI_2 } else { FRAC_PI_2 }, Vec3::ONE), color);
                        }
                        for u in 0..5 {
                            slots.push(Slot { pos: Vec3::new(x0 + 2.5 + u as f32 * 3.8, 0.0, z - 2.2), yaw: 0.0, max_h: 6.0, floor: true });
                        }
                    }
                }
            }
        }
    }

    // Overhead pipe runs along some aisles, one object per bay length.
    for i in 0..=side {
        if !b.rng.chance(0.5) {
            continue;
        }
        let (y, r) = (b.rng.range(7.0, 9.5), b.rng.range(0.15, 0.4));
        let along_x = b.rng.chance(0.5);
        let color = b.rng.color(&[[0.6, 0.3, 0.15], [0.3, 0.5, 0.3], [0.7, 0.7, 0.7]], 0.05);
        for k in 0..side {
            let (a, c) = (line(k), line(k + 1));
            let m =
                if along_x { trs(Vec3::new(a, y, line(i) + 1.0), 0.0, Vec3::new(c - a, r, r)) } else { trs(Vec3::new(line(i) + 1.0, y, a), -FRAC_PI_2, Vec3::new(c - a, r, r)) };
            b.push(pipe, m, color);
        }
    }

    // Goods fill the slots (racks first come as they were made); when there
    // are more goods than slots, they stack on the floor spots.
    let left = b.left();
    let mut order = b.rng.sample_indices(slots.len(), left);
    let floor: Vec<usize> = (0..slots.len()).filter(|&i| slots[i].floor).collect();
    let mut tops: Vec<f32> = slots.iter().map(|s| s.pos.y).collect();
    while order.len() < left && !floor.is_empty() {
        order.push(floor[b.rng.below(floor.len())]);
    }
    let mut misses = 0;
    let mut k = 0;
    while b.left() > 0 {
        let s = if k < order.len() { order[k] } else { b.rng.below(slots.len().max(1)) };
        k += 1;
        let Some(slot) = slots.get(s) else {
            // No bays with goods (tiny scenes): crates along the walls.
            let m = trs(Vec3::new(b.rng.range(-half, half), 0.0, half - 1.0), 0.0, Vec3::ONE);
            b.push(goods[3].0, m, CARDBOARD[0]);
            continue;
        };
        let w: Vec<f32> = goods
            .iter()
            .map(|g| {
                if slot.floor {
                    g.3
                } else if g.1 <= slot.max_h {
                    g.2
                } else {
                    0.0
                }
            })
            .collect();
        let g = &goods[b.rng.weighted(&w)];
        let pos = Vec3::new(slot.pos.x, tops[s], slot.pos.z);
        let m = trs(pos, slot.yaw + b.rng.range(-0.05, 0.05), Vec3::ONE);
        if misses < 50 && clear.blocks(&b.bounds(g.0, &m)) {
            misses += 1;
            continue;
        }
        misses = 0;
        tops[s] += g.1;
        let color = b.rng.color(g.4, 0.1);
        b.push(g.0, m, color);
    }
    path
}
