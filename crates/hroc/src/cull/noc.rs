//! `noc`: draw everything, in object order. Also the ground truth.

use super::{CullMethod, Frame, Method, Stage};
use crate::contract::Phase;
use crate::cull::facts::Facts;
use crate::error::Result;

/// `noc`'s facts.
pub(crate) const FACTS: Facts = Facts { name: "noc", description: "no culling: draw every object", ..Facts::GPU };

/// The `noc` method: every object, no culling, in object order.
pub struct NoCulling;

impl CullMethod for NoCulling {
    fn method(&self) -> Method {
        Method::Noc
    }

    fn frame(&mut self, f: &mut Frame) -> Result<()> {
        f.stage(Stage::Draw);
        let all = f.all();
        f.draw(Phase::Visible, &all, None);
        Ok(())
    }
}
