//! `hroc view`: an interactive window over a scene (work in progress).

use std::path::PathBuf;

use crate::error::{Error, Result};

/// Command-line options of `hroc view`.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// Built-in scene key or a .gltf/.glb/.obj path.
    #[arg(default_value = "radial-city")]
    pub scene: String,
    /// Object count of a generated scene (its default when omitted).
    #[arg(long)]
    pub objects: Option<usize>,
    /// Method to start with (switch live in the panel).
    #[arg(long, default_value = "hroc")]
    pub method: String,
    /// Renders this many frames, then exits (smoke tests).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Saves the last frame to this PNG on exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
}

pub fn run(_args: ViewArgs) -> Result<()> {
    Err(Error::Arg("hroc view is not built yet".into()))
}
