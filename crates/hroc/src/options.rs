//! Options beyond the method's name: HROC's variants (its counters, its
//! occluder seed) and how moving objects update the BVH.

pub use crate::cull::{Counters, Seed, Variant};
pub use crate::host::{MotionOptions, Refit};
