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
    /// view, the frame, the object, phase and pixel, the mistake and its
    /// fix ([`crate::stats::Finding`]). The frame whose cull returns it
    /// was recorded in full, as without validation.
    #[error("validation: {0}")]
    Validation(Finding),
    /// A bad parameter (a method name, an option).
    #[error("invalid argument: {0}")]
    Arg(String),
}

/// What validation found in one frame of a view
/// ([`Error::Validation`]): the first mistake,
/// which is the cause, and what else the frame's checks found, which may
/// follow from it (a target never cleared also leaves IDs of objects not
/// drawn; a shader that never marks also fails the check of forced
/// early-Z). It prints as one line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Finding {
    /// The view, as the culler names it (method, size, layer and mip).
    pub view: String,
    /// The frame: the view's count of frames culled before it.
    pub frame: u64,
    /// The object of the first mistake where one is known: the object the
    /// ID target names, or, in a view without IDs, the drawn object whose
    /// box lies nearest the sample drawn in front of every box (the
    /// likeliest to have drawn it).
    pub object: Option<u32>,
    /// The pixel of the first mistake, where it has one.
    pub pixel: Option<(u32, u32)>,
    /// The first mistake, where it was found, and its fix.
    pub cause: String,
    /// The first mistake and its fix, as the same text for every finding
    /// of its kind (for a host that reports each kind once).
    pub mistake: &'static str,
    /// What else the frame's checks found, each with its fix: findings
    /// that may follow from the cause.
    pub follow_on: Vec<String>,
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}, frame {}: {}", self.view, self.frame, self.cause)?;
        if !self.follow_on.is_empty() {
            write!(f, " (and what may follow from it: {})", self.follow_on.join("; "))?;
        }
        Ok(())
    }
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
