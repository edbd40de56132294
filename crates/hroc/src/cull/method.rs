//! [`Method`]: the registry of methods, their names and what each takes.

use std::fmt;
use std::str::FromStr;

use super::facts::Facts;
use super::*;
use crate::error::{Error, Result};
use crate::reflect::Layout;

/// How HROC bounds its indirect draws' `max_count` (HROC §4.1, §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Counters {
    /// The list's capacity, N (no acceleration, `na`).
    Capacity,
    /// Counter read-back (§4.1, `cr`): each count is read back mid-frame,
    /// a submit and a wait per list.
    ReadBack,
    /// Stall-free (`sf`, what §6 asks for): last frames' counts, read
    /// without waiting, plus a margin; a second indirect-count draw takes
    /// whatever overflows the estimate, its count (count − estimate, at
    /// least 0) computed on the GPU, so nothing is dropped. With an
    /// emulated draw count ([`crate::capabilities::DrawCount::Emulated`]) every list is
    /// drawn to its capacity anyway, and this runs as [`Counters::Capacity`];
    /// so are lists of at most 4,096 commands, where the overflow's pass
    /// costs more than the bound saves.
    StallFree,
}

/// HROC's accelerations (§4): how draw counts are bounded, and occluder filtering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    /// How `max_count` of each indirect draw is bounded.
    pub counters: Counters,
    /// Occluder filtering: next frame's occluders are the objects owning a
    /// pixel of the object-ID target.
    pub of: bool,
}

impl Variant {
    /// `hroc-na`: no accelerations.
    pub const NA: Variant = Variant { counters: Counters::Capacity, of: false };
    /// `hroc-cr`: counter read-back.
    pub const CR: Variant = Variant { counters: Counters::ReadBack, of: false };
    /// `hroc-of`: occluder filtering.
    pub const OF: Variant = Variant { counters: Counters::Capacity, of: true };
    /// `hroc-cr+of`: both of the paper's accelerations (§4).
    pub const CR_OF: Variant = Variant { counters: Counters::ReadBack, of: true };
    /// `hroc-sf`: stall-free counters.
    pub const SF: Variant = Variant { counters: Counters::StallFree, of: false };
    /// `hroc-sf+of` (= `hroc`): stall-free counters (§6) and occluder filtering.
    pub const SF_OF: Variant = Variant { counters: Counters::StallFree, of: true };
}

/// Every implemented method: one registry, in table order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// No culling: draw every object. Also the ground truth.
    Noc,
    /// GPU view-frustum culling.
    Vfc,
    /// Ideal: exactly the objects visible in `noc`'s ID target. Benchmark
    /// only: it needs that target before the frame.
    Ref,
    /// Hierarchical stop-and-wait occlusion queries.
    Oq,
    /// Statistically skipped occlusion queries.
    Soq,
    /// CHC++.
    Chc,
    /// Raster occlusion culling.
    Roc,
    /// Raster occlusion culling testing every object's box.
    RocAll,
    /// ROC over BVH levels.
    Ioc,
    /// Two-phase Hi-Z culling.
    Hzb,
    /// Warping-based occlusion culling (not conservative).
    Woc,
    /// Hierarchical Raster Occlusion Culling with the given accelerations;
    /// `hroc` is `sf+of`.
    Hroc(Variant),
    /// Adaptive: each frame the cheapest of `noc`, `vfc`, `hzb` and HROC,
    /// by their measured and modelled costs (`cull::auto`).
    Auto,
}

impl Method {
    /// HROC's default variant (SF + OF): occluder filtering, and counts
    /// bounded without the read-back's stall, which the paper's CR pays
    /// three times a frame (HROC §6).
    pub const HROC: Method = Method::Hroc(Variant::SF_OF);

    /// Every method once, in table order (`hroc` after its variants, then `auto`).
    pub const ALL: [Method; 18] = [
        Method::Noc,
        Method::Vfc,
        Method::Ref,
        Method::Oq,
        Method::Soq,
        Method::Chc,
        Method::Roc,
        Method::RocAll,
        Method::Ioc,
        Method::Hzb,
        Method::Woc,
        Method::Hroc(Variant::NA),
        Method::Hroc(Variant::CR),
        Method::Hroc(Variant::OF),
        Method::Hroc(Variant::CR_OF),
        Method::Hroc(Variant::SF),
        Method::HROC,
        Method::Auto,
    ];

    /// The method's facts, stated in its own file.
    pub(crate) const fn facts(self) -> Facts {
        match self {
            Method::Noc => noc::FACTS,
            Method::Vfc => vfc::FACTS,
            Method::Ref => reference::FACTS,
            Method::Oq => queries::oq::FACTS,
            Method::Soq => queries::soq::FACTS,
            Method::Chc => queries::chc::FACTS,
            Method::Roc => roc::FACTS,
            Method::RocAll => roc::FACTS_ALL,
            Method::Ioc => ioc::FACTS,
            Method::Hzb => hzb::FACTS,
            Method::Woc => woc::FACTS,
            Method::Hroc(v) => hroc::facts(v),
            Method::Auto => auto::FACTS,
        }
    }

    /// The name on the command line and in tables. `hroc` and `hroc-sf+of`
    /// are the same method; this returns `hroc` for it, and
    /// [`Method::names`] lists both names.
    pub fn name(self) -> &'static str {
        self.facts().name
    }

    /// Every (name, method, one-line description), in table order.
    /// `hroc-sf+of` also parses, as `hroc`.
    pub fn names() -> Vec<(&'static str, Method, &'static str)> {
        Method::ALL.iter().map(|&m| (m.name(), m, m.description())).collect()
    }

    /// One line on what the method does.
    pub fn description(self) -> &'static str {
        self.facts().description
    }

    /// False for the methods that may miss visible objects (`woc`).
    pub fn is_conservative(self) -> bool {
        self.facts().conservative
    }

    /// True when the method reads the host's object-ID target (HROC with OF).
    pub fn needs_ids(self) -> bool {
        self.facts().needs_ids
    }

    /// True when the method reads counts back in the middle of a frame
    /// (`hroc-cr`, `hroc-cr+of`, `ioc`, `oq`, `soq`, `chc++`): its
    /// [`crate::View::cull`] submits the host's encoder, waits, and goes on
    /// in a new one. A frame of such a view is culled into the encoder its
    /// previous frame ended in, or after that encoder was submitted (or
    /// dropped); otherwise the cull fails with [`crate::Error::SubmitOrder`].
    pub fn submits_mid_frame(self) -> bool {
        self.facts().submits_mid_frame
    }

    /// True when the method reads which objects the host's draws left
    /// visible (`roc`, `ioc`, HROC): with [`crate::capabilities::Marks::Ids`] its views
    /// need the object-ID target.
    pub fn reads_marks(self) -> bool {
        self.facts().reads_marks
    }

    /// The bind-group layouts of the method's own passes.
    pub(crate) fn layouts(self) -> &'static [Layout] {
        self.facts().layouts
    }

    /// True for `ref`, which only the benchmark can feed (`View::set_oracle`).
    pub fn is_benchmark_only(self) -> bool {
        self.facts().benchmark_only
    }

    /// True when the method follows objects that move ([`crate::Culler::set_bounds`]):
    /// every method that reads the culler's boxes and BVH on the GPU. The
    /// query methods keep a CPU copy of the BVH (and CHC++ its tighter
    /// bounds) from their creation, so they take static scenes only.
    pub fn takes_motion(self) -> bool {
        self.facts().takes_motion
    }

    /// True when the method culls objects outside the BVH too:
    /// [`crate::ObjectFlags::DYNAMIC`] ones and those added since the last
    /// build. HROC tests them on their own (its §6 hybrid); the per-object
    /// methods never read the tree. IOC culls through the tree alone.
    pub fn takes_dynamic(self) -> bool {
        self.facts().takes_dynamic
    }

    /// True when the method's per-view state holds the BVH's shape (IOC's
    /// level queues, the query methods' copies): its views start over when
    /// the culler rebuilds the tree.
    pub fn keeps_tree(self) -> bool {
        self.facts().keeps_tree
    }

    /// True when the method takes reversed depth (`woc`'s warp does not).
    pub fn supports_reversed_depth(self) -> bool {
        self.facts().reversed_depth
    }

    pub(crate) fn create(self, cx: &MethodContext) -> Result<Box<dyn CullMethod>> {
        Ok(match self {
            Method::Noc => Box::new(noc::NoCulling),
            Method::Vfc => Box::new(vfc::FrustumCuller::new(cx)),
            Method::Ref => Box::new(reference::Reference::new(cx)?),
            Method::Oq => Box::new(queries::oq::Oq::new(cx)?),
            Method::Soq => Box::new(queries::soq::Soq::new(cx)?),
            Method::Chc => Box::new(queries::chc::Chc::new(cx)?),
            Method::Roc => Box::new(roc::Roc::new(cx, false)),
            Method::RocAll => Box::new(roc::Roc::new(cx, true)),
            Method::Ioc => Box::new(ioc::Ioc::new(cx, cx.options.ioc_range)?),
            Method::Hzb => Box::new(hzb::Hzb::new(cx)),
            Method::Woc => Box::new(woc::Woc::new(cx)),
            Method::Hroc(v) => Box::new(hroc::Hroc::new(v, cx)?),
            Method::Auto => Box::new(auto::Auto::new(cx, cx.auto)?),
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = Error;
    /// A name of [`Method::names`], or `hroc-sf+of` (the default HROC
    /// variant's full name) for `hroc`.
    fn from_str(s: &str) -> Result<Method> {
        if s == "hroc-sf+of" {
            return Ok(Method::HROC);
        }
        Method::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| {
            let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
            Error::Arg(format!("unknown method '{s}': expected one of {} (or hroc-sf+of, hroc's full name)", names.join(", ")))
        })
    }
}
