//! CPU references of HROC's GPU passes, for tests: occludee group
//! extraction (Algorithm 1 + frustum culling + adaptive grouping) and the
//! per-pixel ray marking of the batch occlusion test.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::aabb::OrientedBox;
use crate::bvh::Bvh;
use crate::frustum::ViewGeometry;
use crate::{frustum::aabb_in_frustum, Aabb};

/// Node state: not reached from any occluder (paper Algorithm 1).
pub const NIL: u32 = 0;
/// Node state: sibling of a node on an occluder's path; a candidate occludee group.
pub const UNKNOWN: u32 = 1;
/// Node state: on the path from an occluder's leaf to the root.
pub const VISIBLE: u32 = 2;

/// Node states after walking up from every occluder (paper Algorithm 1).
pub fn node_states(bvh: &Bvh, occluders: &[bool]) -> Vec<u32> {
    let mut state = vec![NIL; bvh.nodes.len()];
    for (o, _) in occluders.iter().enumerate().filter(|(_, &x)| x) {
        let mut n = bvh.leaf_of_object[o];
        loop {
            let prev = state[n as usize];
            state[n as usize] = VISIBLE;
            if prev == VISIBLE || n == 0 {
                break;
            }
            let s = bvh.sibling(n).expect("non-root has a sibling") as usize;
            state[s] = state[s].max(UNKNOWN);
            n = bvh.parent(n).expect("non-root has a parent");
        }
    }
    state
}

/// `PIXEL_PAD` in common.wgsl.
pub const PIXEL_PAD: f32 = 0.0625;

/// `pixel_angle` in common.wgsl: a pixel's height at distance d from the
/// eye is `a + b d`, `(a, b)` ([`crate::frustum::ViewGeometry::footprint`]).
pub fn pixel_angle(g: &ViewGeometry, size: (u32, u32)) -> Vec2 {
    let f = g.footprint(size);
    Vec2::new(f.x, f.y)
}

/// `pixel_angle_xy` in common.wgsl: the larger of a pixel's width and
/// height, as [`pixel_angle`].
pub fn pixel_angle_xy(g: &ViewGeometry, size: (u32, u32)) -> Vec2 {
    let f = g.footprint(size);
    Vec2::new(f.z, f.w)
}

/// The shaders' box padding (`padded_box` in common.wgsl).
pub fn padded(b: Aabb, eye: Vec3, pixel: Vec2) -> Aabb {
    padded_px(b, eye, pixel, PIXEL_PAD)
}

/// `padded_box_px` in common.wgsl: `px` pixels of padding at the farthest corner.
pub fn padded_px(b: Aabb, eye: Vec3, pixel: Vec2, px: f32) -> Aabb {
    let pad = box_pad(b, eye, pixel, px);
    Aabb::new(b.min - Vec3::splat(pad), b.max + Vec3::splat(pad))
}

/// The box the box tests rasterize for an object's box `b`, seen from
/// `eye` through pixels `pixel = (a, b)` wide (`a + b d` at distance d;
/// [`crate::frustum::ViewGeometry::footprint`]) on targets of `samples`
/// samples per pixel: `b` grown by the margins the shaders add
/// (`box_pad` in common.wgsl, one-pixel blocks). A host that compares its
/// pictures with and without culling can tell a rasterizer's stray
/// fragment by it: one in front of this box is no box test's to keep.
pub fn tested_box(b: Aabb, eye: Vec3, pixel: Vec2, samples: u32) -> Aabb {
    padded_px(b, eye, pixel, block_pad_px(1, samples))
}

/// `box_pad` in common.wgsl: the world distance [`padded_px`] grows a box by.
pub fn box_pad(b: Aabb, eye: Vec3, pixel: Vec2, px: f32) -> f32 {
    let far = (b.min - eye).abs().max((b.max - eye).abs()).length();
    let scale = b.min.abs().max(b.max.abs()).max_element();
    px * (pixel.x + pixel.y * far) + 1e-4 * (b.max - b.min).length() + 1e-6 * (scale + eye.length()) + 1e-7
}

/// The span `(enter, exit)` of the ray `eye + t dir` in `o`'s local box
/// grown by `grow` times its diagonal, and so that it holds the ball of
/// radius `pad` around each of its points (`ray_oriented` in common.wgsl,
/// without its rounding slack).
pub fn oriented_span(o: &OrientedBox, eye: Vec3, dir: Vec3, pad: f32, grow: f32) -> (f32, f32) {
    let Some(inv) = o.to_local() else { return (f32::NEG_INFINITY, f32::INFINITY) };
    let (e, d) = (inv.transform_point3(eye), inv.transform_vector3(dir));
    let rows = glam::Mat3::from(inv.matrix3).transpose();
    let g = pad * Vec3::new(rows.x_axis.length(), rows.y_axis.length(), rows.z_axis.length()) + Vec3::splat(grow * (o.local.max - o.local.min).length());
    let (t0, t1) = ((o.local.min - g - e) / d, (o.local.max + g - e) / d);
    (t0.min(t1).max_element(), t0.max(t1).min_element())
}

/// `block_pad_px` in common.wgsl: the padding, in pixels, of boxes tested
/// by one ray per block of `scale` × `scale` pixels of `samples` samples.
/// (The references below model single-sample targets and pass 1.)
pub fn block_pad_px(scale: u32, samples: u32) -> f32 {
    let spread = if samples > 1 { scale } else { scale - 1 };
    spread as f32 * std::f32::consts::FRAC_1_SQRT_2 + scale as f32 * PIXEL_PAD
}

/// `crosses_near` in common.wgsl, of the near plane `p`.
pub fn crosses_near(p: Vec4, near: f32, b: &Aabb) -> bool {
    let v = Vec3::select(p.truncate().cmpge(Vec3::ZERO), b.min, b.max);
    p.truncate().dot(v) + p.w <= near
}

/// Groups to rasterize (sorted) and leaves made visible without a test
/// (adaptive grouping), from the node states, with boxes padded for a test
/// of `scale` × `scale` blocks (`pixel` from [`pixel_angle_xy`]) in `view`.
pub fn groups(bvh: &Bvh, state: &[u32], view: &ViewGeometry, pixel: Vec2, scale: u32) -> (Vec<u32>, Vec<u32>) {
    let (planes, eye) = (&view.planes, view.eye);
    let (mut groups, mut forced) = (Vec::new(), Vec::new());
    for g in 0..bvh.nodes.len() as u32 {
        let s = state[g as usize];
        if !(s == UNKNOWN || (g == 0 && s == NIL)) {
            continue;
        }
        let mut stack = vec![g];
        while let Some(n) = stack.pop() {
            let b = padded_px(bvh.aabb(n), eye, pixel, block_pad_px(scale, 1));
            if !aabb_in_frustum(planes, b.min, b.max) {
                continue;
            }
            if !crosses_near(view.near_plane, view.near, &b) {
                groups.push(n);
            } else if let Some(o) = bvh.object(n) {
                forced.push(o);
            } else if let Some([l, r]) = bvh.children(n) {
                stack.extend([l, r]);
            }
        }
    }
    groups.sort_unstable();
    forced.sort_unstable();
    (groups, forced)
}

/// Leaves in the subtrees of `groups` that a ray through the centre of some
/// block of `block` × `block` pixels enters no deeper than the block's
/// farthest occlusion-map depth plus `tolerance` (in depth-buffer units).
/// Boxes are first padded as the shaders pad them for such blocks when
/// `pixel` is given, then grown by `grow` times their diagonal. With
/// blocks of one pixel, no padding, a shrinking `grow` and a negative
/// tolerance this is what the GPU must find at any test scale; with the
/// GPU's blocks, padding and generous ones, all it may find. A leaf whose
/// object has an oriented box (`oriented[o]`, empty for none) is entered
/// where the ray is inside both boxes, the oriented one padded and grown
/// alike.
#[allow(clippy::too_many_arguments)]
pub fn ray_marked(
    bvh: &Bvh,
    groups: &[u32],
    view_proj: &Mat4,
    ray_dirs: &Mat4,
    ray_origins: &Mat4,
    eye: Vec3,
    (w, h): (u32, u32),
    depth: &[f32],
    block: u32,
    pixel: Option<Vec2>,
    grow: f32,
    tolerance: f32,
    oriented: &[Option<OrientedBox>],
) -> Vec<bool> {
    let n_obj = bvh.leaf_of_object.len();
    let mut in_group = vec![false; bvh.nodes.len()];
    for &g in groups {
        let mut stack = vec![g];
        while let Some(n) = stack.pop() {
            in_group[n as usize] = true;
            if let Some([l, r]) = bvh.children(n) {
                stack.extend([l, r]);
            }
        }
    }
    let mut marked = vec![false; n_obj];
    let s = block;
    for y in 0..h / s {
        for x in 0..w / s {
            let px = Vec2::new((x * s) as f32 + 0.5 * s as f32, (y * s) as f32 + 0.5 * s as f32);
            let ndc = Vec2::new(px.x / w as f32 * 2.0 - 1.0, 1.0 - px.y / h as f32 * 2.0);
            let dir = (*ray_dirs * Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
            let origin = (*ray_origins * Vec4::new(ndc.x, ndc.y, 0.0, 1.0)).truncate();
            let c0 = *view_proj * origin.extend(1.0);
            let c1 = *view_proj * dir.extend(0.0);
            let farthest = (0..s * s).map(|i| depth[((y * s + i / s) * w + x * s + i % s) as usize]).fold(0.0f32, f32::max);
            let limit = farthest + tolerance;
            let mut stack = vec![0u32];
            while let Some(n) = stack.pop() {
                let pad = pixel.map_or(0.0, |px| box_pad(bvh.aabb(n), eye, px, block_pad_px(s, 1)));
                let b = pixel.map_or(bvh.aabb(n), |px| padded_px(bvh.aabb(n), eye, px, block_pad_px(s, 1)));
                let g = Vec3::splat(grow * (b.max - b.min).length().max(1e-3));
                let (t0, t1) = ((b.min - g - origin) / dir, (b.max + g - origin) / dir);
                let (mut enter, mut exit) = (t0.min(t1).max_element(), t0.max(t1).min_element());
                if let Some(o) = bvh.object(n).and_then(|o| oriented.get(o as usize).copied().flatten()) {
                    let (e, x) = oriented_span(&o, origin, dir, pad, grow);
                    (enter, exit) = (enter.max(e), exit.min(x));
                }
                let t = enter.max(1.0);
                if exit < t || exit.is_nan() {
                    continue;
                }
                let d = (c0.z + t * c1.z) / (c0.w + t * c1.w);
                if d > limit {
                    continue;
                }
                match (bvh.object(n), bvh.children(n)) {
                    (Some(o), _) if in_group[n as usize] => marked[o as usize] = true,
                    (_, Some([l, r])) => stack.extend([l, r]),
                    _ => {}
                }
            }
        }
    }
    marked
}

/// `seed` in hroc_seed.wgsl: for each cell centre of a `cols` × `rows`
/// screen grid, the object whose (unpadded) box the cell's ray enters
/// first at or past the near plane (t = 1). Sorted, without repeats.
pub fn seed(bvh: &Bvh, ray_dirs: &Mat4, ray_origins: &Mat4, grid: (u32, u32)) -> Vec<u32> {
    let mut hits: Vec<u32> = first_hits(bvh, ray_dirs, ray_origins, grid).into_iter().flatten().collect();
    hits.sort_unstable();
    hits.dedup();
    hits
}

/// `refill_holes` in hroc_seed.wgsl: the first hits of the cells whose
/// centre pixel (of a `size` target) is at the far plane in `depth` (V's
/// standard depth, one sample) and was not in `last` (last frame's final
/// depth), leaving out V's objects (`in_v`). Sorted, without repeats.
/// `depth` and `last` hold `size.0 * size.1` values (row by row), `size`
/// is not empty, and `in_v` has an entry for every object.
#[allow(clippy::too_many_arguments)]
pub fn refill(bvh: &Bvh, ray_dirs: &Mat4, ray_origins: &Mat4, grid: (u32, u32), size: (u32, u32), depth: &[f32], last: &[f32], in_v: &[bool]) -> Vec<u32> {
    let (cols, rows) = grid;
    let pixel = |cell: u32| {
        let x = ((((cell % cols) as f32 + 0.5) / cols as f32 * size.0 as f32) as u32).min(size.0 - 1);
        let y = ((((cell / cols) as f32 + 0.5) / rows as f32 * size.1 as f32) as u32).min(size.1 - 1);
        (y * size.0 + x) as usize
    };
    let mut hits: Vec<u32> = first_hits(bvh, ray_dirs, ray_origins, grid)
        .into_iter()
        .enumerate()
        .filter(|&(cell, _)| last[pixel(cell as u32)] < 1.0 && depth[pixel(cell as u32)] >= 1.0)
        .filter_map(|(_, hit)| hit.filter(|&o| !in_v[o as usize]))
        .collect();
    hits.sort_unstable();
    hits.dedup();
    hits
}

/// The object each cell's ray enters first, cell by cell.
fn first_hits(bvh: &Bvh, ray_dirs: &Mat4, ray_origins: &Mat4, (cols, rows): (u32, u32)) -> Vec<Option<u32>> {
    let mut hits = Vec::new();
    if bvh.nodes.is_empty() {
        return vec![None; (cols * rows) as usize];
    }
    for cell in 0..cols * rows {
        let ndc = Vec2::new(((cell % cols) as f32 + 0.5) / cols as f32 * 2.0 - 1.0, 1.0 - ((cell / cols) as f32 + 0.5) / rows as f32 * 2.0);
        let dir = (*ray_dirs * Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
        let eye = (*ray_origins * Vec4::new(ndc.x, ndc.y, 0.0, 1.0)).truncate();
        let (mut best, mut hit) = (f32::MAX, None);
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let b = bvh.aabb(n);
            let (t0, t1) = ((b.min - eye) / dir, (b.max - eye) / dir);
            let enter = t0.min(t1).max_element().max(1.0);
            let exit = t0.max(t1).min_element();
            if exit < enter || enter >= best || exit.is_nan() {
                continue;
            }
            match (bvh.object(n), bvh.children(n)) {
                (Some(o), _) => (best, hit) = (enter, Some(o)),
                (_, Some([l, r])) => stack.extend([l, r]),
                _ => {}
            }
        }
        hits.push(hit);
    }
    hits
}
