//! Errors of the culling library: every variant prints as one clear line.

/// What can go wrong when culling: the host's device, objects, targets or view.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The device lacks features the culler needs.
    #[error("{what} needs device features {missing:?}: request them when creating the device")]
    MissingFeatures {
        /// What needs them.
        what: String,
        /// The features the device lacks.
        missing: wgpu::Features,
    },
    /// A limit of the device is below what the culler needs.
    #[error("{what} needs the device's {limit} to be at least {needed}, and it is {have}: request hroc::device::limits(&adapter) when creating the device")]
    DeviceLimit {
        /// What needs it.
        what: String,
        /// The `wgpu::Limits` field.
        limit: &'static str,
        /// The value needed.
        needed: u64,
        /// The device's value.
        have: u64,
    },
    /// A method this culler cannot serve on its device, and why.
    #[error("{method} cannot run on this culler: {reason}")]
    MethodUnavailable {
        /// The method's name.
        method: String,
        /// What it lacks.
        reason: String,
    },
    /// An object the host registered is unusable.
    #[error("invalid object: {0}")]
    InvalidObject(String),
    /// A render target the host handed in is unusable.
    #[error("invalid render targets: {0}")]
    InvalidTargets(String),
    /// A pipeline the host recorded a [`crate::Draw`] with lacks what the
    /// draw needs (the marks group); the draw was not recorded.
    #[error("invalid host pipeline: {0}")]
    InvalidPipeline(String),
    /// A view or projection the host handed in is unusable.
    #[error("invalid view: {0}")]
    InvalidView(String),
    /// The objects (or their BVH) do not fit what a method can hold.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
    /// The objects exceed the device's limits.
    #[error("scene too large for this device: {0}")]
    OverDeviceLimits(String),
    /// A view whose method submits the host's encoder mid-frame
    /// ([`crate::Method::submits_mid_frame`]) was culled while the encoder
    /// holding its previous frame's end was neither submitted nor dropped:
    /// that submit would have run this frame's start before the last
    /// frame's end.
    #[error("submit order: {0}")]
    SubmitOrder(String),
    /// The device reported an error, or a read-back failed.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// Validation ([`crate::CullerDesc::validation`]) found that the
    /// host's draws broke the host contract in an earlier frame: the
    /// message names the view, the frame, the object, phase and pixel,
    /// the mistake and its fix.
    #[error("validation: {0}")]
    Validation(String),
    /// A bad parameter (a method name, an option).
    #[error("invalid argument: {0}")]
    Arg(String),
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
