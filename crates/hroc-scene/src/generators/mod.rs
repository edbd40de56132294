//! Built-in deterministic scene generators.
//!
//! Every generator takes an object count and a seed and returns exactly that
//! many objects, instancing a few dozen shared meshes, plus a 10 s camera
//! path through the scene. World size grows with the object count so the
//! density (and so the occlusion) stays like the paper's scene.
//!
//! Determinism: the same key, count and seed give the same scene on a given
//! platform (own RNG, no hash-order dependence); transcendental `f32`
//! functions may differ in the last bit between platforms' math libraries.

mod downtown;
mod factory;
mod fantasy;
mod figures;
mod houses;
mod library;
mod radial_city;
pub use crate::rng;
mod rooms;
mod satellites;
pub mod shapes;
mod teapots;

use glam::{Mat4, Quat, Vec3};
use std::collections::HashMap;

use crate::error::{Error, Result};
use crate::{Aabb, CameraKey, CameraPath, Scene};
use rng::Rng;
use shapes::Part;

/// A built-in scene.
#[derive(Debug)]
pub struct Generator {
    pub key: &'static str,
    pub description: &'static str,
    /// Object count used when none is given (sized for a CPU renderer).
    pub default_objects: usize,
    /// Object count of the scene in the papers (Lee et al. 2021 Table 1;
    /// Lee's thesis, Table 1); for a scene of no paper (`houses`), its default.
    pub paper_objects: usize,
}

static GENERATORS: [Generator; 11] = [
    Generator { key: "rooms", description: "grid of rooms joined by doorways, furnished (IOC poster RM)", default_objects: 2_753, paper_objects: 2_753 },
    Generator {
        key: "downtown",
        description: "street grid of varied buildings and street furniture, eye-level drive (IOC poster DT)",
        default_objects: 15_000,
        paper_objects: 31_392,
    },
    Generator {
        key: "figures",
        description: "dense field of low-poly geometric figures, very high depth complexity (IOC poster GF)",
        default_objects: 20_000,
        paper_objects: 72_000,
    },
    Generator { key: "fantasy", description: "few, very detailed objects: rocks, trees, arches, crystals (HROC FN)", default_objects: 1_200, paper_objects: 7_437 },
    Generator { key: "factory", description: "wide factory hall: racks, machines, tanks, barrels, pipes (HROC FC)", default_objects: 15_000, paper_objects: 46_600 },
    Generator { key: "radial-city", description: "radial city of low-poly buildings, tall towers at the centre (HROC RC)", default_objects: 20_000, paper_objects: 73_812 },
    Generator { key: "radial-city-fast", description: "radial-city with fast rotations and a backward walk (HROC RC')", default_objects: 20_000, paper_objects: 73_812 },
    Generator {
        key: "satellites",
        description: "field of satellites, rocks and a few planets of varied size and detail (HROC ST)",
        default_objects: 20_000,
        paper_objects: 120_000,
    },
    Generator { key: "library", description: "rows of shelves without backs; the books are the occluders (statistical OQ paper)", default_objects: 15_000, paper_objects: 40_000 },
    Generator { key: "teapots", description: "randomly placed teapots in a volume (statistical OQ paper)", default_objects: 5_000, paper_objects: 5_000 },
    Generator {
        key: "houses",
        description: "grid of hollow furnished buildings; the path enters two and leaves them (visible sets that collapse)",
        default_objects: 11_000,
        paper_objects: 11_000,
    },
];

/// The generator for a scene key (`rooms`, `radial-city-fast`, ...).
pub fn find(key: &str) -> Option<&'static Generator> {
    GENERATORS.iter().find(|g| g.key == key)
}

/// All scene keys, in table order.
pub fn keys() -> Vec<&'static str> {
    GENERATORS.iter().map(|g| g.key).collect()
}

/// All generators, in table order.
pub fn all() -> &'static [Generator] {
    &GENERATORS
}

/// Generates scene `g` with exactly `objects.max(1)` objects.
pub fn generate(g: &Generator, objects: usize, seed: u64) -> Result<Scene> {
    let n = objects.max(1);
    // radial-city-fast is radial-city's scene: same RNG stream, other path.
    let stream = if g.key == "radial-city-fast" { "radial-city" } else { g.key };
    let mut b = Builder::new(g.key, n, Rng::derive(seed, stream));
    let path = match g.key {
        "rooms" => rooms::build(&mut b),
        "downtown" => downtown::build(&mut b),
        "figures" => figures::build(&mut b),
        "fantasy" => fantasy::build(&mut b),
        "factory" => factory::build(&mut b),
        "radial-city" => radial_city::build(&mut b, false),
        "radial-city-fast" => radial_city::build(&mut b, true),
        "satellites" => satellites::build(&mut b),
        "library" => library::build(&mut b),
        "teapots" => teapots::build(&mut b),
        "houses" => houses::build(&mut b),
        other => return Err(Error::UnknownScene(other.to_string(), keys().join(", "))),
    };
    if b.scene.objects.len() != n {
        return Err(Error::Invalid(format!("generator '{}' made {} objects instead of {n}", g.key, b.scene.objects.len())));
    }
    b.scene.path = path;
    b.scene.validate()?;
    Ok(b.scene)
}

/// Scene under construction: meshes, objects capped at the requested count.
pub(crate) struct Builder {
    pub scene: Scene,
    pub rng: Rng,
    pub n: usize,
}

impl Builder {
    fn new(name: &str, n: usize, rng: Rng) -> Self {
        let scene = Scene { name: name.to_string(), objects: Vec::with_capacity(n), ..Scene::default() };
        Builder { scene, rng, n }
    }

    pub fn mesh(&mut self, name: &str, part: Part) -> u32 {
        self.scene.meshes.push(part.into_mesh(name));
        (self.scene.meshes.len() - 1) as u32
    }

    /// Objects still to place.
    pub fn left(&self) -> usize {
        self.n - self.scene.objects.len()
    }

    /// Adds an object unless the count is reached (so structure generated
    /// for a tiny count is simply cut short).
    pub fn push(&mut self, mesh: u32, transform: Mat4, color: [f32; 3]) -> bool {
        if self.left() == 0 {
            return false;
        }
        self.scene.push_object(mesh, transform, color);
        true
    }

    /// World box `mesh` would get under `transform`.
    pub fn bounds(&self, mesh: u32, transform: &Mat4) -> Aabb {
        self.scene.meshes[mesh as usize].bounds.transformed(transform)
    }
}

/// Translation * yaw rotation * scale.
pub(crate) fn trs(pos: Vec3, yaw: f32, scale: Vec3) -> Mat4 {
    Mat4::from_scale_rotation_translation(scale, Quat::from_rotation_y(yaw), pos)
}

/// Arc-length parametrised polyline.
pub(crate) struct Polyline {
    pub pts: Vec<Vec3>,
    cum: Vec<f32>,
}

impl Polyline {
    pub fn new(pts: Vec<Vec3>) -> Self {
        let mut pts = pts;
        pts.dedup_by(|a, b| a.distance_squared(*b) < 1e-10);
        let mut cum = vec![0.0];
        for w in pts.windows(2) {
            cum.push(cum.last().unwrap() + w[0].distance(w[1]));
        }
        Polyline { pts, cum }
    }

    pub fn length(&self) -> f32 {
        *self.cum.last().unwrap()
    }

    /// Distance from `p` to the nearest point of the polyline.
    pub fn distance(&self, p: Vec3) -> f32 {
        if self.pts.len() == 1 {
            return p.distance(self.pts[0]);
        }
        self.pts
            .windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                let t = ((p - w[0]).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                p.distance(w[0] + d * t)
            })
            .fold(f32::INFINITY, f32::min)
    }

    /// Point at arc length `s`, extrapolated along the end segments.
    pub fn at(&self, s: f32) -> Vec3 {
        if self.pts.len() == 1 {
            return self.pts[0];
        }
        let i = self.cum.partition_point(|&c| c <= s).clamp(1, self.pts.len() - 1);
        let (a, b) = (self.pts[i - 1], self.pts[i]);
        let len = self.cum[i] - self.cum[i - 1];
        a + (b - a) * ((s - self.cum[i - 1]) / len)
    }
}

/// Camera key at time `t`.
pub(crate) fn key(t: f32, eye: Vec3, target: Vec3) -> CameraKey {
    CameraKey { t, eye: eye.to_array(), target: target.to_array(), up: [0.0, 1.0, 0.0], fov_y_deg: 60.0 }
}

/// A 10 s walk along `points` at constant speed, looking at the point
/// `look_ahead` further along the path (so corners turn the view smoothly).
/// Keys sit on every corner (corners are never cut) and at least
/// `min_keys` keys in all. A path of one point looks around on the spot.
pub(crate) fn walk_path(points: Vec<Vec3>, look_ahead: f32, min_keys: usize) -> CameraPath {
    let line = Polyline::new(points);
    let total = line.length();
    if total < 1e-3 {
        return look_around(line.pts[0], look_ahead.max(1.0), min_keys);
    }
    let step = total / (min_keys.max(2) - 1) as f32;
    let mut ss = vec![0.0f32];
    for i in 1..line.pts.len() {
        let (a, b) = (line.cum[i - 1], line.cum[i]);
        let k = ((b - a) / step).ceil().max(1.0) as usize;
        ss.extend((1..=k).map(|j| a + (b - a) * j as f32 / k as f32));
    }
    let keys = ss.iter().map(|&s| key(10.0 * s / total, line.at(s), line.at(s + look_ahead))).collect();
    CameraPath::new(keys)
}

/// Standing at `eye`, turning once around in 10 s.
pub(crate) fn look_around(eye: Vec3, dist: f32, keys: usize) -> CameraPath {
    let k = keys.max(17);
    CameraPath::new(
        (0..k)
            .map(|i| {
                let s = i as f32 / (k - 1) as f32;
                let a = s * std::f32::consts::TAU;
                key(10.0 * s, eye, eye + Vec3::new(a.sin(), 0.0, -a.cos()) * dist)
            })
            .collect(),
    )
}

/// The space the camera moves through, kept free of objects: within
/// `radius` of the path horizontally and from `below` under the eye to
/// `above` over it vertically.
pub(crate) struct Clearance {
    pts: Vec<Vec3>,
    grid: HashMap<(i32, i32), Vec<u32>>,
    cell: f32,
    radius: f32,
    below: f32,
    above: f32,
}

impl Clearance {
    pub fn new(paths: &[&CameraPath], radius: f32, below: f32, above: f32) -> Self {
        let cell = (radius * 4.0).max(1.0);
        let mut c = Clearance { pts: vec![], grid: HashMap::new(), cell, radius, below, above };
        for p in paths {
            let line = Polyline::new(p.keys.iter().map(|k| Vec3::from(k.eye)).collect());
            let n = (line.length() / (radius * 0.5)).ceil() as usize;
            for i in 0..=n {
                c.add(line.at(line.length() * i as f32 / n.max(1) as f32));
            }
        }
        c
    }

    fn add(&mut self, p: Vec3) {
        let k = ((p.x / self.cell).floor() as i32, (p.z / self.cell).floor() as i32);
        self.grid.entry(k).or_default().push(self.pts.len() as u32);
        self.pts.push(p);
    }

    /// True when the box reaches into the kept-free space.
    pub fn blocks(&self, b: &Aabb) -> bool {
        let r = self.radius;
        let hit = |p: &Vec3| {
            let dx = (b.min.x - p.x).max(p.x - b.max.x).max(0.0);
            let dz = (b.min.z - p.z).max(p.z - b.max.z).max(0.0);
            dx * dx + dz * dz < r * r && b.max.y > p.y - self.below && b.min.y < p.y + self.above
        };
        let lo = ((b.min.x - r) / self.cell).floor() as i32;
        let hi = ((b.max.x + r) / self.cell).floor() as i32;
        let lo_z = ((b.min.z - r) / self.cell).floor() as i32;
        let hi_z = ((b.max.z + r) / self.cell).floor() as i32;
        let cells = (hi - lo + 1) as i64 * (hi_z - lo_z + 1) as i64;
        if cells > self.grid.len() as i64 {
            return self.pts.iter().any(hit);
        }
        (lo..=hi).any(|x| (lo_z..=hi_z).any(|z| self.grid.get(&(x, z)).is_some_and(|ix| ix.iter().any(|&i| hit(&self.pts[i as usize])))))
    }
}

/// Eye points of a flight through a box centred on the origin with half
/// size `half`: three quarters of a loop around the centre at about half
/// the box's reach, weaving up and down and in and out, so the view always
/// looks across the volume rather than out of it.
pub(crate) fn flight(rng: &mut Rng, half: Vec3, points: usize) -> Vec<Vec3> {
    use std::f32::consts::TAU;
    let (a0, py, pr) = (rng.range(0.0, TAU), rng.range(0.0, TAU), rng.range(0.0, TAU));
    (0..points)
        .map(|i| {
            let s = i as f32 / (points - 1) as f32;
            let a = a0 + s * TAU * 0.75;
            let r = 0.5 + 0.15 * (pr + s * TAU * 1.5).sin();
            Vec3::new(half.x * r * a.cos(), half.y * 0.35 * (py + s * TAU).sin(), half.z * r * a.sin())
        })
        .collect()
}

/// A self-avoiding walk over grid points (i, j) in [lo, hi]^2, up to
/// `steps` steps, mostly straight, starting towards the grid's centre and
/// turning towards it, so the view looks across the scene, not out of it.
/// The longest of a few tries.
pub(crate) fn grid_walk(rng: &mut Rng, lo: usize, hi: usize, steps: usize) -> Vec<(usize, usize)> {
    const DIRS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
    let centre = (lo + hi) as f32 * 0.5;
    // How much direction d at (i, j) heads towards the centre.
    let toward = |(i, j): (usize, usize), d: usize| DIRS[d].0 as f32 * (centre - i as f32) + DIRS[d].1 as f32 * (centre - j as f32);
    let mut best: Vec<(usize, usize)> = vec![];
    for _ in 0..24 {
        let start = (lo + rng.below(hi - lo + 1), lo + rng.below(hi - lo + 1));
        let mut walk = vec![start];
        let mut dir = (0..4).max_by(|&a, &b| toward(start, a).total_cmp(&toward(start, b))).unwrap_or(0);
        let mut straight = 0;
        while walk.len() <= steps {
            let here = *walk.last().unwrap();
            let (l, r) = ((dir + 1) % 4, (dir + 3) % 4);
            let (l, r) = if toward(here, l) >= toward(here, r) { (l, r) } else { (r, l) };
            let dirs = if straight >= 2 && rng.chance(0.5) { [l, dir, r] } else { [dir, l, r] };
            let next = dirs.iter().find_map(|&d| {
                let (ni, nj) = (here.0 as i64 + DIRS[d].0, here.1 as i64 + DIRS[d].1);
                let inside = (lo as i64..=hi as i64).contains(&ni) && (lo as i64..=hi as i64).contains(&nj);
                (inside && !walk.contains(&(ni as usize, nj as usize))).then_some((d, (ni as usize, nj as usize)))
            });
            let Some((d, cell)) = next else { break };
            straight = if d == dir { straight + 1 } else { 0 };
            dir = d;
            walk.push(cell);
        }
        if walk.len() > best.len() {
            best = walk;
        }
        if best.len() > steps {
            break;
        }
    }
    best
}
