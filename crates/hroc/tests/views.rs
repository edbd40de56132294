//! View conventions (GPU-free): standard and reversed depth, finite and
//! infinite far planes give the culler the same rays and planes; views it
//! cannot cull are refused.

#[test]
fn views_in_every_convention_give_the_same_rays_and_planes() {
    use glam::{Mat4, Vec3};
    use hroc::{DepthRange, ViewDesc};
    let (eye, target) = (Vec3::new(3.0, 2.0, 5.0), Vec3::new(-1.0, 0.5, -4.0));
    let view = Mat4::look_at_rh(eye, target, Vec3::Y);
    let (fov, aspect, near, far) = (1.0f32, 1.6, 0.25, 400.0);
    let standard = ViewDesc { view, proj: Mat4::perspective_rh(fov, aspect, near, far), depth: DepthRange::Standard }.geometry().unwrap();
    let infinite = ViewDesc { view, proj: Mat4::perspective_infinite_rh(fov, aspect, near), depth: DepthRange::Standard }.geometry().unwrap();
    let reversed = ViewDesc { view, proj: Mat4::perspective_rh(fov, aspect, far, near), depth: DepthRange::Reversed }.geometry().unwrap();
    let rev_inf = ViewDesc { view, proj: Mat4::perspective_infinite_reverse_rh(fov, aspect, near), depth: DepthRange::Reversed }.geometry().unwrap();
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
    // A reversed projection declared standard (or the other way) is
    // refused, and the error names the fix for the one declared.
    let err = |proj, depth| ViewDesc { view, proj, depth }.geometry().unwrap_err().to_string();
    let e = err(Mat4::perspective_infinite_reverse_rh(fov, aspect, near), DepthRange::Standard);
    assert!(e.contains("needs DepthRange::Reversed"), "{e}");
    let e = err(Mat4::perspective_rh(fov, aspect, near, far), DepthRange::Reversed);
    assert!(e.contains("needs DepthRange::Standard") && !e.contains("needs DepthRange::Reversed"), "{e}");
    // Left-handed and mirrored views are refused: the box tests would keep
    // the back faces.
    assert!(ViewDesc { view: Mat4::look_at_lh(eye, target, Vec3::Y), proj: Mat4::perspective_lh(fov, aspect, near, far), depth: DepthRange::Standard }.geometry().is_err());
    assert!(ViewDesc { view: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * view, proj: Mat4::perspective_rh(fov, aspect, near, far), depth: DepthRange::Standard }
        .geometry()
        .is_err());
    // Orthographic and non-finite matrices are refused, not mis-culled.
    assert!(ViewDesc { view, proj: Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0), depth: DepthRange::Standard }.geometry().is_err());
    assert!(ViewDesc { view: Mat4::NAN, proj: Mat4::perspective_rh(fov, aspect, near, far), depth: DepthRange::Standard }.geometry().is_err());
    // The look-at helper agrees with the old camera basis.
    let helper = ViewDesc::look_at(eye, target, Vec3::Y, fov.to_degrees(), aspect, near, far).geometry().unwrap();
    assert!(helper.ray_dirs.abs_diff_eq(standard.ray_dirs, 1e-5));
}
