//! [`Method`]: the registry of methods, their names and what each takes.

use std::fmt;
use std::str::FromStr;

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

    /// The name on the command line and in tables. `hroc` and `hroc-sf+of`
    /// are the same method; this returns `hroc` for it, and
    /// [`Method::names`] lists both names.
    pub fn name(self) -> &'static str {
        match self {
            Method::Noc => "noc",
            Method::Vfc => "vfc",
            Method::Ref => "ref",
            Method::Oq => "oq",
            Method::Soq => "soq",
            Method::Chc => "chc++",
            Method::Roc => "roc",
            Method::RocAll => "roc-all",
            Method::Ioc => "ioc",
            Method::Hzb => "hzb",
            Method::Woc => "woc",
            Method::Hroc(Variant { counters: Counters::Capacity, of: false }) => "hroc-na",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: false }) => "hroc-cr",
            Method::Hroc(Variant { counters: Counters::Capacity, of: true }) => "hroc-of",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: true }) => "hroc-cr+of",
            Method::Hroc(Variant { counters: Counters::StallFree, of: false }) => "hroc-sf",
            Method::Hroc(Variant { counters: Counters::StallFree, of: true }) => "hroc",
            Method::Auto => "auto",
        }
    }

    /// Every (name, method, one-line description), in table order.
    /// `hroc-sf+of` also parses, as `hroc`.
    pub fn names() -> Vec<(&'static str, Method, &'static str)> {
        Method::ALL.iter().map(|&m| (m.name(), m, m.description())).collect()
    }

    /// One line on what the method does.
    pub fn description(self) -> &'static str {
        match self {
            Method::Noc => "no culling: draw every object",
            Method::Vfc => "GPU view-frustum culling",
            Method::Ref => "ideal: draw exactly the objects visible in noc's ID target",
            Method::Oq => "hierarchical stop-and-wait occlusion queries, front to back (004's simple OC)",
            Method::Soq => "occlusion queries skipped for recently visible nodes (004's statistical OC)",
            Method::Chc => "CHC++: batched multiqueries, randomized re-queries, tighter bounds",
            Method::Roc => "raster occlusion culling: draw V, rasterize the boxes of the rest with early-Z, draw what passed",
            Method::RocAll => "raster occlusion culling testing every object's box (the HROC paper's ROC)",
            Method::Ioc => "ROC over BVH levels [start, bottom] with a queue read-back per level (HPG 2020 poster)",
            Method::Hzb => "two-phase Hi-Z culling (Nanite, niagara, Bevy)",
            Method::Woc => "warping-based: last frame's depth reprojected, Hi-Z test before drawing (not conservative)",
            Method::Hroc(Variant { counters: Counters::Capacity, of: false }) => "HROC without accelerations",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: false }) => "HROC with counter read-back",
            Method::Hroc(Variant { counters: Counters::Capacity, of: true }) => "HROC with occluder filtering",
            Method::Hroc(Variant { counters: Counters::ReadBack, of: true }) => "HROC with counter read-back and occluder filtering",
            Method::Hroc(Variant { counters: Counters::StallFree, of: false }) => "HROC with stall-free counters (earlier frames' counts, GPU overflow draw)",
            Method::Hroc(Variant { counters: Counters::StallFree, of: true }) => "HROC, the default variant: stall-free counters and occluder filtering (also hroc-sf+of)",
            Method::Auto => "adaptive: each frame the cheapest of noc, vfc, hzb and hroc, by measured and modelled cost",
        }
    }

    /// False for the methods that may miss visible objects (`woc`).
    pub fn is_conservative(self) -> bool {
        self != Method::Woc
    }

    /// True when the method reads the host's object-ID target (HROC with OF).
    pub fn needs_ids(self) -> bool {
        matches!(self, Method::Hroc(Variant { of: true, .. }))
    }

    /// True when the method reads counts back in the middle of a frame
    /// (`hroc-cr`, `hroc-cr+of`, `ioc`, `oq`, `soq`, `chc++`): its
    /// [`crate::View::cull`] submits the host's encoder, waits, and goes on
    /// in a new one. A frame of such a view is culled into the encoder its
    /// previous frame ended in, or after that encoder was submitted (or
    /// dropped); otherwise the cull fails with [`crate::Error::SubmitOrder`].
    pub fn submits_mid_frame(self) -> bool {
        matches!(self, Method::Hroc(Variant { counters: Counters::ReadBack, .. }) | Method::Ioc | Method::Oq | Method::Soq | Method::Chc)
    }

    /// True when the method reads which objects the host's draws left
    /// visible (`roc`, `ioc`, HROC): with [`crate::capabilities::Marks::Ids`] its views
    /// need the object-ID target.
    pub fn reads_marks(self) -> bool {
        matches!(self, Method::Roc | Method::Ioc | Method::Hroc(_))
    }

    /// The bind-group layouts of the method's own passes.
    pub(crate) fn layouts(self) -> &'static [Layout] {
        match self {
            Method::Noc | Method::Ref => &[],
            Method::Vfc => &[Layout::Vfc, Layout::Compact],
            Method::Oq | Method::Soq | Method::Chc => &[Layout::QueryBoxes],
            Method::Roc | Method::RocAll => &[Layout::RocBoxes, Layout::Roc, Layout::Compact],
            Method::Ioc => &[Layout::Ioc, Layout::RocBoxes, Layout::Compact],
            Method::Hzb => &[Layout::HiZBuild, Layout::HiZTest, Layout::Compact],
            // Its candidates are checked one by one (`Culler::auto_candidates`).
            Method::Auto => &[],
            Method::Woc => &[Layout::WocWarp, Layout::HiZBuild, Layout::HiZTest, Layout::Compact],
            Method::Hroc(_) => &[
                Layout::HrocSeed,
                Layout::HrocWalk,
                Layout::HrocGroups,
                Layout::HrocNext,
                Layout::HrocTest,
                Layout::HrocRounds,
                Layout::HrocRoundsInit,
                Layout::HrocReduce,
                Layout::Overflow,
                Layout::Compact,
            ],
        }
    }

    /// True for `ref`, which only the benchmark can feed (`View::set_oracle`).
    pub fn is_benchmark_only(self) -> bool {
        self == Method::Ref
    }

    /// True when the method follows objects that move ([`crate::Culler::set_bounds`]):
    /// every method that reads the culler's boxes and BVH on the GPU. The
    /// query methods keep a CPU copy of the BVH (and CHC++ its tighter
    /// bounds) from their creation, so they take static scenes only.
    pub fn takes_motion(self) -> bool {
        !matches!(self, Method::Oq | Method::Soq | Method::Chc)
    }

    /// True when the method culls objects outside the BVH too:
    /// [`crate::ObjectFlags::DYNAMIC`] ones and those added since the last
    /// build. HROC tests them on their own (its §6 hybrid); the per-object
    /// methods never read the tree. IOC culls through the tree alone.
    pub fn takes_dynamic(self) -> bool {
        self.takes_motion() && self != Method::Ioc
    }

    /// True when the method's per-view state holds the BVH's shape (IOC's
    /// level queues, the query methods' copies): its views start over when
    /// the culler rebuilds the tree.
    pub fn keeps_tree(self) -> bool {
        matches!(self, Method::Ioc | Method::Oq | Method::Soq | Method::Chc)
    }

    /// True when the method takes reversed depth (`woc`'s warp does not).
    pub fn supports_reversed_depth(self) -> bool {
        self != Method::Woc
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
            Error::Arg(format!("unknown method '{s}': expected one of {}, hroc-sf+of or all", names.join(", ")))
        })
    }
}
