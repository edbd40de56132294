//! Deterministic motion for the generated scenes (the HROC paper's §6
//! names moving objects as its main limit): which objects move, and where
//! each is at a path time. Each scene moves in its own way:
//! - `radial-city`: traffic, sliding back and forth along the radial
//!   streets, up to 12 m;
//! - `factory`: forklifts crossing the aisles (x) and conveyor goods
//!   running along z, wrapping every 24 m;
//! - `satellites`: orbits around the vertical axis through the scene's
//!   centre, slower further out;
//! - every other scene: a slide in the ground plane, up to 8 m by 6 m.

use glam::{Mat4, Quat, Vec3};

/// The objects that move when a `fraction` (0 to 1) of `n` do: a
/// deterministic spread (every object whose index hashes below it).
pub fn moving_objects(n: usize, fraction: f32) -> Vec<u32> {
    (0..n as u32).filter(|&i| ((i.wrapping_mul(0x9E37_79B1) >> 8) as f32 / (1u32 << 24) as f32) < fraction).collect()
}

/// Object `i`'s transform at path time `t` seconds, from its transform as
/// generated (`base`), in scene `scene` whose box centre is `centre`.
pub fn moved(scene: &str, centre: Vec3, base: &Mat4, i: u32, t: f32) -> Mat4 {
    let phase = i as f32 * 0.37;
    let at = base.w_axis.truncate();
    let offset = match scene {
        "radial-city" => {
            let radial = Vec3::new(at.x - centre.x, 0.0, at.z - centre.z).try_normalize().unwrap_or(Vec3::X);
            return Mat4::from_translation(radial * 12.0 * (1.3 * t + phase).sin()) * *base;
        }
        "factory" if i.is_multiple_of(2) => Vec3::new(6.0 * (0.9 * t + phase).sin(), 0.0, 0.0),
        "factory" => Vec3::new(0.0, 0.0, (2.0 * t + phase * 10.0).rem_euclid(24.0) - 12.0),
        "satellites" => {
            let r = Vec3::new(at.x - centre.x, 0.0, at.z - centre.z).length().max(1.0);
            let angle = t * 20.0 / r;
            let spin = Mat4::from_translation(centre) * Mat4::from_quat(Quat::from_rotation_y(angle)) * Mat4::from_translation(-centre);
            return spin * *base;
        }
        _ => Vec3::new(8.0 * (1.2 * t + phase).sin(), 0.0, 6.0 * (0.8 * t + phase).cos()),
    };
    Mat4::from_translation(offset) * *base
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_pick_deterministic_spreads() {
        assert!(moving_objects(1000, 0.0).is_empty());
        assert_eq!(moving_objects(1000, 1.0).len(), 1000);
        let tenth = moving_objects(10_000, 0.1);
        assert!((900..1100).contains(&tenth.len()), "{}", tenth.len());
        assert_eq!(tenth, moving_objects(10_000, 0.1));
    }

    #[test]
    fn each_scene_moves_its_own_way() {
        let base = Mat4::from_translation(Vec3::new(40.0, 2.0, -30.0));
        let centre = Vec3::new(0.0, 5.0, 0.0);
        for scene in ["radial-city", "factory", "satellites", "rooms"] {
            for i in [0u32, 1, 7] {
                let a = moved(scene, centre, &base, i, 0.7).w_axis.truncate();
                assert!(a.distance(base.w_axis.truncate()) > 0.01, "{scene} object {i} moves");
                assert_eq!(a, moved(scene, centre, &base, i, 0.7).w_axis.truncate(), "deterministic");
            }
        }
        // Traffic stays on its radial street; orbits keep their radius.
        let r = moved("radial-city", centre, &base, 3, 1.1).w_axis.truncate();
        assert!(Vec3::new(r.x, 0.0, r.z).normalize().abs_diff_eq(Vec3::new(40.0, 0.0, -30.0).normalize(), 1e-5));
        let o = moved("satellites", centre, &base, 3, 5.0).w_axis.truncate();
        assert!((Vec3::new(o.x, 0.0, o.z).length() - 50.0).abs() < 1e-3 && (o.y - 2.0).abs() < 1e-5);
    }
}
