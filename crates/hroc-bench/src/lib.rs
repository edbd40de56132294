//! hroc's own renderer as the first host of the culling API, and the
//! benchmark that runs every method side by side through that API.
//!
//! - [`render`]: a forward renderer (one vertex/index pool, object colours,
//!   colour/depth/object-ID targets) that draws what a [`hroc::View`] hands it;
//! - [`bench`](mod@bench): the session (scene + camera path on the GPU), the side-by-side
//!   benchmark checked against `noc`, tables, plots and the papers' reports;
//! - [`headless`]: a headless Vulkan device with the features hroc needs.

pub mod bench;
pub mod headless;
/// The headless device.
pub mod gpu {
    pub use crate::headless::{Backend, Headless, Tier};
}
pub mod render;

pub use hroc::bvh;
pub use hroc_scene as scene;

pub mod error;
pub use error::{Error, Result};
