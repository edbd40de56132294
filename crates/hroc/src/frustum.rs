//! Views in the conventions engines use: a right-handed perspective
//! projection with standard (near → 0) or reversed (near → 1) depth and a
//! finite or infinite far plane, or a right-handed orthographic one (a
//! directional light's shadow cascade). Everything the culling passes need
//! of a view (planes, eye, pixel rays, near distance) is derived here, once,
//! on the CPU.

use glam::{Mat4, Vec3, Vec4};

use crate::error::{Error, Result};

/// Which end of the depth range is near.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthRange {
    /// Near plane at depth 0, far at 1; the host's depth test is `Less` or
    /// `LessEqual` and it clears to 1.
    #[default]
    Standard,
    /// Near plane at depth 1, far (or infinity) at 0; the host's depth test is
    /// `Greater` or `GreaterEqual` and it clears to 0.
    Reversed,
}

impl DepthRange {
    /// The range a right-handed projection maps depth to: standard where
    /// depth grows away from the viewer, reversed where it falls; `None`
    /// where `proj` keeps depth constant (no range at all).
    pub fn of_projection(proj: &Mat4) -> Option<DepthRange> {
        // Orthographic: z_ndc = p22 z + p32, with z = -d. Perspective
        // (clip w = -z = d): z_ndc = -p22 + p32 / d.
        let grows = if proj.z_axis.w == 0.0 { -proj.z_axis.z } else { -proj.w_axis.z };
        match grows.partial_cmp(&0.0)? {
            std::cmp::Ordering::Greater => Some(DepthRange::Standard),
            std::cmp::Ordering::Less => Some(DepthRange::Reversed),
            std::cmp::Ordering::Equal => None,
        }
    }
}

/// The six frustum planes (left, right, bottom, top, near, far) of a
/// standard-depth view-projection matrix, each `n·p + d >= 0` inside
/// (Gribb–Hartmann).
pub fn frustum_planes(view_proj: &Mat4) -> [Vec4; 6] {
    frustum_planes_for(view_proj, DepthRange::Standard)
}

/// [`frustum_planes`] for either depth range: plane 4 is always the near
/// plane. The plane at infinity of an infinite projection has no normal; it
/// is returned as `(0, 0, 0, 1)`, which every point is inside.
pub fn frustum_planes_for(view_proj: &Mat4, depth: DepthRange) -> [Vec4; 6] {
    let r = view_proj.transpose(); // rows of view_proj as columns
    let (r0, r1, r2, r3) = (r.x_axis, r.y_axis, r.z_axis, r.w_axis);
    // wgpu clip space: -w <= x,y <= w, 0 <= z <= w.
    let (near, far) = match depth {
        DepthRange::Standard => (r2, r3 - r2),
        DepthRange::Reversed => (r3 - r2, r2),
    };
    let planes = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, near, far];
    planes.map(|p| {
        let len = p.truncate().length();
        if len > 1e-12 * p.w.abs().max(1.0) {
            p / len
        } else {
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        }
    })
}

/// Conservative box-vs-frustum test: false only when the box lies wholly
/// outside one plane (boxes near corners may pass; that is conservative).
pub fn aabb_in_frustum(planes: &[Vec4; 6], min: Vec3, max: Vec3) -> bool {
    planes.iter().all(|p| {
        let n = p.truncate();
        let v = Vec3::select(n.cmpge(Vec3::ZERO), max, min); // the "positive vertex"
        n.dot(v) + p.w >= 0.0
    })
}

/// A view as the host renders it this frame: right-handed, perspective or
/// orthographic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewDesc {
    /// World to view space.
    pub view: Mat4,
    /// View to clip space: a right-handed perspective projection, symmetric
    /// or off-centre, finite or infinite far plane; or a right-handed
    /// orthographic one (`Mat4::orthographic_rh`, or its reversed-depth
    /// form), whose near plane may lie behind the camera position.
    pub proj: Mat4,
    /// The host's pipelines clamp depth rather than clip it at the near
    /// plane (wgpu's `PrimitiveState::unclipped_depth`, as shadow passes
    /// "pancake" casters in front of a cascade): geometry in front of the
    /// near plane is drawn at the near depth, so the near plane culls
    /// nothing, and every box that reaches it is drawn untested.
    pub unclipped_depth: bool,
}

/// What the culling passes know of a view (the CPU side of the `Frame`
/// uniform in `common.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewGeometry {
    /// `proj * view`.
    pub view_proj: Mat4,
    /// Frustum planes, plane 4 the near plane ([`frustum_planes_for`]),
    /// which with [`ViewDesc::unclipped_depth`] is `(0, 0, 0, 1)`: it culls
    /// nothing.
    pub planes: [Vec4; 6],
    /// The near plane: a box that reaches it (or within [`ViewGeometry::near`]
    /// of it) is drawn untested.
    pub near_plane: Vec4,
    /// Camera position in world space.
    pub eye: Vec3,
    /// Columns x, y, z: world offsets such that the ray through NDC (x, y)
    /// is `origin + t * (x * X + y * Y + Z)`, reaching the near plane at
    /// t = 1 (orthographic: the far plane at t = 2). Built from the view
    /// basis, not by unprojecting through the inverse view-projection, which
    /// loses the direction to cancellation.
    pub ray_dirs: Mat4,
    /// Columns x, y and w: the origin of the ray through NDC (x, y) is
    /// `x * X + y * Y + W` (perspective: the eye; orthographic: a point
    /// one ray length in front of the near plane).
    pub ray_origins: Mat4,
    /// Which end of the depth range `proj` maps near to
    /// ([`DepthRange::of_projection`]): it must be the view's targets'
    /// ([`crate::ViewTargets::depth_range`]).
    pub depth: DepthRange,
    /// Distance from the eye to the near plane (orthographic: the margin
    /// within which a box counts as reaching the near plane, a thousandth
    /// of the depth range).
    pub near: f32,
    /// Distance from the eye to the far plane (infinite for an infinite projection).
    pub far: f32,
    /// True for an orthographic projection.
    pub orthographic: bool,
}

impl ViewGeometry {
    /// A pixel's size at distance `d` from the eye is `a + b d` for a
    /// target of `size` pixels: `(a, b)` of its height, then of the larger
    /// of its width and height (perspective: `a = 0`; orthographic: `b = 0`).
    pub fn footprint(&self, (w, h): (u32, u32)) -> Vec4 {
        let (w, h) = (w as f32, h as f32);
        let o = (2.0 * self.ray_origins.x_axis.truncate().length() / w, 2.0 * self.ray_origins.y_axis.truncate().length() / h);
        let d = (2.0 * self.ray_dirs.x_axis.truncate().length() / self.near / w, 2.0 * self.ray_dirs.y_axis.truncate().length() / self.near / h);
        Vec4::new(o.1, d.1, o.0.max(o.1), d.0.max(d.1))
    }

    /// The `Frame` uniform every culling pass reads, for a depth attachment
    /// of `size` pixels.
    pub fn uniform(&self, size: (u32, u32), object_count: u32, node_count: u32) -> crate::layout::FrameUniform {
        let (w, h) = (size.0 as f32, size.1 as f32);
        crate::layout::FrameUniform {
            view_proj: self.view_proj.to_cols_array_2d(),
            ray_dirs: self.ray_dirs.to_cols_array_2d(),
            ray_origins: self.ray_origins.to_cols_array_2d(),
            eye: self.eye.extend(1.0).to_array(),
            viewport: [w, h, 1.0 / w, 1.0 / h],
            footprint: self.footprint(size).to_array(),
            planes: self.planes.map(|p| p.to_array()),
            near_plane: self.near_plane.to_array(),
            object_count,
            node_count,
            near: self.near,
            reversed: (self.depth == DepthRange::Reversed) as u32,
        }
    }
}

impl ViewDesc {
    /// A right-handed standard-depth view from a look-at camera (what hroc's
    /// own scenes and camera paths use).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y_deg: f32, aspect: f32, near: f32, far: f32) -> Self {
        ViewDesc { view: Mat4::look_at_rh(eye, target, up), proj: Mat4::perspective_rh(fov_y_deg.to_radians(), aspect, near, far), unclipped_depth: false }
    }

    /// Checks the projection and derives the view's geometry, with the
    /// depth range the projection maps to. Errors (never panics) on a
    /// non-perspective or non-invertible matrix, and on one without a
    /// depth range.
    pub fn geometry(&self) -> Result<ViewGeometry> {
        let bad = |m: &str| Err(Error::InvalidView(m.to_string()));
        if !self.view.is_finite() || !self.proj.is_finite() {
            return bad("view or projection matrix is not finite");
        }
        let p = self.proj;
        let Some(depth) = DepthRange::of_projection(&p) else {
            return bad("projection maps every distance to one depth");
        };
        if p.x_axis.w == 0.0 && p.y_axis.w == 0.0 && p.z_axis.w == 0.0 && p.w_axis.w == 1.0 {
            return self.orthographic(depth);
        }
        // Perspective: clip w = s * z_view with s = ±1 (right-handed: -1).
        let s = p.z_axis.w;
        if (s.abs() - 1.0).abs() > 1e-5 || p.x_axis.w != 0.0 || p.y_axis.w != 0.0 || p.w_axis.w != 0.0 {
            return bad("projection is neither perspective nor orthographic");
        }
        if p.x_axis.x == 0.0 || p.y_axis.y == 0.0 || self.view.determinant().abs() < 1e-12 {
            return bad("view or projection matrix is singular");
        }
        // The box tests keep the faces a right-handed view sees in front
        // (counter-clockwise on screen); a left-handed projection or a
        // mirrored view would test the back faces instead.
        if s > 0.0 || self.view.determinant() * p.x_axis.x * p.y_axis.y < 0.0 {
            return bad("left-handed or mirrored views are not supported: use a right-handed view and projection");
        }
        let view_proj = p * self.view;
        let mut planes = frustum_planes_for(&view_proj, depth);
        let inv_view = self.view.inverse();
        let eye = inv_view.w_axis.truncate();
        // Near distance: the eye lies `near` behind the (normalized) near plane.
        let near = -(planes[4].truncate().dot(eye) + planes[4].w);
        let far_plane = planes[5];
        let far = if far_plane.truncate() == Vec3::ZERO { f32::INFINITY } else { far_plane.truncate().dot(eye) + far_plane.w };
        // NaN fails both comparisons, so it is refused too.
        let valid = near > 0.0 && far > near;
        if !valid {
            return Err(Error::InvalidView(format!("projection has no valid near and far planes for {depth:?} depth (near {near}, far {far})")));
        }
        // A finite far plane from the near plane's normal: the far plane of
        // a standard projection, r3 - r2, cancels and tilts at large far/near.
        if far.is_finite() {
            let n = planes[4].truncate();
            planes[5] = (-n).extend(n.dot(eye) + far);
        }
        // View-space direction of the ray through NDC (x, y), scaled to reach
        // the near plane: (near (x - s p20) / p00, near (y - s p21) / p11, s near).
        let (p00, p11, p20, p21) = (p.x_axis.x, p.y_axis.y, p.z_axis.x, p.z_axis.y);
        let cx = inv_view.transform_vector3(Vec3::new(near / p00, 0.0, 0.0));
        let cy = inv_view.transform_vector3(Vec3::new(0.0, near / p11, 0.0));
        let cz = inv_view.transform_vector3(Vec3::new(-s * p20 * near / p00, -s * p21 * near / p11, s * near));
        let ray_dirs = Mat4::from_cols(cx.extend(0.0), cy.extend(0.0), cz.extend(0.0), Vec4::W);
        let ray_origins = Mat4::from_cols(Vec4::ZERO, Vec4::ZERO, Vec4::ZERO, eye.extend(1.0));
        Ok(self.unclip(ViewGeometry { view_proj, planes, near_plane: planes[4], eye, ray_dirs, ray_origins, depth, near, far, orthographic: false }))
    }

    /// With [`ViewDesc::unclipped_depth`], a frustum whose near plane culls nothing.
    fn unclip(&self, mut g: ViewGeometry) -> ViewGeometry {
        if self.unclipped_depth {
            g.planes[4] = Vec4::W;
        }
        g
    }

    /// [`ViewDesc::geometry`] of an orthographic projection: parallel rays
    /// along the view direction, from one ray length in front of the near
    /// plane (t = 1 there, t = 2 on the far plane).
    fn orthographic(&self, depth: DepthRange) -> Result<ViewGeometry> {
        let bad = |m: String| Err(Error::InvalidView(m));
        let p = self.proj;
        if p.x_axis.x == 0.0 || p.y_axis.y == 0.0 || p.z_axis.z == 0.0 || self.view.determinant().abs() < 1e-12 {
            return bad("view or projection matrix is singular".into());
        }
        if self.view.determinant() * p.x_axis.x * p.y_axis.y < 0.0 {
            return bad("mirrored views are not supported: use a right-handed view and projection".into());
        }
        let view_proj = p * self.view;
        let planes = frustum_planes_for(&view_proj, depth);
        let inv_view = self.view.inverse();
        let eye = inv_view.w_axis.truncate();
        // View-space points on the near and far planes, from the projection
        // alone (x = (X - p30) / p00 and so on), then to world space.
        let (near_z, far_z) = match depth {
            DepthRange::Standard => (0.0, 1.0),
            DepthRange::Reversed => (1.0, 0.0),
        };
        let at = |x: f32, y: f32, z: f32| Vec3::new((x - p.w_axis.x) / p.x_axis.x, (y - p.w_axis.y) / p.y_axis.y, (z - p.w_axis.z) / p.z_axis.z);
        let centre = inv_view.transform_point3(at(0.0, 0.0, near_z));
        let right = inv_view.transform_vector3(Vec3::new(1.0 / p.x_axis.x, 0.0, 0.0));
        let up = inv_view.transform_vector3(Vec3::new(0.0, 1.0 / p.y_axis.y, 0.0));
        let dir = inv_view.transform_vector3(at(0.0, 0.0, far_z) - at(0.0, 0.0, near_z));
        let length = dir.length();
        if !(length > 0.0 && length.is_finite()) {
            return bad("orthographic projection has no depth range".into());
        }
        let ray_dirs = Mat4::from_cols(Vec4::ZERO, Vec4::ZERO, dir.extend(0.0), Vec4::W);
        let ray_origins = Mat4::from_cols(right.extend(0.0), up.extend(0.0), Vec4::ZERO, (centre - dir).extend(1.0));
        let near = 1e-3 * length;
        let far = planes[5].truncate().dot(eye) + planes[5].w;
        Ok(self.unclip(ViewGeometry { view_proj, planes, near_plane: planes[4], eye, ray_dirs, ray_origins, depth, near, far, orthographic: true }))
    }
}
