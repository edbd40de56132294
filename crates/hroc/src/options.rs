//! Options beyond the method's name: HROC's variants (its counters, its
//! occluder seed) and how moving objects update the BVH.

pub use crate::cull::{Counters, Seed, Variant};
pub use crate::host::{MotionOptions, Refit};

/// [`crate::MethodOptions::hroc_frustum_triangles`] for views drawn depth
/// only (shadow maps: a light's cascades, a point light's faces), where a
/// culled triangle saves no shading: occlusion must save 0.05 triangles
/// per pixel of the view (each culled object counted as 64 at least).
pub const DEPTH_ONLY_TRIANGLES: f32 = 0.05;

/// [`crate::MethodOptions::box_marks_scale`] for views drawn depth only at
/// shadow-map sizes (the Bevy plugin's light views): one pixel in 4 × 4,
/// a sixteenth of the fragments of marking a 1024² map per pixel.
pub const BOX_MARKS_SCALE_LIGHTS: u32 = 4;
