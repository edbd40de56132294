//! What the device must have and what the culler runs with on it: the
//! features and limits to request, the [`Capabilities`] a culler
//! uses (its tier), the marks shaders' WGSL and bind-group layout, and the
//! WGSL that reads a view's visibility as data.

pub use crate::capabilities::{features, limits, Capabilities, DrawCount, Marks, FULL_FEATURES, REQUIRED_FEATURES};
pub use crate::host::{marks_layout, marks_wgsl, PIPELINE_STATISTICS_FEATURES, TIMESTAMP_FEATURES};
pub use crate::visibility::{visibility_wgsl, HEADER as VISIBILITY_HEADER};
