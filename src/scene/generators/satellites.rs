use super::Builder;
use crate::scene::CameraPath;
pub(super) fn build(b: &mut Builder) -> CameraPath {
    let m = b.mesh("x", super::shapes::block(1.0, 1.0, 1.0));
    while b.left() > 0 { let i = b.scene.objects.len() as f32; b.push(m, glam::Mat4::from_translation(glam::Vec3::X * i * 2.0), [1.0; 3]); }
    super::look_around(glam::Vec3::Y, 1.0, 11)
}
