//! View conventions (GPU-free): standard and reversed depth, finite and
//! infinite far planes give the culler the same rays and planes; views it
//! cannot cull are refused; orthographic views get parallel rays that
//! cross the near plane at t = 1 and the far plane at t = 2 through every
//! pixel.

#[test]
fn views_in_every_convention_give_the_same_rays_and_planes() {
    use glam::{Mat4, Vec3};
    use hroc::{DepthRange, ViewDesc};
    let (eye, target) = (Vec3::new(3.0, 2.0, 5.0), Vec3::new(-1.0, 0.5, -4.0));
    let view = Mat4::look_at_rh(eye, target, Vec3::Y);
    let (fov, aspect, near, far) = (1.0f32, 1.6, 0.25, 400.0);
    let standard = ViewDesc { view, proj: Mat4::perspective_rh(fov, aspect, near, far), unclipped_depth: false }.geometry().unwrap();
    let infinite = ViewDesc { view, proj: Mat4::perspective_infinite_rh(fov, aspect, near), unclipped_depth: false }.geometry().unwrap();
    let reversed = ViewDesc { view, proj: Mat4::perspective_rh(fov, aspect, far, near), unclipped_depth: false }.geometry().unwrap();
    let rev_inf = ViewDesc { view, proj: Mat4::perspective_infinite_reverse_rh(fov, aspect, near), unclipped_depth: false }.geometry().unwrap();
    for g in [&infinite, &reversed, &rev_inf] {
        assert!((g.near - near).abs() < 1e-4, "near {}", g.near);
        assert!(g.eye.distance(eye) < 1e-4);
        assert!(g.ray_dirs.abs_diff_eq(standard.ray_dirs, 1e-4), "{:?}", g.ray_dirs);
        for i in 0..5 {
            assert!(g.planes[i].abs_diff_eq(standard.planes[i], 1e-4), "plane {i}: {:?} vs {:?}", g.planes[i], standard.planes[i]);
        }
    }
    assert!(infinite.far.is_infinite() && rev_inf.far.is_infinite());
    assert!((reversed.far - far).abs() < 0.1 && (standard.far - far).abs() < 0.1);
    // The depth range is the projection's: a host states it once, with
    // its targets, and a view checks the projection against it.
    use DepthRange::{Reversed, Standard};
    assert_eq!([standard.depth, infinite.depth, reversed.depth, rev_inf.depth], [Standard, Standard, Reversed, Reversed]);
    assert_eq!(DepthRange::of_projection(&Mat4::ZERO), None);
    // Left-handed and mirrored views are refused: the box tests would keep
    // the back faces.
    assert!(ViewDesc { view: Mat4::look_at_lh(eye, target, Vec3::Y), proj: Mat4::perspective_lh(fov, aspect, near, far), unclipped_depth: false }.geometry().is_err());
    assert!(ViewDesc { view: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * view, proj: Mat4::perspective_rh(fov, aspect, near, far), unclipped_depth: false }.geometry().is_err());
    // Non-finite matrices are refused, not mis-culled.
    assert!(ViewDesc { view: Mat4::NAN, proj: Mat4::perspective_rh(fov, aspect, near, far), unclipped_depth: false }.geometry().is_err());
    // The look-at helper agrees with the old camera basis.
    let helper = ViewDesc::look_at(eye, target, Vec3::Y, fov.to_degrees(), aspect, near, far).geometry().unwrap();
    assert!(helper.ray_dirs.abs_diff_eq(standard.ray_dirs, 1e-5));
}

#[test]
fn orthographic_views_give_parallel_rays_through_every_pixel() {
    use glam::{Mat4, Vec2, Vec3, Vec4};
    use hroc::{DepthRange, ViewDesc};
    // A light looking down and sideways; its near plane behind the camera
    // position, as shadow cascades place it; off-centre.
    let view = Mat4::look_at_rh(Vec3::new(10.0, 30.0, 5.0), Vec3::new(0.0, 0.0, -3.0), Vec3::Y);
    let (l, r, b, t, near, far) = (-12.0f32, 20.0, -8.0, 10.0, -15.0, 60.0);
    let standard = ViewDesc { view, proj: Mat4::orthographic_rh(l, r, b, t, near, far), unclipped_depth: false }.geometry().unwrap();
    let reversed = ViewDesc { view, proj: Mat4::orthographic_rh(l, r, b, t, far, near), unclipped_depth: false }.geometry().unwrap();
    for (g, depth) in [(&standard, DepthRange::Standard), (&reversed, DepthRange::Reversed)] {
        assert!(g.orthographic);
        let (near_z, far_z) = if depth == DepthRange::Standard { (0.0, 1.0) } else { (1.0, 0.0) };
        for ndc in [Vec2::new(-1.0, -1.0), Vec2::new(0.3, -0.7), Vec2::new(1.0, 1.0)] {
            let dir = (g.ray_dirs * Vec4::new(ndc.x, ndc.y, 1.0, 0.0)).truncate();
            let origin = (g.ray_origins * Vec4::new(ndc.x, ndc.y, 0.0, 1.0)).truncate();
            for (k, z) in [(1.0, near_z), (2.0, far_z)] {
                let clip = g.view_proj.project_point3(origin + k * dir);
                assert!(clip.abs_diff_eq(Vec3::new(ndc.x, ndc.y, z), 1e-4), "{depth:?} ndc {ndc} t {k}: {clip}");
            }
        }
        for i in 0..6 {
            assert!(g.planes[i].abs_diff_eq(standard.planes[i], 1e-4), "plane {i}: {:?} vs {:?}", g.planes[i], standard.planes[i]);
        }
        // A pixel is the same size at every distance: (r - l) / width wide,
        // (t - b) / height high.
        let f = g.footprint((320, 90));
        assert!((f.x - 18.0 / 90.0).abs() < 1e-4 && f.y == 0.0 && (f.z - 0.2).abs() < 1e-4 && f.w == 0.0, "{f}");
    }
    // A left-handed orthographic projection is a reversed right-handed one
    // whose planes lie behind the eye: a view on standard targets refuses it.
    let lh = ViewDesc { view, proj: Mat4::orthographic_lh(l, r, b, t, near, far), unclipped_depth: false }.geometry();
    assert_eq!(lh.map(|g| g.depth).ok(), Some(DepthRange::Reversed));
    // Mirrored orthographic views are refused.
    assert!(ViewDesc { view: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * view, proj: Mat4::orthographic_rh(l, r, b, t, near, far), unclipped_depth: false }.geometry().is_err());
}
