//! `fantasy` (HROC's FN): few but very detailed objects, hundreds to
//! thousands of triangles each: conifers and broadleaf trees, boulders and
//! mounds, mushrooms, crystals, fluted pillars, ruined arches and orbs on a
//! rolling ground. The path walks a winding trail at eye level; trees,
//! mounds and boulders hide most of the land beyond a few dozen metres.

use glam::{Quat, Vec3};
use std::f32::consts::{PI, TAU};

use super::rng::Rng;
use super::shapes::{cylinder, frustum, heightfield, lathe, prism, pyramid, rock, torus_arc, uv_sphere, Part};
use super::{trs, walk_path, Builder, Clearance};
use crate::CameraPath;

const CELL: f32 = 6.0;
const TILE: f32 = 30.0;
const EYE: f32 = 1.7;

/// Conifer: trunk and a jagged stack of tiers, one lathe (~1000 triangles).
fn conifer() -> Part {
    let mut prof = vec![[0.0, 0.4]];
    let tiers = 6;
    for i in 0..tiers {
        let y = 0.4 + i as f32 * 0.55;
        let r = 1.0 - i as f32 / tiers as f32 * 0.85;
        prof.extend([[r, y], [r * 0.95, y + 0.08], [r * 0.45, y + 0.5]]);
    }
    prof.push([0.0, 0.4 + tiers as f32 * 0.55 + 0.3]);
    lathe(&prof, 32).with(cylinder(0.12, 0.5, 12))
}

/// Broadleaf: lathed trunk with flare and a crown of lumpy spheres.
fn broadleaf(rng: &mut Rng) -> Part {
    let mut p = lathe(&[[0.0, 0.0], [0.35, 0.0], [0.35, 0.0], [0.22, 0.3], [0.16, 1.0], [0.14, 2.0], [0.1, 2.6], [0.0, 2.7]], 16);
    for _ in 0..4 {
        let c = Vec3::new(rng.range(-0.8, 0.8), rng.range(2.6, 3.6), rng.range(-0.8, 0.8));
        p.append(&rock(2, 0.25, rng).scaled(Vec3::splat(rng.range(0.9, 1.4))).at(c));
    }
    p
}

fn mushroom() -> Part {
    lathe(
        &[
            [0.0, 0.0],
            [0.25, 0.0],
            [0.25, 0.0],
            [0.2, 0.3],
            [0.18, 0.9],
            [0.22, 1.2],
            [0.3, 1.25],
            [0.3, 1.25],
            [0.9, 1.2],
            [1.0, 1.3],
            [0.95, 1.5],
            [0.75, 1.7],
            [0.45, 1.82],
            [0.0, 1.86],
        ],
        32,
    )
}

fn crystals(rng: &mut Rng) -> Part {
    let mut p = Part::new();
    for _ in 0..6 {
        let h = rng.range(0.8, 2.0);
        let c = prism(6, 0.18, h).with(pyramid(6, 0.18, 0.35).at(Vec3::Y * h));
        let q = Quat::from_rotation_z(rng.range(-0.5, 0.5)) * Quat::from_rotation_x(rng.range(-0.5, 0.5));
        p.append(&c.rotated(q).at(Vec3::new(rng.range(-0.4, 0.4), 0.0, rng.range(-0.4, 0.4))));
    }
    p
}

/// Fluted column on a stepped base.
fn pillar() -> Part {
    let segs = 48;
    let mut p = Part::new();
    let rings = 10;
    for i in 0..=rings {
        let y = 0.3 + i as f32 / rings as f32 * 4.0;
        for j in 0..=segs {
            let a = j as f32 / segs as f32 * TAU;
            let r = 0.4 * (1.0 - 0.06 * (a * 12.0).cos().max(0.0));
            let (s, c) = a.sin_cos();
            p.vertex(Vec3::new(r * s, y, r * c), Vec3::new(s, 0.0, c));
        }
    }
    let w = segs + 1;
    for i in 0..rings {
        for j in 0..segs {
            let a = i * w + j;
            p.quad(a, a + 1, a + w + 1, a + w);
        }
    }
    p.recompute_normals();
    p.with(frustum(0.6, 0.55, 0.3, 24)).with(frustum(0.55, 0.6, 0.3, 24).at(Vec3::Y * 4.3))
}

/// A ruined arch: half a torus on two columns.
fn arch() -> Part {
    let legs = cylinder(0.45, 3.0, 24).at(Vec3::X * -2.5).with(cylinder(0.45, 3.0, 24).at(Vec3::X * 2.5));
    let top = torus_arc(2.5, 0.45, 48, 16, -PI * 0.5, PI * 0.5).rotated(Quat::from_rotation_x(-PI * 0.5)).at(Vec3::Y * 3.0);
    legs.with(top)
}

fn orb() -> Part {
    frustum(0.7, 0.5, 0.8, 24).with(uv_sphere(0.9, 48, 24).at(Vec3::Y * 1.6))
}

/// Gentle bumps that vanish on the patch border, so patches tile.
fn ground_patch(rng: &mut Rng) -> Part {
    let bumps: Vec<(f32, f32, f32)> = (0..6).map(|_| (rng.range(1.0, 3.0), rng.range(1.0, 3.0), rng.range(-0.2, 0.2))).collect();
    heightfield(24, move |x, z| {
        let (u, v) = (x + 0.5, z + 0.5);
        let edge = (u * (1.0 - u) * v * (1.0 - v) * 16.0).min(1.0);
        edge * bumps.iter().map(|&(fx, fz, a)| a * (u * fx * PI).sin() * (v * fz * PI).sin()).sum::<f32>()
    })
    .scaled(Vec3::new(TILE, 1.0, TILE))
}

struct Kind {
    mesh: u32,
    weight: f32,
    /// Size (scale) range and how far it sinks into the ground (fraction of height).
    scale: (f32, f32),
    sink: f32,
    colors: &'static [[f32; 3]],
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    let g = (((n as f32) * 1.2).sqrt().ceil() as usize).max(3);
    let half = g as f32 * CELL * 0.5;

    // Trail: most of a winding loop around the middle of the land, so the
    // view runs across it, never out of it.
    let pts: Vec<Vec3> = super::flight(&mut b.rng, Vec3::new(half, 0.0, half), 31).into_iter().map(|p| Vec3::new(p.x, EYE, p.z)).collect();
    let path = walk_path(pts, 8.0, 31);
    let clear = Clearance::new(&[&path], 1.5, EYE - 0.5, 2.0);

    let mut rr = Rng::new(b.rng.next_u64());
    let ground = b.mesh("ground-patch", ground_patch(&mut rr));
    let tiles = ((2.0 * half) / TILE).ceil() as usize;
    for i in 0..tiles {
        for j in 0..tiles {
            let c = Vec3::new(-half + (i as f32 + 0.5) * TILE, 0.0, -half + (j as f32 + 0.5) * TILE);
            let color = b.rng.tint([0.3, 0.42, 0.2], 0.06);
            b.push(ground, trs(c, 0.0, Vec3::ONE), color);
        }
    }

    const NEEDLES: &[[f32; 3]] = &[[0.2, 0.35, 0.18], [0.15, 0.3, 0.2], [0.25, 0.4, 0.15]];
    const LEAF: &[[f32; 3]] = &[[0.35, 0.5, 0.15], [0.55, 0.45, 0.15], [0.4, 0.55, 0.2], [0.6, 0.3, 0.1]];
    const STONE: &[[f32; 3]] = &[[0.5, 0.48, 0.45], [0.42, 0.4, 0.38], [0.55, 0.5, 0.42]];
    const MOSS: &[[f32; 3]] = &[[0.3, 0.4, 0.2], [0.25, 0.35, 0.2]];
    const CAP: &[[f32; 3]] = &[[0.8, 0.15, 0.1], [0.6, 0.3, 0.6], [0.9, 0.7, 0.3]];
    const GEM: &[[f32; 3]] = &[[0.4, 0.8, 0.9], [0.7, 0.4, 0.9], [0.9, 0.5, 0.7]];
    const MARBLE: &[[f32; 3]] = &[[0.85, 0.83, 0.78], [0.75, 0.72, 0.68]];
    const ORB: &[[f32; 3]] = &[[0.9, 0.8, 0.3], [0.3, 0.6, 0.9]];
    let kinds = [
        Kind { mesh: b.mesh("conifer", conifer()), weight: 0.35, scale: (2.2, 4.0), sink: 0.0, colors: NEEDLES },
        Kind { mesh: b.mesh("broadleaf-a", broadleaf(&mut rr)), weight: 0.08, scale: (1.4, 2.4), sink: 0.0, colors: LEAF },
        Kind { mesh: b.mesh("broadleaf-b", broadleaf(&mut rr)), weight: 0.07, scale: (1.4, 2.4), sink: 0.0, colors: LEAF },
        Kind { mesh: b.mesh("boulder-a", rock(3, 0.5, &mut rr)), weight: 0.1, scale: (1.2, 3.0), sink: 0.25, colors: STONE },
        Kind { mesh: b.mesh("boulder-b", rock(3, 0.6, &mut rr)), weight: 0.1, scale: (1.2, 3.0), sink: 0.25, colors: STONE },
        Kind { mesh: b.mesh("bush", rock(2, 0.35, &mut rr)), weight: 0.15, scale: (1.0, 2.0), sink: 0.3, colors: MOSS },
        Kind { mesh: b.mesh("mushroom", mushroom()), weight: 0.08, scale: (0.8, 2.5), sink: 0.0, colors: CAP },
        Kind { mesh: b.mesh("crystals", crystals(&mut rr)), weight: 0.03, scale: (0.8, 2.0), sink: 0.05, colors: GEM },
        Kind { mesh: b.mesh("pillar", pillar()), weight: 0.05, scale: (0.8, 1.4), sink: 0.0, colors: MARBLE },
        Kind { mesh: b.mesh("arch", arch()), weight: 0.03, scale: (0.8, 1.2), sink: 0.0, colors: MARBLE },
        Kind { mesh: b.mesh("orb", orb()), weight: 0.02, scale: (0.8, 1.5), sink: 0.0, colors: ORB },
        Kind { mesh: b.mesh("mound", rock(4, 0.4, &mut rr).scaled(Vec3::new(1.0, 0.6, 1.0))), weight: 0.04, scale: (5.0, 9.0), sink: 0.3, colors: MOSS },
    ];
    let weights: Vec<f32> = kinds.iter().map(|k| k.weight).collect();

    let mut cells: Vec<u32> = (0..(g * g) as u32).collect();
    b.rng.shuffle(&mut cells);
    let mut next = 0;
    while b.left() > 0 {
        let (c, round) = (cells[next % cells.len()] as usize, next / cells.len());
        next += 1;
        let k = &kinds[b.rng.weighted(&weights)];
        let s = b.rng.range(k.scale.0, k.scale.1);
        let mb = b.scene.meshes[k.mesh as usize].bounds;
        let jitter = b.rng.vec2(-0.3, 0.3) * CELL;
        // Bottom on the ground, then sunk by `sink` of the height.
        let y = (-mb.min.y - k.sink * mb.extent().y) * s;
        let pos = Vec3::new(-half + ((c % g) as f32 + 0.5) * CELL + jitter.x, y, -half + ((c / g) as f32 + 0.5) * CELL + jitter.y);
        let m = trs(pos, b.rng.range(0.0, TAU), Vec3::splat(s));
        if round < 4 && clear.blocks(&b.bounds(k.mesh, &m)) {
            continue;
        }
        let color = b.rng.color(k.colors, 0.1);
        b.push(k.mesh, m, color);
    }
    path
}
