//! The culler's internals, for hroc's own tests, benchmark and tools: the
//! methods' state and CPU references, the WGSL sources and their Rust
//! mirrors, and the GPU helpers. Not part of the API (hidden from the
//! docs, and free to change).

/// The methods, their frame context, their CPU references and debug read-backs.
pub mod cull {
    pub use crate::cull::*;
}

/// Ordered compaction of flagged items.
pub mod compact {
    pub use crate::compact::*;
}

/// Read-back helpers, timestamps and pipeline statistics on a device.
pub mod gpu {
    pub use crate::gpu::*;
}

/// `#[repr(C)]` mirrors of the WGSL structs.
pub mod layout {
    pub use crate::layout::*;
}

/// Bind-group layouts reflected from the WGSL.
pub mod reflect {
    pub use crate::reflect::*;
}

/// The WGSL passes and the pipelines built from them.
pub mod shaders {
    pub use crate::shaders::*;
}

/// Visibility marks read from the object-ID target.
pub mod id_marks {
    pub use crate::id_marks::*;
}
