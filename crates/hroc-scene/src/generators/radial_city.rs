//! `radial-city` (HROC's RC): many low-poly buildings in rings around a
//! central plaza, cut by ring roads and radial spokes; towers near the centre
//! rise far above everything and hide the streets behind them. The path walks
//! a ring road at eye level, then turns into a spoke towards the towers.
//! `radial-city-fast` (RC') is the same city, walked backwards along a spoke
//! while the view swings quickly from side to side and spins once.

use glam::{Quat, Vec3};
use std::f32::consts::{PI, TAU};

use super::shapes::{block, cone, cylinder, gable, pyramid};
use super::{key, trs, walk_path, Builder, Clearance};
use crate::CameraPath;

const ROAD: f32 = 14.0;
const PLAZA: f32 = 50.0;
const BAND: f32 = 70.0;
const SETBACK: f32 = 3.0;
/// Spokes that run uninterrupted from the plaza to the edge.
const MAIN_SPOKES: usize = 8;
const EYE: f32 = 1.7;

struct Lot {
    pos: Vec3,
    yaw: f32,
    size: Vec3,
    tall: bool,
}

/// Position at radius `r`, angle `a` (0 on +Z, growing towards +X).
fn polar(r: f32, a: f32) -> Vec3 {
    Vec3::new(r * a.sin(), 0.0, r * a.cos())
}

fn ring_radius(k: usize) -> f32 {
    PLAZA + BAND * k as f32
}

/// Spokes through band `k` (between ring roads k and k + 1): sectors stay
/// about 90 m long, and the main spokes run through every band.
fn spokes_in_band(k: usize) -> usize {
    let mid = (ring_radius(k) + ring_radius(k + 1)) * 0.5;
    MAIN_SPOKES * ((TAU * mid / 90.0 / MAIN_SPOKES as f32).round() as usize).max(1)
}

/// True when a ground point lies on a road (or within `margin` of one).
fn on_road(p: Vec3, margin: f32) -> bool {
    let r = p.x.hypot(p.z);
    if r < PLAZA {
        return false;
    }
    let k = ((r - PLAZA) / BAND).round();
    if (r - PLAZA - k * BAND).abs() < ROAD * 0.5 + margin {
        return true;
    }
    let spokes = spokes_in_band(((r - PLAZA) / BAND).floor() as usize) as f32;
    let a = p.x.atan2(p.z).rem_euclid(TAU);
    let nearest = (a * spokes / TAU).round() * TAU / spokes;
    ((a - nearest) * r).abs() < ROAD * 0.5 + margin
}

pub(super) fn build(b: &mut Builder, fast: bool) -> CameraPath {
    let n = b.n;
    let want_buildings = ((n as f32 * 0.78).round() as usize).max(1);

    // Lots band by band until there are enough; bands are split into
    // sectors by spokes, each sector holds an inner and an outer row of lots.
    let tower_scale = 2.5 * BAND;
    let mut lots: Vec<Lot> = vec![];
    let mut bands = 0;
    while lots.len() < want_buildings {
        let (r_in, r_out) = (ring_radius(bands) + ROAD * 0.5, ring_radius(bands + 1) - ROAD * 0.5);
        let spokes = spokes_in_band(bands);
        let depth = (r_out - r_in) * 0.5 - SETBACK - 1.0;
        for j in 0..spokes {
            let (a0, a1) = (j as f32 / spokes as f32 * TAU, (j + 1) as f32 / spokes as f32 * TAU);
            for outer in [false, true] {
                let rho = if outer { r_out - SETBACK - depth * 0.5 } else { r_in + SETBACK + depth * 0.5 };
                let start = a0 * rho + ROAD * 0.5 + SETBACK;
                let end = a1 * rho - ROAD * 0.5 - SETBACK;
                let mut s = start;
                while end - s > 8.0 {
                    let w = b.rng.range(10.0, 22.0).min(end - s);
                    let gap = b.rng.range(1.0, 3.0);
                    let d = depth * b.rng.range(0.6, 1.0);
                    let r = if outer { r_out - SETBACK - d * 0.5 } else { r_in + SETBACK + d * 0.5 };
                    let a = (s + w * 0.5) / rho;
                    let centre = (r - PLAZA).max(0.0);
                    let tall_h = 240.0 * (-centre / tower_scale).exp() * b.rng.range(0.35, 1.0);
                    let low_h = 5.0 + 16.0 * b.rng.f32().powi(2);
                    let h = low_h.max(tall_h);
                    lots.push(Lot { pos: polar(r, a), yaw: a, size: Vec3::new(w - gap, h, d), tall: h > 40.0 });
                    s += w;
                }
            }
        }
        bands += 1;
    }
    let radius = ring_radius(bands);

    // Paths. RC: along a ring road, then in along a main spoke to the
    // towers. RC': backwards out along another main spoke.
    let spoke = b.rng.below(MAIN_SPOKES) as f32 / MAIN_SPOKES as f32 * TAU;
    let k_end = 2.min(bands);
    let r_end = ring_radius(k_end);
    let k_start = ((300.0 / BAND).round() as usize + k_end).min(bands);
    let r_start = ring_radius(k_start);
    let arc = (180.0 / r_start).min(TAU / MAIN_SPOKES as f32 * 0.9);
    let mut pts: Vec<Vec3> = (0..=12).map(|i| polar(r_start, spoke - arc * (1.0 - i as f32 / 12.0))).collect();
    pts.push(polar(r_end, spoke));
    for p in &mut pts {
        p.y = EYE;
    }
    let walk = walk_path(pts, 20.0, 25);
    let back_spoke = spoke + TAU / MAIN_SPOKES as f32 * (1 + b.rng.below(MAIN_SPOKES - 1)) as f32;
    let fast_path = backward_spin(r_end.max(PLAZA * 0.5), (r_end + 300.0).min(radius), back_spoke);
    let clear = Clearance::new(&[&walk, &fast_path], 1.5, EYE, 2.0);

    let unit = b.mesh("ground", block(1.0, 1.0, 1.0));
    // Low-poly building kinds: unit footprint, height 1.
    let kinds = [
        (b.mesh("box", block(1.0, 1.0, 1.0)), 3.0, 1.0),
        (b.mesh("gabled", block(1.0, 0.75, 1.0).with(gable().scaled(Vec3::new(1.0, 0.25, 1.0)).at(Vec3::Y * 0.75))), 1.0, 0.0),
        (b.mesh("hipped", block(1.0, 0.85, 1.0).with(pyramid(4, 0.71, 0.15).rotated(Quat::from_rotation_y(PI / 4.0)).at(Vec3::Y * 0.85))), 0.8, 0.5),
        (b.mesh("stepped", block(1.0, 0.7, 1.0).with(block(0.7, 0.3, 0.7).at(Vec3::Y * 0.7))), 1.0, 1.0),
        (b.mesh("round-tower", cylinder(0.5, 1.0, 8)), 0.0, 0.6),
    ];
    let tree = b.mesh("tree", cone(1.0, 1.0, 6));
    let lamp = b.mesh("lamp", block(0.25, 1.0, 0.25));
    let kiosk = b.mesh("kiosk", block(3.0, 2.8, 2.5));
    let monument = b.mesh("monument", cylinder(6.0, 2.0, 16).with(pyramid(4, 2.5, 40.0).at(Vec3::Y * 2.0)));

    // Ground tiles over the disc, the plaza's monument, then the buildings
    // (random lots left empty: parks), then trees, lamps and kiosks.
    let tile = 150.0;
    let tiles = (radius / tile).ceil() as i32;
    for i in -tiles..tiles {
        for j in -tiles..tiles {
            let c = Vec3::new((i as f32 + 0.5) * tile, -0.1, (j as f32 + 0.5) * tile);
            if c.length() - tile * 0.71 < radius {
                let color = b.rng.tint([0.32, 0.33, 0.3], 0.04);
                b.push(unit, trs(c, 0.0, Vec3::new(tile, 0.1, tile)), color);
            }
        }
    }
    b.push(monument, trs(Vec3::ZERO, 0.0, Vec3::ONE), [0.75, 0.72, 0.65]);
    let keep = b.rng.sample_indices(lots.len(), want_buildings.min(b.left()));
    for i in keep {
        let lot = &lots[i];
        let weights: Vec<f32> = kinds.iter().map(|k| if lot.tall { k.2 } else { k.1 }).collect();
        let mesh = kinds[b.rng.weighted(&weights)].0;
        let color = if lot.tall {
            b.rng.color(&[[0.45, 0.55, 0.65], [0.6, 0.62, 0.66], [0.3, 0.38, 0.45], [0.7, 0.68, 0.6]], 0.08)
        } else {
            b.rng.color(&[[0.8, 0.72, 0.6], [0.65, 0.4, 0.3], [0.85, 0.85, 0.8], [0.55, 0.55, 0.5], [0.75, 0.6, 0.45]], 0.1)
        };
        b.push(mesh, trs(lot.pos, lot.yaw, lot.size), color);
    }
    let mut misses = 0;
    while b.left() > 0 {
        // A spot on a sidewalk: along a ring road or along a main spoke.
        let k = 1 + b.rng.below(bands.max(1));
        let side = if b.rng.chance(0.5) { 1.0 } else { -1.0 };
        let pos = if b.rng.chance(0.75) {
            polar(ring_radius(k) + side * (ROAD * 0.5 + 1.5), b.rng.range(0.0, TAU))
        } else {
            let a = b.rng.below(MAIN_SPOKES) as f32 / MAIN_SPOKES as f32 * TAU;
            let r = b.rng.range(PLAZA + 10.0, radius);
            polar(r, a) + polar(ROAD * 0.5 + 1.5, a + PI * 0.5) * side
        };
        let (mesh, m, color) = match b.rng.below(10) {
            0..=6 => {
                let h = b.rng.range(3.0, 8.0);
                let r = h * b.rng.range(0.2, 0.3);
                (tree, trs(pos, 0.0, Vec3::new(r, h, r)), b.rng.color(&[[0.2, 0.45, 0.2], [0.25, 0.5, 0.15], [0.15, 0.35, 0.2]], 0.1))
            }
            7 | 8 => (lamp, trs(pos, 0.0, Vec3::new(1.0, 6.0, 1.0)), [0.3, 0.3, 0.32]),
            _ => (kiosk, trs(pos, pos.x.atan2(pos.z), Vec3::ONE), b.rng.color(&[[0.8, 0.3, 0.2], [0.2, 0.4, 0.7], [0.9, 0.8, 0.3]], 0.1)),
        };
        if misses < 100 && (on_road(pos, 1.0) || clear.blocks(&b.bounds(mesh, &m))) {
            misses += 1;
            continue;
        }
        misses = 0;
        b.push(mesh, m, color);
    }
    if fast {
        fast_path
    } else {
        walk
    }
}

/// RC': walking backwards out along the spoke at angle `a`, from radius
/// `r0` to `r1`, facing the centre, while the view swings +-80 degrees
/// about every 2.5 s and spins once around between 4 s and 6 s.
fn backward_spin(r0: f32, r1: f32, a: f32) -> CameraPath {
    let keys = 101;
    let inward = a + PI; // view yaw towards the centre
    CameraPath::new(
        (0..keys)
            .map(|i| {
                let t = 10.0 * i as f32 / (keys - 1) as f32;
                let eye = polar(r0 + (r1 - r0) * t / 10.0, a) + Vec3::Y * EYE;
                let s = ((t - 4.0) / 2.0).clamp(0.0, 1.0);
                let spin = TAU * s * s * (3.0 - 2.0 * s);
                let yaw = inward + 1.4 * (t * TAU / 2.5).sin() + spin;
                key(t, eye, eye + polar(10.0, yaw))
            })
            .collect(),
    )
}
