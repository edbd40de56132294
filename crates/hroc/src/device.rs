//! What the device must have and what the culler runs with on it: the
//! features and limits to request, the [`Capabilities`] a culler
//! uses (its tier), and the marks shaders' WGSL and bind-group layout.

pub use crate::capabilities::{features, limits, Capabilities, DrawCount, Marks, FULL_FEATURES, REQUIRED_FEATURES};
pub use crate::host::{marks_layout, marks_wgsl, PIPELINE_STATISTICS_FEATURES, TIMESTAMP_FEATURES};
