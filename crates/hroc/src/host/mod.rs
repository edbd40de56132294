//! The host contract: what a renderer hands the culler, what it gets back.
//! The crate docs state the preconditions once; these modules implement
//! them.

mod contract;
mod culler;
mod flag_split;
mod motion;
mod objects;
mod view;

pub use contract::*;
pub use culler::*;
pub(crate) use flag_split::*;
pub use motion::*;
pub use objects::*;
pub use view::*;
