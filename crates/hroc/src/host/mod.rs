//! The host contract: what a renderer hands the culler, what it gets back.
//! The crate docs state the preconditions once; these modules implement
//! them.

mod culler;
mod motion;
mod serving;
mod set;
mod steps;
mod view;

pub use crate::contract::*;
pub(crate) use crate::flag_split::*;
pub use crate::objects::*;
pub use culler::*;
pub use motion::*;
pub use steps::Steps;
pub use view::*;
