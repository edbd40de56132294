//! hroc: GPU occlusion culling of massive scenes on wgpu.
//!
//! The pieces, in the order a frame uses them:
//! - [`scene`]: meshes + object instances, loaders (glTF, OBJ), generators, camera paths;
//! - [`bvh`]: the object-level BVH every hierarchical method walks;
//! - [`gpu`]: headless wgpu context, read-back, timestamps;
//! - [`render`]: the shared renderer (one vertex/index pool, multi-draw-indirect-count);
//! - [`cull`]: one [`cull::Culler`] per method, all drawing through the renderer;
//! - [`bench`]: runs methods side by side over one camera path and measures them;
//!   `bench::report` turns runs into the papers' tables and figures;
//! - [`viewer`]: an interactive window to fly through a scene and switch methods.

pub mod bvh;
pub mod error;
pub mod scene;

pub use error::{Error, Result};
pub mod cull;
pub mod gpu;
pub mod render;

pub mod bench;
pub mod viewer;
