//! `hroc report`: the papers' tables and figures for this machine (work in progress).

use std::path::PathBuf;

use crate::error::{Error, Result};

/// Command-line options of `hroc report`.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// Output folder (created).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(_args: ReportArgs) -> Result<()> {
    Err(Error::Arg("hroc report is not built yet".into()))
}
