//! Axis-aligned boxes (object bounds, BVH nodes) and oriented boxes (an
//! object's box in its own frame).

use glam::{Affine3A, Mat4, Vec3};

/// Axis-aligned box. `Aabb::EMPTY` has min > max and grows by `grow`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner (world units).
    pub min: Vec3,
    /// Maximum corner (world units).
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box: min = +∞, max = -∞, so any `grow`/`union` replaces it.
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// Box with the given corners (not checked: min > max gives an empty box).
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Aabb { min, max }
    }
    /// Smallest box holding every point; [`Aabb::EMPTY`] for none.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grow_point(p))
    }
    /// This box grown to include `p`.
    pub fn grow_point(self, p: Vec3) -> Self {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }
    /// Smallest box holding both boxes.
    pub fn union(self, o: Aabb) -> Self {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }
    /// True when min > max on any axis (e.g. [`Aabb::EMPTY`]).
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }
    /// Midpoint of min and max.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
    /// Size per axis, max - min, clamped at 0 for empty boxes.
    pub fn extent(&self) -> Vec3 {
        (self.max - self.min).max(Vec3::ZERO)
    }
    /// Surface area; 0 for an empty box (the SAH's measure).
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
    /// True when `p` lies inside or on the boundary.
    pub fn contains_point(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
    /// True when `o` lies entirely inside this box (boundaries included).
    pub fn contains(&self, o: &Aabb) -> bool {
        o.min.cmpge(self.min).all() && o.max.cmple(self.max).all()
    }
    /// True when the boxes intersect (closed intervals: touching counts).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }
    /// World box of this box under an affine transform (Arvo's method).
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        let t = m.w_axis.truncate();
        let (mut min, mut max) = (t, t);
        for (i, col) in [m.x_axis, m.y_axis, m.z_axis].into_iter().enumerate() {
            let col = col.truncate();
            let a = col * self.min[i];
            let b = col * self.max[i];
            min += a.min(b);
            max += a.max(b);
        }
        Aabb { min, max }
    }
}

/// A box in an object's own frame, placed in the world by an affine map:
/// for rotated or sheared geometry, a much tighter bound than its world
/// box. Points `to_world(p)` for `p` in `local` must hold everything the
/// object's draw can rasterize, as [`Aabb`] bounds must.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox {
    /// The box in the object's frame.
    pub local: Aabb,
    /// Object frame to world (invertible).
    pub to_world: Affine3A,
}

impl OrientedBox {
    /// `local` placed by `to_world`.
    pub fn new(local: Aabb, to_world: Affine3A) -> Self {
        OrientedBox { local, to_world }
    }
    /// Its world-axis box.
    pub fn world_bounds(&self) -> Aabb {
        self.local.transformed(&Mat4::from(self.to_world))
    }
    /// World to object frame, when the map is invertible and the box and
    /// the inverse are finite and non-empty; `None` otherwise.
    pub fn to_local(&self) -> Option<Affine3A> {
        let finite = |v: Vec3| v.is_finite();
        let ok = finite(self.local.min) && finite(self.local.max) && !self.local.is_empty() && self.to_world.is_finite();
        let det = self.to_world.matrix3.determinant();
        if !ok || !det.is_normal() {
            return None;
        }
        let inv = self.to_world.inverse();
        inv.is_finite().then_some(inv)
    }
}
