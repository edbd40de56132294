//! `library` (the statistical occlusion-query paper's second scene): rows of
//! bookcases WITHOUT backs, every shelf filled with books of varied size, a
//! few leaning or lying in stacks, some gaps. With open backs only the books
//! occlude. The path walks the aisles, turning through the cross aisles.

use glam::{Mat4, Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

use super::shapes::{block, box_at, cuboid, cylinder, Part};
use super::{trs, walk_path, Builder};
use crate::CameraPath;

const SECTION_W: f32 = 1.0;
const CASE_D: f32 = 0.32;
const CASE_H: f32 = 2.3;
const LEVELS: usize = 7;
const LEVEL_H: f32 = 0.315;
const BOARD: f32 = 0.025;
const AISLE: f32 = 1.5;
const ROW_PITCH: f32 = CASE_D + AISLE;
/// Sections between two cross aisles, and the cross aisle width.
const RUN: usize = 6;
const CROSS: f32 = 2.4;
/// Aisle round the stacks, inside the walls.
const MARGIN: f32 = 4.0;
const EYE: f32 = 1.6;

const LEATHER: &[[f32; 3]] = &[
    [0.45, 0.1, 0.08],
    [0.12, 0.3, 0.15],
    [0.1, 0.15, 0.4],
    [0.4, 0.25, 0.12],
    [0.7, 0.55, 0.35],
    [0.15, 0.12, 0.1],
    [0.6, 0.5, 0.2],
    [0.5, 0.45, 0.4],
    [0.8, 0.2, 0.15],
    [0.85, 0.8, 0.65],
];

/// Bookcase section without a back: sides and boards, base on y = 0,
/// x in [0, 1], depth along z centred.
fn bookcase() -> Part {
    let mut p = Part::new();
    for x in [BOARD * 0.5, SECTION_W - BOARD * 0.5] {
        p.append(&box_at(Vec3::new(x, CASE_H * 0.5, 0.0), Vec3::new(BOARD, CASE_H, CASE_D)));
    }
    for i in 0..=LEVELS {
        let y = 0.06 + i as f32 * LEVEL_H;
        p.append(&box_at(Vec3::new(SECTION_W * 0.5, y - BOARD * 0.5, 0.0), Vec3::new(SECTION_W - 2.0 * BOARD, BOARD, CASE_D)));
    }
    p
}

/// Books: x in [0, 1] (thickness), y in [0, 1] (height), z in [-0.5, 0.5]
/// (depth), spine at +z.
fn book_plain() -> Part {
    cuboid(Vec3::new(0.0, 0.0, -0.5), Vec3::ONE * Vec3::new(1.0, 1.0, 0.5))
}

fn book_round_spine() -> Part {
    cuboid(Vec3::new(0.0, 0.0, -0.5), Vec3::new(1.0, 1.0, 0.42)).with(cylinder(0.5, 1.0, 10).scaled(Vec3::new(1.0, 1.0, 0.16)).at(Vec3::new(0.5, 0.0, 0.42)))
}

fn book_hardcover() -> Part {
    // Two covers and an inset block of pages.
    cuboid(Vec3::new(0.0, 0.0, -0.5), Vec3::new(0.15, 1.0, 0.5))
        .with(cuboid(Vec3::new(0.85, 0.0, -0.5), Vec3::new(1.0, 1.0, 0.5)))
        .with(cuboid(Vec3::new(0.15, 0.03, -0.47), Vec3::new(0.85, 0.97, 0.5)))
        .with(cuboid(Vec3::new(0.15, 0.0, 0.45), Vec3::new(0.85, 1.0, 0.5)))
}

struct Book {
    section: u32,
    /// Section-local transform (x along the shelf, +z to the aisle).
    local: Mat4,
    kind: usize,
    color: [f32; 3],
}

/// Fills one shelf of width `w` (starting at x = x0, base at y) with books.
fn fill_shelf(b: &mut Builder, section: u32, x0: f32, w: f32, y: f32, out: &mut Vec<Book>) {
    let clear_h = LEVEL_H - BOARD - 0.015;
    let mut x = x0;
    let end = x0 + w;
    let rng = &mut b.rng;
    loop {
        let r = rng.f32();
        let kind = rng.weighted(&[0.45, 0.25, 0.3]);
        let color = rng.color(LEATHER, 0.15);
        if r < 0.03 {
            x += rng.range(0.02, 0.1); // a gap
            continue;
        }
        let t = rng.log_range(0.015, 0.07);
        let h = rng.range(0.19, clear_h);
        let d = (h * rng.range(0.6, 0.85)).min(CASE_D - 0.03);
        let front = CASE_D * 0.5 - 0.01 - rng.range(0.0, 0.02);
        if r < 0.06 {
            // A stack of books lying flat.
            let count = 2 + rng.below(4);
            let len = rng.range(0.17, 0.26);
            if x + len > end {
                break;
            }
            let mut yy = y;
            for _ in 0..count {
                let t = rng.log_range(0.015, 0.05);
                let d = (len * rng.range(0.65, 0.8)).min(CASE_D - 0.03);
                let color = rng.color(LEATHER, 0.15);
                let kind = rng.weighted(&[0.45, 0.25, 0.3]);
                // Height axis along +x, thickness axis down.
                let m = Mat4::from_translation(Vec3::new(x, yy + t, front - d * 0.5)) * Mat4::from_rotation_z(-FRAC_PI_2) * Mat4::from_scale(Vec3::new(t, len, d));
                out.push(Book { section, local: m, kind, color });
                yy += t;
            }
            x += len + 0.005;
            continue;
        }
        // Upright, sometimes leaning on the previous book.
        let lean = if r < 0.1 { rng.range(0.08, 0.25) } else { 0.0 };
        let width = t * lean.cos() + h * lean.sin();
        if x + width > end {
            break;
        }
        let m = Mat4::from_translation(Vec3::new(x + h * lean.sin(), y, front - d * 0.5)) * Mat4::from_rotation_z(lean) * Mat4::from_scale(Vec3::new(t, h, d));
        out.push(Book { section, local: m, kind, color });
        x += width + 0.001;
    }
}

pub(super) fn build(b: &mut Builder) -> CameraPath {
    let n = b.n;
    // Sections needed: about 165 books each; the layout is rows x cols with
    // cols a multiple of RUN where possible, the stacks roughly square.
    let mut sections = ((n as f32 / 165.0).ceil() as usize).max(1);
    let (rows, cols, books) = loop {
        let rows = ((sections as f32 / (ROW_PITCH / SECTION_W)).sqrt().round() as usize).max(1);
        let cols = sections.div_ceil(rows);
        let mut books = vec![];
        for s in 0..rows * cols {
            for level in 0..LEVELS {
                let y = 0.06 + level as f32 * LEVEL_H;
                fill_shelf(b, s as u32, BOARD, SECTION_W - 2.0 * BOARD, y, &mut books);
            }
        }
        let structure = rows * cols + 4 + 1;
        if books.len() + structure >= n || rows * cols >= n {
            break (rows, cols, books);
        }
        sections = sections * 11 / 10 + 1;
    };

    // Geometry of the stacks: x of each section (a cross aisle after every
    // RUN sections), z of each row; rows alternate which way books face.
    let section_x = |c: usize| c as f32 * SECTION_W + (c / RUN) as f32 * CROSS;
    let length = section_x(cols - 1) + SECTION_W;
    let depth = (rows - 1) as f32 * ROW_PITCH + CASE_D;
    let (ox, oz) = (-length * 0.5, -depth * 0.5);
    let row_z = |r: usize| oz + CASE_D * 0.5 + r as f32 * ROW_PITCH;
    let (x_lo, x_hi) = (ox - MARGIN, ox + length + MARGIN);
    let (z_lo, z_hi) = (oz - MARGIN, oz + depth + MARGIN);

    // Path: aisle, cross aisle, another aisle, ... Aisles lie between rows
    // (and outside the first and last); cross aisles at the ends and gaps.
    let aisles: Vec<f32> = (0..=rows).map(|r| row_z(r) - CASE_D * 0.5 - AISLE * 0.5).collect();
    let mut crosses = vec![ox - MARGIN * 0.5];
    crosses.extend((1..cols.div_ceil(RUN)).map(|k| ox + section_x(k * RUN) - CROSS * 0.5));
    crosses.push(ox + length + MARGIN * 0.5);
    // Turn in the interior cross aisles where there are enough of them:
    // turning at the ends of the stacks means staring at a wall.
    let crosses = if crosses.len() >= 4 { crosses[1..crosses.len() - 1].to_vec() } else { crosses };
    let mut ai = if aisles.len() > 2 { 1 + b.rng.below(aisles.len() - 2) } else { 0 };
    let mut ci = 0;
    let mut dir_c: i64 = 1;
    let mut pts = vec![Vec3::new(crosses[0], EYE, aisles[ai])];
    for leg in 0..7 {
        if leg % 2 == 0 {
            // Along the aisle to another cross aisle.
            let step = 1 + b.rng.below(2) as i64;
            if !(0..crosses.len() as i64).contains(&(ci as i64 + dir_c * step)) {
                dir_c = -dir_c;
            }
            ci = (ci as i64 + dir_c * step).clamp(0, crosses.len() as i64 - 1) as usize;
        } else {
            // Along the cross aisle, past a few row ends, into another aisle.
            let shift = 2 + b.rng.below(3);
            ai = if ai + shift < aisles.len() { ai + shift } else { ai.saturating_sub(shift) };
        }
        pts.push(Vec3::new(crosses[ci], EYE, aisles[ai]));
    }
    // End halfway down the last aisle, among the books.
    let n_pts = pts.len();
    pts[n_pts - 1] = (pts[n_pts - 1] + pts[n_pts - 2]) * 0.5;
    let path = walk_path(pts, 2.5, 25);

    // Structure: floor, walls, bookcases.
    let unit = b.mesh("unit-box", block(1.0, 1.0, 1.0));
    let case = b.mesh("bookcase", bookcase());
    let kinds = [b.mesh("book", book_plain()), b.mesh("book-round-spine", book_round_spine()), b.mesh("book-hardcover", book_hardcover())];
    let (cx, cz) = ((x_lo + x_hi) * 0.5, (z_lo + z_hi) * 0.5);
    b.push(unit, trs(Vec3::new(cx, -0.1, cz), 0.0, Vec3::new(x_hi - x_lo, 0.1, z_hi - z_lo)), [0.45, 0.3, 0.2]);
    let wall = [0.8, 0.76, 0.68];
    let wall_h = 4.0;
    for (pos, size) in [
        (Vec3::new(cx, 0.0, z_lo - 0.15), Vec3::new(x_hi - x_lo + 0.6, wall_h, 0.3)),
        (Vec3::new(cx, 0.0, z_hi + 0.15), Vec3::new(x_hi - x_lo + 0.6, wall_h, 0.3)),
        (Vec3::new(x_lo - 0.15, 0.0, cz), Vec3::new(0.3, wall_h, z_hi - z_lo)),
        (Vec3::new(x_hi + 0.15, 0.0, cz), Vec3::new(0.3, wall_h, z_hi - z_lo)),
    ] {
        b.push(unit, trs(pos, 0.0, size), wall);
    }
    let section_m = |r: usize, c: usize| {
        // Odd rows turn round: their books face the aisle on the other side.
        let (x, z) = (ox + section_x(c), row_z(r));
        if r.is_multiple_of(2) {
            Mat4::from_translation(Vec3::new(x, 0.0, z))
        } else {
            Mat4::from_translation(Vec3::new(x + SECTION_W, 0.0, z)) * Mat4::from_quat(Quat::from_rotation_y(PI))
        }
    };
    for r in 0..rows {
        for c in 0..cols {
            let color = b.rng.tint([0.42, 0.28, 0.16], 0.08);
            b.push(case, section_m(r, c), color);
        }
    }

    // Books: random ones taken out so the count is exact, which leaves gaps.
    let keep = b.rng.sample_indices(books.len(), b.left());
    for i in keep {
        let bk = &books[i];
        let s = bk.section as usize;
        let m = section_m(s / cols, s % cols) * bk.local;
        b.push(kinds[bk.kind], m, bk.color);
    }
    path
}
