//! Boxes and views: object boxes (world and oriented), the view
//! conventions (depth range, projections) and the geometry the culling
//! passes derive from a view.

pub use crate::aabb::{Aabb, OrientedBox};
pub use crate::cull::hroc::cpu::tested_box;
pub use crate::frustum::*;
