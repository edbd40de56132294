//! The culling methods, each behind one [`CullMethod`] trait, and the
//! recording context [`Frame`] they run in.
//!
//! A method never owns the draw: per frame it hands the host draw lists
//! (indirect commands + a GPU count, object order kept) through
//! [`Frame::draw`], tagged with their [`Phase`](crate::Phase), and records its own passes
//! between them. [`crate::View::cull`] builds the frame from what the host
//! hands in, so the benchmark and any engine drive a method the same way.

pub mod auto;
pub mod hroc;
pub mod hzb;
pub mod ioc;
pub mod noc;
pub mod queries;
pub mod reference;
pub mod roc;
pub mod vfc;
pub mod woc;

mod facts;
mod frame;
mod marks;
mod method;
mod options;
pub(crate) mod steps;

pub use crate::contract::DrawList;
pub use crate::metrics::{Stage, Stat};
pub use frame::*;
pub(crate) use marks::BoxMarks;
pub use marks::MarkTarget;
pub use method::*;
pub use options::*;

use std::any::Any;

use crate::error::Result;
use crate::gpu::Gpu;

/// A culling method: what a [`crate::View`] runs every frame.
pub trait CullMethod: Any + Send {
    /// Which method this is.
    fn method(&self) -> Method;

    /// Records (and may submit) the frame's culling passes and hands the
    /// host its draw lists.
    fn frame(&mut self, f: &mut Frame) -> Result<()>;

    /// Plans the next frame before it is recorded, for a set of views
    /// ([`crate::Culler::cull_views`]): the list that frame hands where it
    /// culls by the frustum alone (every object whose box meets the
    /// frustum, as `vfc.wgsl` tests, in object order), which the set's pass
    /// packs; `None` where it culls otherwise. Asked only before a frame
    /// that is not a cut; that frame then hands the list with
    /// `Frame::set_frustum`. The default: `None`.
    fn plan_set(&mut self, _gpu: &Gpu) -> Option<DrawList> {
        None
    }

    /// After [`CullMethod::plan_set`] returned a list: whether the frame
    /// still needs recording where the host culls it by its own frustum
    /// culling and reads nothing of it (`View::wants_steps`). The default:
    /// true.
    fn planned_frame_needed(&self) -> bool {
        true
    }

    /// Forgets what earlier frames taught (a camera cut): the next frame is
    /// culled as a first frame. Every method with temporal state overrides it.
    fn reset(&mut self, _enc: &mut wgpu::CommandEncoder) {}

    /// Records each of the method's compute pipelines once, bound as its
    /// frames bind it, with no work (zero workgroups): drivers that
    /// compile a pipeline on first use (llvmpipe and lavapipe, some GL
    /// drivers) compile it now, not in the frame the method first runs.
    /// `auto` warms its candidates in its first frame, so that a candidate
    /// it switches to later does not pay for it (on lavapipe `vfc`'s
    /// first frame cost 3-8 ms more than its next). The default records
    /// nothing.
    fn warm(&self, _enc: &mut wgpu::CommandEncoder) {}

    /// The objects the method's last frame found visible, as a temporal
    /// method keeps them for its next frame: one `u32` per object, nonzero
    /// where visible (`hzb`'s and HROC's V). `None` for methods that keep
    /// no such set.
    fn visible_set(&self) -> Option<&wgpu::Buffer> {
        None
    }

    /// Takes over a view from another method (`auto`'s switch): `visible`
    /// is the other method's [`CullMethod::visible_set`] from the frame
    /// just before, or `None` (nothing to start from). A temporal method
    /// starts from it as from its own last frame; what the set holds only
    /// orders the work (everything outside it is still tested against this
    /// frame's depth), so any set keeps the method conservative. The
    /// default, and any method without such state, resets.
    fn take_over(&mut self, enc: &mut wgpu::CommandEncoder, _visible: Option<&wgpu::Buffer>) {
        self.reset(enc);
    }

    /// `ref` only: the objects that own a pixel in `noc`'s ID target this
    /// frame, sorted.
    fn set_oracle(&mut self, _gpu: &Gpu, _visible: &[u32]) -> Result<()> {
        Ok(())
    }

    /// Per-frame method statistics of the frame just run (set sizes, nodes
    /// per ray...). Reads back; call after the frame.
    fn stats(&mut self, _gpu: &Gpu) -> Result<Vec<(Stat, f64)>> {
        Ok(Vec::new())
    }

    /// BVH nodes whose boxes the method rasterized in its last frame (for
    /// `hroc render --view groups`); `None` for methods that test no boxes.
    fn tested_nodes(&self, _gpu: &Gpu) -> Result<Option<Vec<u32>>> {
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each method's facts, stated in its own file, as the host contract
    /// lists them: which methods submit mid-frame, keep the tree, take
    /// motion and objects outside the tree, read marks and IDs.
    #[test]
    fn every_method_s_facts_are_the_contract_s() {
        let with = |fact: fn(Method) -> bool| Method::ALL.into_iter().filter(|&m| fact(m)).map(Method::name).collect::<Vec<_>>().join(",");
        assert_eq!(with(Method::submits_mid_frame), "oq,soq,chc++,ioc,hroc-cr,hroc-cr+of");
        assert_eq!(with(Method::keeps_tree), "oq,soq,chc++,ioc");
        assert_eq!(with(|m| !m.takes_motion()), "oq,soq,chc++");
        assert_eq!(with(|m| !m.takes_dynamic()), "oq,soq,chc++,ioc");
        assert_eq!(with(Method::reads_marks), "roc,ioc,hroc-na,hroc-cr,hroc-of,hroc-cr+of,hroc-sf,hroc");
        assert_eq!(with(Method::needs_ids), "hroc-of,hroc-cr+of,hroc");
        assert_eq!(with(|m| !m.is_conservative() || !m.supports_reversed_depth()), "woc");
        assert_eq!(with(Method::is_benchmark_only), "ref");
        assert_eq!(with(|m| m.layouts().is_empty()), "noc,ref,auto");
    }

    #[test]
    fn the_registry_round_trips_every_name() {
        let names = Method::names();
        for (name, m, what) in &names {
            assert_eq!(name.parse::<Method>().unwrap(), *m, "{name}");
            assert!(!what.is_empty());
        }
        let mut unique: Vec<_> = names.iter().map(|n| n.0).collect();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), names.len(), "a name is listed twice");
        // Every method of ALL is listed, under its own name.
        for m in Method::ALL {
            assert!(names.iter().any(|n| n.1 == m && n.0 == m.name()), "{m:?}");
        }
        assert_eq!("hroc-sf+of".parse::<Method>().unwrap(), Method::HROC);
        let e = "hroc-xyz".parse::<Method>().unwrap_err().to_string();
        assert!(e.contains("unknown method 'hroc-xyz'") && e.contains("chc++"), "{e}");
        // `all` is a list's word (the bench's `--methods all`), not a method's.
        assert!(!e.contains(" all") && "all".parse::<Method>().is_err(), "{e}");
    }

    #[test]
    fn stage_and_stat_names_are_unique() {
        let mut s: Vec<_> = Stage::ALL.iter().map(|s| s.name()).collect();
        s.sort_unstable();
        s.dedup();
        assert_eq!(s.len(), Stage::ALL.len());
        let mut t: Vec<_> = Stat::ALL.iter().map(|s| s.name()).collect();
        t.sort_unstable();
        t.dedup();
        assert_eq!(t.len(), Stat::ALL.len());
    }
}
