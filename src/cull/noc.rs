//! `noc`: draw everything, in object order. Also the ground truth.

use super::{Culler, Frame};
use crate::error::Result;

pub struct NoCulling;

impl Culler for NoCulling {
    fn name(&self) -> &str {
        "noc"
    }
    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage("draw");
        let all = f.renderer.all();
        f.draw(&all, None);
        Ok(())
    }
}
