//! Mesh builders shared by the generators: boxes, surfaces of revolution,
//! spheres, tori, tubes, rocks, flat-shaded solids, and a teapot. A `Part`
//! is an editable triangle soup; parts merge under transforms into one mesh
//! (a chair, a machine), which the scene then instances many times.
//!
//! Triangles are counter-clockwise seen from outside (wgpu's default front
//! face): smooth surfaces are oriented against their vertex normals, so a
//! builder only has to get the normals right.

use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use std::collections::HashMap;
use std::f32::consts::{PI, TAU};

use super::rng::Rng;
use crate::Mesh;

#[derive(Clone, Debug, Default)]
pub struct Part {
    pub pos: Vec<Vec3>,
    pub nrm: Vec<Vec3>,
    pub idx: Vec<u32>,
}

impl Part {
    pub fn new() -> Self {
        Part::default()
    }

    pub fn triangles(&self) -> usize {
        self.idx.len() / 3
    }

    pub fn vertex(&mut self, p: Vec3, n: Vec3) -> u32 {
        self.pos.push(p);
        self.nrm.push(n);
        (self.pos.len() - 1) as u32
    }

    /// Adds triangle (a, b, c), flipped if needed so that its face normal
    /// agrees with its vertex normals; degenerate triangles are dropped.
    pub fn tri(&mut self, a: u32, b: u32, c: u32) {
        let (pa, pb, pc) = (self.pos[a as usize], self.pos[b as usize], self.pos[c as usize]);
        let f = (pb - pa).cross(pc - pa);
        let scale = (pb - pa).length_squared().max((pc - pa).length_squared());
        if f.length_squared() <= 1e-12 * scale * scale || scale == 0.0 {
            return;
        }
        let n = self.nrm[a as usize] + self.nrm[b as usize] + self.nrm[c as usize];
        if f.dot(n) >= 0.0 {
            self.idx.extend([a, b, c]);
        } else {
            self.idx.extend([a, c, b]);
        }
    }

    pub fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.tri(a, b, c);
        self.tri(a, c, d);
    }

    /// A flat polygon (convex, planar) with normal `n`.
    pub fn flat_poly(&mut self, pts: &[Vec3], n: Vec3) {
        let base = self.pos.len() as u32;
        for &p in pts {
            self.vertex(p, n);
        }
        for i in 1..pts.len().saturating_sub(1) as u32 {
            self.tri(base, base + i, base + i + 1);
        }
    }

    pub fn append(&mut self, o: &Part) {
        let base = self.pos.len() as u32;
        self.pos.extend_from_slice(&o.pos);
        self.nrm.extend_from_slice(&o.nrm);
        self.idx.extend(o.idx.iter().map(|i| i + base));
    }

    /// `self` plus `o`, for chaining parts into one mesh.
    pub fn with(mut self, o: Part) -> Part {
        self.append(&o);
        self
    }

    /// Applies an affine transform; normals use the inverse transpose so
    /// non-uniform scales keep them perpendicular.
    pub fn transform(mut self, m: Mat4) -> Part {
        let nm = Mat3::from_mat4(m).inverse().transpose();
        let mirror = Mat3::from_mat4(m).determinant() < 0.0;
        for p in &mut self.pos {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.nrm {
            *n = (nm * *n).try_normalize().unwrap_or(Vec3::Y);
        }
        if mirror {
            for t in self.idx.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        self
    }

    pub fn at(self, t: Vec3) -> Part {
        self.transform(Mat4::from_translation(t))
    }

    pub fn scaled(self, s: Vec3) -> Part {
        self.transform(Mat4::from_scale(s))
    }

    pub fn rotated(self, q: Quat) -> Part {
        self.transform(Mat4::from_quat(q))
    }

    /// Smooth area-weighted normals (after displacing vertices).
    pub fn recompute_normals(&mut self) {
        let mut n = vec![Vec3::ZERO; self.pos.len()];
        for t in self.idx.chunks_exact(3) {
            let (a, b, c) = (self.pos[t[0] as usize], self.pos[t[1] as usize], self.pos[t[2] as usize]);
            let f = (b - a).cross(c - a);
            for &i in t {
                n[i as usize] += f;
            }
        }
        self.nrm = n.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Y)).collect();
    }

    pub fn into_mesh(self, name: &str) -> Mesh {
        let positions = self.pos.iter().map(|p| p.to_array()).collect();
        let normals = self.nrm.iter().map(|n| n.to_array()).collect();
        Mesh::new(name, positions, Some(normals), self.idx)
    }
}

/// Axis-aligned box, 12 triangles, flat normals.
pub fn cuboid(min: Vec3, max: Vec3) -> Part {
    let mut p = Part::new();
    let c = (min + max) * 0.5;
    let h = (max - min) * 0.5;
    for axis in 0..3 {
        for s in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = s;
            let mut u = Vec3::ZERO;
            u[(axis + 1) % 3] = h[(axis + 1) % 3];
            let mut v = Vec3::ZERO;
            v[(axis + 2) % 3] = h[(axis + 2) % 3];
            let fc = c + n * h[axis];
            p.flat_poly(&[fc - u - v, fc + u - v, fc + u + v, fc - u + v], n);
        }
    }
    p
}

/// Box with its base centred on the origin: x, z in [-w/2, w/2], y in [0, h].
pub fn block(w: f32, h: f32, d: f32) -> Part {
    cuboid(Vec3::new(-w * 0.5, 0.0, -d * 0.5), Vec3::new(w * 0.5, h, d * 0.5))
}

/// Box centred at `c` with size `s`.
pub fn box_at(c: Vec3, s: Vec3) -> Part {
    cuboid(c - s * 0.5, c + s * 0.5)
}

/// Surface of revolution around +Y. `profile` holds (radius, y) from the
/// bottom up; a repeated point makes a crease (the ring is split so both
/// sides keep their own normals). Zero-radius points become poles.
pub fn lathe(profile: &[[f32; 2]], segs: u32) -> Part {
    let mut p = Part::new();
    let segs = segs.max(3);
    // Split into runs at repeated points.
    let mut runs: Vec<Vec<Vec2>> = vec![vec![]];
    for w in profile.iter().map(|&[r, y]| Vec2::new(r, y)) {
        let run = runs.last_mut().unwrap();
        if run.last() == Some(&w) {
            runs.push(vec![w]);
        } else {
            run.push(w);
        }
    }
    for run in runs.iter().filter(|r| r.len() >= 2) {
        // Profile normals: (dy, -dr) of the local tangent.
        let normal2 = |i: usize| {
            let a = run[i.saturating_sub(1)];
            let b = run[(i + 1).min(run.len() - 1)];
            let t = (b - a).normalize_or_zero();
            Vec2::new(t.y, -t.x)
        };
        let base = p.pos.len() as u32;
        for (i, q) in run.iter().enumerate() {
            let n2 = normal2(i);
            for j in 0..=segs {
                let a = j as f32 / segs as f32 * TAU;
                let (s, c) = a.sin_cos();
                p.vertex(Vec3::new(q.x * s, q.y, q.x * c), Vec3::new(n2.x * s, n2.y, n2.x * c).normalize_or_zero());
            }
        }
        let ring = segs + 1;
        for i in 0..run.len() as u32 - 1 {
            for j in 0..segs {
                let a = base + i * ring + j;
                let (b, c, d) = (a + 1, a + ring + 1, a + ring);
                p.quad(a, b, c, d);
            }
        }
    }
    p
}

/// Closed cylinder (or frustum) from y = 0 to y = h.
pub fn frustum(r0: f32, r1: f32, h: f32, segs: u32) -> Part {
    let mut prof = vec![[0.0, 0.0], [r0, 0.0], [r0, 0.0], [r1, h], [r1, h]];
    if r1 > 0.0 {
        prof.push([0.0, h]);
    } else {
        prof.pop();
    }
    lathe(&prof, segs)
}

pub fn cylinder(r: f32, h: f32, segs: u32) -> Part {
    frustum(r, r, h, segs)
}

pub fn cone(r: f32, h: f32, segs: u32) -> Part {
    frustum(r, 0.0, h, segs)
}

/// UV sphere of radius `r` centred on the origin.
pub fn uv_sphere(r: f32, segs: u32, rings: u32) -> Part {
    let prof: Vec<[f32; 2]> = (0..=rings)
        .map(|i| {
            let a = i as f32 / rings as f32 * PI;
            [r * a.sin(), -r * a.cos()]
        })
        .collect();
    lathe(&prof, segs)
}

/// Unit icosphere: 20 * 4^level triangles, smooth normals.
pub fn icosphere(level: u32) -> Part {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut pos: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|v| Vec3::from(*v).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(faces.len() * 4);
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push(((pos[a as usize] + pos[b as usize]) * 0.5).normalize());
                (pos.len() - 1) as u32
            })
        };
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut pos);
            let bc = midpoint(b, c, &mut pos);
            let ca = midpoint(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let mut p = Part::new();
    for &v in &pos {
        p.vertex(v, v);
    }
    for [a, b, c] in faces {
        p.tri(a, b, c);
    }
    p
}

/// A lumpy rock: a unit icosphere pushed in and out by random bumps, then
/// squashed a little. Deterministic for the RNG state.
pub fn rock(level: u32, roughness: f32, rng: &mut Rng) -> Part {
    let mut p = icosphere(level);
    let bumps: Vec<(Vec3, f32, f32)> = (0..12).map(|_| (rng.unit_vec3(), rng.range(-1.0, 1.0) * roughness, rng.range(2.0, 9.0))).collect();
    let fine: Vec<(Vec3, f32)> = (0..24).map(|_| (rng.unit_vec3(), rng.range(-0.3, 0.3) * roughness)).collect();
    for v in &mut p.pos {
        let d = *v;
        let mut r = 1.0;
        for (dir, amp, sharp) in &bumps {
            r += amp * d.dot(*dir).max(0.0).powf(*sharp);
        }
        for (dir, amp) in &fine {
            r += amp * (d.dot(*dir) * 9.0).sin() * 0.3;
        }
        *v = d * r.max(0.3);
    }
    p.recompute_normals();
    p
}

/// Torus around +Y: ring radius `big`, tube radius `small`.
pub fn torus(big: f32, small: f32, segs: u32, sides: u32) -> Part {
    torus_arc(big, small, segs, sides, 0.0, TAU)
}

/// Part of a torus: the ring angle runs from `a0` to `a1` (around +Y, 0 at +Z).
pub fn torus_arc(big: f32, small: f32, segs: u32, sides: u32, a0: f32, a1: f32) -> Part {
    let mut p = Part::new();
    for i in 0..=segs {
        let u = a0 + (a1 - a0) * i as f32 / segs as f32;
        let (su, cu) = u.sin_cos();
        for j in 0..=sides {
            let v = j as f32 / sides as f32 * TAU;
            let (sv, cv) = v.sin_cos();
            let n = Vec3::new(cv * su, sv, cv * cu);
            p.vertex(Vec3::new((big + small * cv) * su, small * sv, (big + small * cv) * cu), n);
        }
    }
    grid_faces(&mut p, 0, segs, sides);
    p
}

/// Quads over a (rows + 1) x (cols + 1) vertex grid starting at `base`.
fn grid_faces(p: &mut Part, base: u32, rows: u32, cols: u32) {
    let w = cols + 1;
    for i in 0..rows {
        for j in 0..cols {
            let a = base + i * w + j;
            p.quad(a, a + 1, a + w + 1, a + w);
        }
    }
}

/// A tube swept along `path` with radius `radii[i]` at point i; ends open
/// unless `caps`. Frames come from a fixed reference axis, so paths must not
/// run parallel to `reference`.
pub fn tube(path: &[Vec3], radii: &[f32], sides: u32, reference: Vec3, caps: bool) -> Part {
    let mut p = Part::new();
    let n = path.len();
    for i in 0..n {
        let t = (path[(i + 1).min(n - 1)] - path[i.saturating_sub(1)]).normalize_or_zero();
        let b = t.cross(reference).normalize_or_zero();
        let nn = b.cross(t);
        for j in 0..=sides {
            let a = j as f32 / sides as f32 * TAU;
            let d = b * a.cos() + nn * a.sin();
            p.vertex(path[i] + d * radii[i], d);
        }
    }
    grid_faces(&mut p, 0, n as u32 - 1, sides);
    if caps {
        for (i, sgn) in [(0, -1.0f32), (n - 1, 1.0)] {
            let t = (path[(i + 1).min(n - 1)] - path[i.saturating_sub(1)]).normalize_or_zero() * sgn;
            let base = i as u32 * (sides + 1);
            let ring: Vec<Vec3> = (0..sides).map(|j| p.pos[(base + j) as usize]).collect();
            let c = p.vertex(path[i], t);
            let first = p.pos.len() as u32;
            for &q in &ring {
                p.vertex(q, t);
            }
            for j in 0..sides {
                p.tri(c, first + j, first + (j + 1) % sides);
            }
        }
    }
    p
}

/// Convex solid from its vertices and faces (vertex index lists), flat
/// shaded; faces are oriented away from the centroid.
pub fn convex(verts: &[Vec3], faces: &[&[usize]]) -> Part {
    let centroid = verts.iter().copied().sum::<Vec3>() / verts.len() as f32;
    let mut p = Part::new();
    for f in faces {
        let pts: Vec<Vec3> = f.iter().map(|&i| verts[i]).collect();
        let fc = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
        let mut n = (pts[1] - pts[0]).cross(pts[2] - pts[0]).normalize_or_zero();
        if n.dot(fc - centroid) < 0.0 {
            n = -n;
        }
        p.flat_poly(&pts, n);
    }
    p
}

/// Prism over a regular `k`-gon (radius r, height h, base at y = 0), flat shaded.
pub fn prism(k: usize, r: f32, h: f32) -> Part {
    let ring = |y: f32| {
        (0..k).map(move |i| {
            let a = i as f32 / k as f32 * TAU;
            Vec3::new(r * a.sin(), y, r * a.cos())
        })
    };
    let verts: Vec<Vec3> = ring(0.0).chain(ring(h)).collect();
    let bottom: Vec<usize> = (0..k).collect();
    let top: Vec<usize> = (k..2 * k).collect();
    let sides: Vec<[usize; 4]> = (0..k).map(|i| [i, (i + 1) % k, k + (i + 1) % k, k + i]).collect();
    let mut faces: Vec<&[usize]> = vec![&bottom, &top];
    faces.extend(sides.iter().map(|s| s.as_slice()));
    convex(&verts, &faces)
}

/// Pyramid over a regular `k`-gon, flat shaded.
pub fn pyramid(k: usize, r: f32, h: f32) -> Part {
    let mut verts: Vec<Vec3> = (0..k)
        .map(|i| {
            let a = i as f32 / k as f32 * TAU;
            Vec3::new(r * a.sin(), 0.0, r * a.cos())
        })
        .collect();
    verts.push(Vec3::new(0.0, h, 0.0));
    let bottom: Vec<usize> = (0..k).collect();
    let sides: Vec<[usize; 3]> = (0..k).map(|i| [i, (i + 1) % k, k]).collect();
    let mut faces: Vec<&[usize]> = vec![&bottom];
    faces.extend(sides.iter().map(|s| s.as_slice()));
    convex(&verts, &faces)
}

/// Octahedron of radius r centred at the origin.
pub fn octahedron(r: f32) -> Part {
    let v = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z].map(|v| v * r);
    let faces: [&[usize]; 8] = [&[0, 2, 4], &[0, 4, 3], &[0, 3, 5], &[0, 5, 2], &[1, 4, 2], &[1, 3, 4], &[1, 5, 3], &[1, 2, 5]];
    convex(&v, &faces)
}

/// Regular tetrahedron of radius r centred at the origin.
pub fn tetrahedron(r: f32) -> Part {
    let v = [Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, -1.0, -1.0), Vec3::new(-1.0, 1.0, -1.0), Vec3::new(-1.0, -1.0, 1.0)].map(|v| v * (r / 3f32.sqrt()));
    let faces: [&[usize]; 4] = [&[0, 1, 2], &[0, 3, 1], &[0, 2, 3], &[1, 3, 2]];
    convex(&v, &faces)
}

/// Gabled roof (triangular prism) over x, z in [-0.5, 0.5], y in [0, 1].
pub fn gable() -> Part {
    let v = [Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 0.0, -0.5), Vec3::new(0.0, 1.0, -0.5), Vec3::new(-0.5, 0.0, 0.5), Vec3::new(0.5, 0.0, 0.5), Vec3::new(0.0, 1.0, 0.5)];
    let faces: [&[usize]; 5] = [&[0, 1, 2], &[3, 4, 5], &[0, 1, 4, 3], &[1, 2, 5, 4], &[2, 0, 3, 5]];
    convex(&v, &faces)
}

/// Heightfield patch over x, z in [-0.5, 0.5] with `n` x `n` quads;
/// `height` maps (x, z) to y.
pub fn heightfield(n: u32, height: impl Fn(f32, f32) -> f32) -> Part {
    let mut p = Part::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, z) = (j as f32 / n as f32 - 0.5, i as f32 / n as f32 - 0.5);
            p.vertex(Vec3::new(x, height(x, z), z), Vec3::Y);
        }
    }
    grid_faces(&mut p, 0, n, n);
    p.recompute_normals();
    p
}

/// A teapot-like mesh: lathed body and lid with knob, a tapered curved
/// spout and a handle. Base at y = 0, about 2.4 x 1.4 x 1.7 (spout on +X).
/// `segs` sets the tessellation (10 → ~250 triangles, 20 → ~700).
pub fn teapot(segs: u32) -> Part {
    // No top disk on the body: the lid covers the opening.
    let body = lathe(&[[0.0, 0.0], [0.7, 0.0], [0.7, 0.0], [0.85, 0.05], [1.05, 0.22], [1.15, 0.45], [1.12, 0.7], [1.0, 0.92], [0.82, 1.05]], segs);
    let lid = lathe(&[[0.84, 1.05], [0.7, 1.15], [0.4, 1.24], [0.12, 1.28], [0.12, 1.28], [0.16, 1.38], [0.12, 1.46], [0.0, 1.48]], segs);
    let k = (segs / 2).max(4);
    let spout_path: Vec<Vec3> = (0..=k)
        .map(|i| {
            let s = i as f32 / k as f32;
            Vec3::new(0.95 + 0.85 * s, 0.35 + 0.75 * s * s, 0.0)
        })
        .collect();
    let spout_r: Vec<f32> = (0..=k).map(|i| 0.2 - 0.1 * i as f32 / k as f32).collect();
    let spout = tube(&spout_path, &spout_r, (segs / 2).max(5), Vec3::Z, false);
    let handle = torus_arc(0.36, 0.07, k + 2, (segs / 2).max(4), -PI * 0.05, -PI * 0.95)
        .rotated(Quat::from_rotation_x(PI * 0.5))
        .scaled(Vec3::new(1.0, 1.15, 1.0))
        .at(Vec3::new(-1.05, 0.62, 0.0));
    body.with(lid).with(spout).with(handle)
}
