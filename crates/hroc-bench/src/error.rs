//! What the bench, its renderer and its tools can fail with: the device,
//! the options asked for, the files they write, and the scene's and the
//! culler's own errors, which pass through as they are. Every variant
//! prints as one clear line; the CLI exits non-zero with it.

use std::path::PathBuf;

/// A bench error.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// No adapter could open a device with what the bench needs.
    #[error("{0}")]
    NoAdapter(String),
    /// The device failed (an error it reported, a lost device, a read-back).
    #[error("GPU error: {0}")]
    Device(String),
    /// An option out of its range, or options that do not go together.
    #[error("invalid argument: {0}")]
    Options(String),
    /// The scene needs more of the device than it has.
    #[error("scene too large for this device: {0}")]
    TooLarge(String),
    /// A report, table or picture could not be written.
    #[error("cannot write {path}: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    /// The scene's (files, contents).
    #[error(transparent)]
    Scene(#[from] hroc_scene::Error),
    /// The culler's (the host contract, the device's features).
    #[error(transparent)]
    Cull(#[from] hroc::Error),
}

/// A bench result.
pub type Result<T, E = Error> = std::result::Result<T, E>;
