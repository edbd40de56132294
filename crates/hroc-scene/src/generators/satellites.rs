//! `satellites`: a field of satellites, stations, rocks and panels of many
//! sizes and tessellation levels, with a few planet-sized bodies (the HROC
//! paper's ST). The path flies through the field and past the planets,
//! which hide large parts of it; the dense field hides the rest.

use glam::{Mat4, Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, TAU};

use super::rng::{hsv, Rng};
use super::shapes::{block, box_at, cone, cylinder, icosphere, rock, torus, uv_sphere, Part};
use super::{flight, walk_path, Builder, Clearance, Polyline};
use crate::CameraPath;

const CELL: f32 = 4.0;

fn panel_pair(span: f32, w: f32) -> Part {
    box_at(Vec3::new(-(0.6 + span * 0.5), 0.0, 0.0), Vec3::new(span, 0.04, w)).with(box_at(Vec3::new(0.6 + span * 0.5, 0.0, 0.0), Vec3::new(span, 0.04, w)))
}

fn satellite_a() -> Part {
    box_at(Vec3::ZERO, Vec3::new(1.0, 1.0, 1.4))
        .with(panel_pair(2.4, 0.9))
        .with(cone(0.45, 0.3, 12).rotated(Quat::from_rotation_x(-FRAC_PI_2)).at(Vec3::new(0.0, 0.0, 0.7)))
        .with(cylinder(0.03, 0.8, 5).at(Vec3::Y * 0.5))
}

fn satellite_b() -> Part {
    cylinder(0.6, 1.8, 16)
        .at(Vec3::Y * -0.9)
        .with(panel_pair(2.0, 0.7).rotated(Quat::from_rotation_y(0.0)).at(Vec3::Y * 0.5))
        .with(panel_pair(2.0, 0.7).rotated(Quat::from_rotation_y(FRAC_PI_2)).at(Vec3::Y * -0.5))
        .with(uv_sphere(0.35, 10, 5).at(Vec3::Y * 0.95))
}

fn station() -> Part {
    let module = |l: f32| cylinder(0.7, l, 20).rotated(Quat::from_rotation_z(FRAC_PI_2));
    module(6.0)
        .at(Vec3::X * 3.0)
        .with(module(2.5).rotated(Quat::from_rotation_y(FRAC_PI_2)).at(Vec3::new(0.0, 0.0, -1.25)))
        .with(uv_sphere(1.1, 16, 8))
        .with(torus(2.6, 0.25, 24, 6).rotated(Quat::from_rotation_z(FRAC_PI_2)).at(Vec3::X * -1.5))
        .with(box_at(Vec3::new(-4.2, 0.0, 0.0), Vec3::new(0.15, 5.0, 1.6)))
        .with(box_at(Vec3::new(1.5, 0.0, 3.0), Vec3::new(1.8, 0.05, 3.5)))
}

fn planet_ring() -> Part {
    // A flat ring: a torus squashed to a disc.
    torus(1.8, 0.35, 64, 6).scaled(Vec3::new(1.0, 0.05, 1.0))
}

struct Kind {
    mesh: u32,
    weight: f32,
    /// Size range (largest extent, metres) and whether it spins freely.
    size: (f32, f32),
    hue: Option<f32>,
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    let planets = (n / 5_000).clamp(2, 10).min(n);
    let gx = (((n as f32 * 1.2) / 0.33).cbrt().ceil() as usize).max(4);
    let gy = ((gx as f32 * 0.33).round() as usize).max(2);
    let half = Vec3::new(gx as f32, gy as f32, gx as f32) * CELL * 0.5;
    let pts = flight(&mut b.rng, half, 25);
    let path = walk_path(pts.clone(), 20.0, 31);
    let clear = Clearance::new(&[&path], 5.0, 5.0, 5.0);

    // Planets beside the flight, mostly on the inner side of the loop where
    // the view looks, close enough to fill much of it when passed.
    let line = Polyline::new(pts);
    let mut bodies = vec![];
    let mut ringed = false;
    let planet_mesh = b.mesh("planet", uv_sphere(1.0, 64, 32));
    let ring_mesh = b.mesh("planet-ring", planet_ring());
    for i in 0..planets {
        let s = line.length() * (i as f32 + 0.6) / planets as f32;
        let p = line.at(s);
        let dir = (line.at(s + 1.0) - p).normalize_or_zero();
        let mut side = dir.cross(Vec3::Y).normalize_or_zero();
        if (side.dot(-p) < 0.0) != (i % 3 == 2) {
            side = -side;
        }
        let mut r = half.y * b.rng.range(0.5, 0.9);
        let gap = b.rng.range(8.0, 20.0);
        let lift = b.rng.range(-0.3, 0.3);
        // The flight curves back: shrink the planet until it clears all of it.
        let mut c = p;
        for _ in 0..16 {
            c = p + side * (r + gap) + Vec3::Y * lift * r;
            if line.distance(c) >= r + 8.0 {
                break;
            }
            r *= 0.85;
        }
        bodies.push((c, r));
        let color = hsv(b.rng.f32(), b.rng.range(0.3, 0.7), b.rng.range(0.5, 0.8));
        b.push(planet_mesh, Mat4::from_scale_rotation_translation(Vec3::splat(r), Quat::IDENTITY, c), color);
        // One planet gets a ring, facing the flight (so it reaches away from
        // it): the first whose ring clears the flight.
        let ring = Mat4::from_scale_rotation_translation(Vec3::splat(r), Quat::from_rotation_arc(Vec3::Y, side) * Quat::from_rotation_x(0.25), c);
        if !ringed && b.left() > 0 && !clear.blocks(&b.bounds(ring_mesh, &ring)) {
            ringed = true;
            let c2 = b.rng.tint([0.75, 0.7, 0.6], 0.1);
            b.push(ring_mesh, ring, c2);
        }
    }

    // Small bodies: detail grows with size (the paper's varied detail).
    let mut rr = Rng::new(b.rng.next_u64());
    let kinds = [
        Kind { mesh: b.mesh("sat-a", satellite_a()), weight: 3.0, size: (1.5, 4.5), hue: None },
        Kind { mesh: b.mesh("sat-b", satellite_b()), weight: 2.0, size: (1.5, 4.5), hue: None },
        Kind { mesh: b.mesh("station", station()), weight: 0.15, size: (6.0, 12.0), hue: None },
        Kind { mesh: b.mesh("rock-1", rock(1, 0.4, &mut rr)), weight: 3.0, size: (0.6, 2.0), hue: Some(0.08) },
        Kind { mesh: b.mesh("rock-2", rock(2, 0.4, &mut rr)), weight: 0.8, size: (1.5, 3.5), hue: Some(0.08) },
        Kind { mesh: b.mesh("rock-3", rock(3, 0.45, &mut rr)), weight: 0.1, size: (3.5, 8.0), hue: Some(0.06) },
        Kind { mesh: b.mesh("ico-0", icosphere(0)), weight: 2.0, size: (0.6, 1.5), hue: Some(-1.0) },
        Kind { mesh: b.mesh("ico-1", icosphere(1)), weight: 1.5, size: (1.0, 3.0), hue: Some(-1.0) },
        Kind { mesh: b.mesh("ico-2", icosphere(2)), weight: 0.4, size: (2.5, 4.5), hue: Some(-1.0) },
        Kind { mesh: b.mesh("box", block(1.0, 1.0, 1.0)), weight: 2.0, size: (0.8, 3.0), hue: Some(-1.0) },
        Kind { mesh: b.mesh("panel", box_at(Vec3::ZERO, Vec3::new(1.0, 0.03, 0.6))), weight: 1.5, size: (1.5, 4.5), hue: Some(0.62) },
        Kind { mesh: b.mesh("ring", torus(1.0, 0.12, 16, 6)), weight: 0.4, size: (1.5, 4.0), hue: Some(-1.0) },
    ];
    let weights: Vec<f32> = kinds.iter().map(|k| k.weight).collect();
    let cells_total = gx * gy * gx;
    let mut cells: Vec<u32> = (0..cells_total as u32).collect();
    b.rng.shuffle(&mut cells);
    let mut next = 0usize;
    while b.left() > 0 {
        let (c, round) = (cells[next % cells_total] as usize, next / cells_total);
        next += 1;
        let cell = Vec3::new((c % gx) as f32, (c / gx % gy) as f32, (c / (gx * gy)) as f32);
        let pos = -half + (cell + Vec3::splat(0.5) + (Vec3::new(b.rng.f32(), b.rng.f32(), b.rng.f32()) - 0.5) * 0.6) * CELL;
        let k = &kinds[b.rng.weighted(&weights)];
        let size = b.rng.log_range(k.size.0, k.size.1) * 1.2;
        let mesh_size = b.scene.meshes[k.mesh as usize].bounds.extent().max_element();
        let rot = Quat::from_axis_angle(b.rng.unit_vec3(), b.rng.range(0.0, TAU));
        let m = Mat4::from_scale_rotation_translation(Vec3::splat(size / mesh_size), rot, pos);
        let bx = b.bounds(k.mesh, &m);
        let in_planet = bodies.iter().any(|&(c, r)| c.distance(pos) < r + size);
        if round < 3 && (in_planet || clear.blocks(&bx)) {
            continue;
        }
        let color = match k.hue {
            None => b.rng.color(&[[0.8, 0.78, 0.7], [0.85, 0.65, 0.2], [0.7, 0.72, 0.75], [0.9, 0.9, 0.92]], 0.1),
            Some(h) if h < 0.0 => hsv(b.rng.f32(), b.rng.range(0.2, 0.7), b.rng.range(0.5, 0.9)),
            Some(h) => hsv(h + b.rng.range(-0.03, 0.03), b.rng.range(0.2, 0.6), b.rng.range(0.3, 0.6)),
        };
        b.push(k.mesh, m, color);
    }
    path
}
