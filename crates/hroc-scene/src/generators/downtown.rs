//! `downtown`: a street grid whose blocks are filled with buildings of
//! varied heights, with street furniture and cars (the IOC poster's DT).
//! At eye level the buildings lining a street hide every other street; the
//! path drives along streets and turns at intersections.

use glam::{Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

use super::rng::Rng;
use super::shapes::{block, box_at, cylinder, gable, icosphere, pyramid};
use super::{grid_walk, trs, walk_path, Builder, Clearance};
use crate::CameraPath;

const STREET: f32 = 12.0;
const SIDEWALK: f32 = 3.0;
const EYE: f32 = 1.7;
/// Objects per block on average (buildings, sidewalk, roads, street furniture).
const PER_BLOCK: f32 = 44.0;

const CONCRETE: &[[f32; 3]] = &[[0.6, 0.6, 0.6], [0.5, 0.5, 0.52], [0.72, 0.7, 0.66], [0.4, 0.42, 0.45]];
const BRICK: &[[f32; 3]] = &[[0.55, 0.25, 0.18], [0.65, 0.35, 0.25], [0.45, 0.2, 0.15]];
const GLASS: &[[f32; 3]] = &[[0.3, 0.45, 0.55], [0.25, 0.35, 0.45], [0.4, 0.55, 0.6]];
const PLASTER: &[[f32; 3]] = &[[0.85, 0.8, 0.65], [0.8, 0.7, 0.55], [0.9, 0.88, 0.8]];
const CAR: &[[f32; 3]] = &[[0.7, 0.1, 0.1], [0.1, 0.2, 0.6], [0.85, 0.85, 0.85], [0.1, 0.1, 0.1], [0.6, 0.6, 0.62], [0.9, 0.75, 0.1], [0.2, 0.45, 0.25]];
const METAL: &[[f32; 3]] = &[[0.3, 0.32, 0.3], [0.2, 0.22, 0.25]];
const LEAF: &[[f32; 3]] = &[[0.2, 0.45, 0.15], [0.3, 0.5, 0.2], [0.25, 0.4, 0.1]];
const WOOD: &[[f32; 3]] = &[[0.5, 0.35, 0.2]];

/// Buildings: unit footprint [-0.5, 0.5]^2, height [0, 1], scaled per lot.
fn building_meshes(b: &mut Builder) -> Vec<(u32, f32, bool)> {
    // (mesh, weight, low-rise only)
    let plain = block(1.0, 1.0, 1.0);
    let roof_box = block(1.0, 0.97, 1.0).with(block(0.4, 0.03, 0.3).at(Vec3::new(0.15, 0.97, -0.1)));
    let setback = block(1.0, 0.6, 1.0).with(block(0.8, 0.25, 0.8).at(Vec3::Y * 0.6)).with(block(0.55, 0.15, 0.55).at(Vec3::Y * 0.85));
    let mut ledges = block(0.94, 1.0, 0.94);
    for i in 1..7 {
        ledges.append(&block(1.0, 0.012, 1.0).at(Vec3::Y * (i as f32 / 7.0)));
    }
    let house = block(1.0, 0.7, 1.0).with(gable().scaled(Vec3::new(1.02, 0.3, 1.02)).at(Vec3::Y * 0.7));
    let l_shape = block(1.0, 1.0, 0.5).at(Vec3::Z * -0.25).with(block(0.5, 0.7, 0.5).at(Vec3::new(-0.25, 0.0, 0.25)));
    let spire = block(1.0, 0.9, 1.0).with(pyramid(4, 0.5, 0.1).rotated(Quat::from_rotation_y(PI / 4.0)).at(Vec3::Y * 0.9));
    vec![
        (b.mesh("building-box", plain), 1.0, false),
        (b.mesh("building-roof", roof_box), 1.0, false),
        (b.mesh("building-setback", setback), 0.7, false),
        (b.mesh("building-ledges", ledges), 0.6, false),
        (b.mesh("house", house), 1.0, true),
        (b.mesh("building-l", l_shape), 0.5, true),
        (b.mesh("tower-spire", spire), 0.3, false),
    ]
}

struct Prop {
    mesh: u32,
    weight: f32,
    on_road: bool,
    colors: &'static [[f32; 3]],
}

fn prop_meshes(b: &mut Builder) -> Vec<Prop> {
    let lamp = cylinder(0.08, 6.0, 6).with(box_at(Vec3::new(0.0, 6.0, 0.7), Vec3::new(0.12, 0.1, 1.5))).with(box_at(Vec3::new(0.0, 5.9, 1.35), Vec3::new(0.3, 0.15, 0.5)));
    let tree = cylinder(0.18, 2.5, 6).with(icosphere(1).scaled(Vec3::new(2.2, 2.6, 2.2)).at(Vec3::Y * 4.2));
    let bench = block(1.8, 0.06, 0.5)
        .at(Vec3::Y * 0.45)
        .with(box_at(Vec3::new(0.0, 0.75, -0.22), Vec3::new(1.8, 0.4, 0.05)))
        .with(block(0.08, 0.45, 0.45).at(Vec3::X * -0.8))
        .with(block(0.08, 0.45, 0.45).at(Vec3::X * 0.8));
    // Wheel centred on its axle, axle along x.
    let wheel = cylinder(0.33, 0.22, 8).at(Vec3::Y * -0.11).rotated(Quat::from_rotation_z(FRAC_PI_2));
    let mut car = block(1.8, 0.7, 4.3).at(Vec3::Y * 0.3).with(block(1.6, 0.55, 2.2).at(Vec3::new(0.0, 1.0, -0.2)));
    for (x, z) in [(-0.8, -1.4), (0.8, -1.4), (-0.8, 1.4), (0.8, 1.4)] {
        car.append(&wheel.clone().at(Vec3::new(x * 1.125, 0.33, z)));
    }
    let mut van = block(2.1, 2.2, 6.0).at(Vec3::Y * 0.4).with(block(2.1, 1.2, 1.2).at(Vec3::new(0.0, 0.4, 3.5)));
    for (x, z) in [(-0.95, -2.0), (0.95, -2.0), (-0.95, 3.3), (0.95, 3.3)] {
        van.append(&wheel.clone().scaled(Vec3::splat(1.2)).at(Vec3::new(x * 1.105, 0.4, z)));
    }
    let bin = cylinder(0.3, 0.9, 10);
    let hydrant = cylinder(0.15, 0.6, 8).with(cylinder(0.1, 0.2, 8).at(Vec3::Y * 0.6)).with(box_at(Vec3::Y * 0.4, Vec3::new(0.45, 0.1, 0.1)));
    let signal = cylinder(0.1, 3.5, 6).with(box_at(Vec3::new(0.0, 3.8, 0.0), Vec3::new(0.4, 1.1, 0.35)));
    let kiosk = block(2.0, 2.5, 1.6).with(block(2.4, 0.1, 2.0).at(Vec3::Y * 2.5));
    let planter = block(1.2, 0.5, 1.2).with(icosphere(1).scaled(Vec3::new(0.55, 0.5, 0.55)).at(Vec3::Y * 0.7));
    vec![
        Prop { mesh: b.mesh("streetlight", lamp), weight: 2.0, on_road: false, colors: METAL },
        Prop { mesh: b.mesh("street-tree", tree), weight: 2.5, on_road: false, colors: LEAF },
        Prop { mesh: b.mesh("bench", bench), weight: 0.8, on_road: false, colors: WOOD },
        Prop { mesh: b.mesh("car", car), weight: 3.0, on_road: true, colors: CAR },
        Prop { mesh: b.mesh("van", van), weight: 0.6, on_road: true, colors: CAR },
        Prop { mesh: b.mesh("bin", bin), weight: 0.8, on_road: false, colors: METAL },
        Prop { mesh: b.mesh("hydrant", hydrant), weight: 0.5, on_road: false, colors: &[[0.8, 0.1, 0.1]] },
        Prop { mesh: b.mesh("signal", signal), weight: 0.5, on_road: false, colors: METAL },
        Prop { mesh: b.mesh("kiosk", kiosk), weight: 0.3, on_road: false, colors: PLASTER },
        Prop { mesh: b.mesh("planter", planter), weight: 0.6, on_road: false, colors: LEAF },
    ]
}

/// Street centre lines: `count + 1` lines, blocks of varied size between.
fn street_lines(rng: &mut Rng, count: usize) -> Vec<f32> {
    let mut v = vec![0.0f32];
    for _ in 0..count {
        v.push(v.last().unwrap() + STREET + rng.range(40.0, 64.0));
    }
    let mid = v[count] * 0.5;
    v.iter().map(|x| x - mid).collect()
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let side = ((b.n as f32 / PER_BLOCK).sqrt().round() as usize).max(1);
    let xs = street_lines(&mut b.rng, side);
    let zs = street_lines(&mut b.rng, side);
    let centre_r = (xs[side] - xs[0]).max(zs[side] - zs[0]) * 0.5;

    let (lo, hi) = if side >= 3 { (1, side - 1) } else { (0, side) };
    let inter = grid_walk(&mut b.rng, lo, hi, 6);
    let pts: Vec<Vec3> = inter.iter().map(|&(i, j)| Vec3::new(xs[i], EYE, zs[j])).collect();
    let path = if pts.len() == 1 {
        // One block: circle it.
        let (x0, x1, z0, z1) = (xs[0], xs[side], zs[0], zs[side]);
        walk_path(vec![Vec3::new(x0, EYE, z0), Vec3::new(x1, EYE, z0), Vec3::new(x1, EYE, z1), Vec3::new(x0, EYE, z1), Vec3::new(x0, EYE, z0 + 1.0)], 15.0, 21)
    } else {
        walk_path(pts, 15.0, 25)
    };
    let clear = Clearance::new(&[&path], 1.2, EYE, 2.0);

    let unit = b.mesh("unit-box", block(1.0, 1.0, 1.0));
    let buildings = building_meshes(b);
    let props = prop_meshes(b);

    // Roads: one slab per street segment; north-south ones run through the
    // intersections.
    let road = [0.18, 0.18, 0.2];
    for i in 0..=side {
        for j in 0..side {
            let (z0, z1) = (zs[j] - STREET * 0.5, zs[j + 1] + STREET * 0.5);
            b.push(unit, trs(Vec3::new(xs[i], -0.1, (z0 + z1) * 0.5), 0.0, Vec3::new(STREET, 0.1, z1 - z0)), road);
            let (x0, x1) = (xs[j] + STREET * 0.5, xs[j + 1] - STREET * 0.5);
            b.push(unit, trs(Vec3::new((x0 + x1) * 0.5, -0.1, zs[i]), 0.0, Vec3::new(x1 - x0, 0.1, STREET)), road);
        }
    }

    // Blocks: a sidewalk slab, then buildings on a grid of lots.
    let mut blocks = vec![];
    for j in 0..side {
        for i in 0..side {
            let (x0, x1) = (xs[i] + STREET * 0.5, xs[i + 1] - STREET * 0.5);
            let (z0, z1) = (zs[j] + STREET * 0.5, zs[j + 1] - STREET * 0.5);
            blocks.push((x0, x1, z0, z1));
            let c = b.rng.tint([0.6, 0.6, 0.58], 0.05);
            b.push(unit, trs(Vec3::new((x0 + x1) * 0.5, 0.0, (z0 + z1) * 0.5), 0.0, Vec3::new(x1 - x0, 0.15, z1 - z0)), c);
            let (ix0, ix1, iz0, iz1) = (x0 + SIDEWALK, x1 - SIDEWALK, z0 + SIDEWALK, z1 - SIDEWALK);
            let kx = ((ix1 - ix0) / 14.0).round().max(1.0) as usize;
            let kz = ((iz1 - iz0) / 14.0).round().max(1.0) as usize;
            let (lw, ld) = ((ix1 - ix0) / kx as f32, (iz1 - iz0) / kz as f32);
            let mid = Vec3::new((x0 + x1) * 0.5, 0.0, (z0 + z1) * 0.5);
            // Taller buildings towards the city centre.
            let core = (1.0 - mid.length() / centre_r.max(1.0)).clamp(0.0, 1.0);
            for lz in 0..kz {
                for lx in 0..kx {
                    let gap = Vec3::new(b.rng.range(0.4, 2.0), 0.0, b.rng.range(0.4, 2.0));
                    let pos = Vec3::new(ix0 + (lx as f32 + 0.5) * lw, 0.15, iz0 + (lz as f32 + 0.5) * ld);
                    let mut h = 6.0 + 30.0 * b.rng.f32().powi(2) * (0.4 + core);
                    if b.rng.chance(0.04 + 0.15 * core * core) {
                        h = b.rng.range(60.0, 160.0) * (0.5 + core);
                    }
                    let low = h < 14.0;
                    let weights: Vec<f32> = buildings.iter().map(|&(_, w, only_low)| if only_low && !low { 0.0 } else { w }).collect();
                    let mesh = buildings[b.rng.weighted(&weights)].0;
                    let palette = match b.rng.below(4) {
                        0 => BRICK,
                        1 if h > 30.0 => GLASS,
                        2 => PLASTER,
                        _ => CONCRETE,
                    };
                    let color = b.rng.color(palette, 0.1);
                    let yaw = b.rng.below(4) as f32 * FRAC_PI_2;
                    let (sx, sz) = if yaw.sin().abs() > 0.5 { (ld, lw) } else { (lw, ld) };
                    b.push(mesh, trs(pos, yaw, Vec3::new(sx - gap.x, h, sz - gap.z)), color);
                }
            }
        }
    }

    // Street furniture on the sidewalks, cars and vans in the lanes.
    let weights: Vec<f32> = props.iter().map(|p| p.weight).collect();
    let mut misses = 0;
    while b.left() > 0 {
        let p = &props[b.rng.weighted(&weights)];
        let (pos, yaw) = if p.on_road {
            let i = b.rng.below(side + 1);
            let along = b.rng.range(zs[0], zs[side]);
            let lane = if b.rng.chance(0.5) { 3.0 } else { -3.0 };
            let yaw = if lane > 0.0 { 0.0 } else { PI };
            if b.rng.chance(0.5) {
                (Vec3::new(xs[i] + lane, 0.0, along), yaw)
            } else {
                (Vec3::new(along, 0.0, zs[i] + lane), yaw + FRAC_PI_2)
            }
        } else {
            let (x0, x1, z0, z1) = blocks[b.rng.below(blocks.len())];
            // A point 1.2 m inside the kerb, facing the street.
            let inset = 1.2;
            match b.rng.below(4) {
                0 => (Vec3::new(b.rng.range(x0 + inset, x1 - inset), 0.15, z0 + inset), PI),
                1 => (Vec3::new(b.rng.range(x0 + inset, x1 - inset), 0.15, z1 - inset), 0.0),
                2 => (Vec3::new(x0 + inset, 0.15, b.rng.range(z0 + inset, z1 - inset)), -FRAC_PI_2),
                _ => (Vec3::new(x1 - inset, 0.15, b.rng.range(z0 + inset, z1 - inset)), FRAC_PI_2),
            }
        };
        let m = trs(pos, yaw, Vec3::ONE);
        if clear.blocks(&b.bounds(p.mesh, &m)) && misses < 100 {
            misses += 1;
            continue;
        }
        misses = 0;
        let color = b.rng.color(p.colors, 0.12);
        b.push(p.mesh, m, color);
    }
    path
}
