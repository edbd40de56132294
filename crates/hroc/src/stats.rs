//! What a view measures: per-frame statistics every method shares
//! ([`FrameStats`], with its recorded [`FrameShape`]),
//! per-stage times and shader invocations, each method's own counts
//! ([`Stat`]), what an object update cost, and what validation found
//! ([`Finding`]).

pub use crate::cull::{Stage, Stat};
pub use crate::error::Finding;
pub use crate::gpu::{FrameShape, Invocations};
pub use crate::host::UpdateStats;
pub use crate::tally::FrameStats;
