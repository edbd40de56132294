//! [`Stage`] and [`Stat`]: the named stages and statistics of a frame.

use std::fmt;

macro_rules! named_enum {
    ($(#[$doc:meta])* $name:ident { $($(#[$vdoc:meta])* $v:ident => $s:literal,)* }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum $name { $($(#[$vdoc])* $v,)* }
        impl $name {
            /// Every value, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$v,)*];
            /// The name in tables, JSON and reports.
            pub fn name(self) -> &'static str {
                match self { $($name::$v => $s,)* }
            }
        }
        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_enum!(
    /// A GPU stage of a frame, timed by timestamps when the device has them:
    /// a step of the method's frame, its passes and the host's draws in it.
    /// (A [`Phase`](crate::Phase) names one list's role for the host; a
    /// stage is where the frame's time goes.)
    Stage {
        /// Draws of a method without stages of its own.
        Draw => "draw",
        /// `vfc`'s frustum test.
        FrustumCull => "frustum cull",
        /// `vfc`'s list compaction.
        Compact => "compact",
        /// HROC's ray grid: the seed of V after a camera cut, and on other
        /// frames the refill of V's holes.
        Seed => "occluder seed",
        /// Drawing last frame's visible set (HROC §3.1): the host's draws of
        /// [`Phase::Occluders`](crate::Phase::Occluders).
        OcclusionMap => "occlusion map",
        /// HROC's front-to-back round over V: nearest boxes, the re-test
        /// and their lists ([`MethodOptions::hroc_occluder_rounds`](crate::MethodOptions::hroc_occluder_rounds)).
        OccluderRounds => "occluder rounds",
        /// HROC's bottom-up group extraction (§3.2).
        GroupExtraction => "group extraction",
        /// Box rasterization, ray casting or Hi-Z tests (HROC §3.3).
        OcclusionTest => "occlusion test",
        /// Drawing the objects that passed (HROC §3.4): the host's draws of
        /// [`Phase::Occludees`](crate::Phase::Occludees).
        OccludeeRendering => "occludee rendering",
        /// HROC's front-to-back occludee rounds: nearest boxes, re-tests
        /// and their lists ([`MethodOptions::hroc_rounds`](crate::MethodOptions::hroc_rounds)).
        OccludeeRounds => "occludee rounds",
        /// HROC's occluder filtering (§4.2).
        Filtering => "filtering",
        /// Hi-Z pyramid build.
        HiZBuild => "hi-z build",
        /// Counter read-back (HROC §4.1), a mid-frame submit and wait.
        ReadBack => "read-back",
        /// Query methods' interleaved queries and draws.
        QueriesAndDraws => "queries and draws",
        /// `woc`: keeping this frame's depth.
        SaveDepth => "save depth",
        /// `woc`: warping last frame's depth.
        Warp => "warp",
        /// Objects flagged never-culled or not-occluder, drawn by the culler.
        FlaggedObjects => "flagged objects",
        /// The frame's change of objects, shared by every view: boxes
        /// uploaded, the BVH refit or rebuilt (HROC §6). Timed by the host
        /// around [`crate::Culler::set_bounds`] and the upload's completion.
        ObjectUpdate => "object update",
    }
);

impl Stage {
    /// True for the stages that draw the scene's geometry (the host's
    /// draws); the others are the cost of culling.
    pub fn draws_scene(self) -> bool {
        matches!(self, Stage::Draw | Stage::OcclusionMap | Stage::OccludeeRendering | Stage::FlaggedObjects)
    }
}

named_enum!(
    /// A per-frame statistic a method reports.
    Stat {
        /// |V|: last frame's visible set, drawn first.
        V => "V",
        /// |O|: effective occluders.
        O => "O",
        /// |G|: occludee groups tested.
        G => "G",
        /// |U|: occludees that passed the test.
        U => "U",
        /// Occludees drawn in the front lists of HROC's rounds before the last.
        Front => "front",
        /// |D|: occludees with a fragment through early-Z (with ID marks,
        /// that own a pixel after their draw; not kept with occluder
        /// filtering, which reads the ID target itself).
        D => "D",
        /// Rays cast by HROC's test.
        Rays => "rays",
        /// BVH nodes visited per ray.
        NodesPerRay => "nodes_per_ray",
        /// Boxes rasterized.
        Boxes => "boxes",
        /// Mid-frame read-backs.
        Readbacks => "readbacks",
        /// BVH levels tested (`ioc`).
        Levels => "levels",
        /// BVH nodes tested (`ioc`).
        NodesTested => "nodes_tested",
        /// Objects tested (`hzb`, `woc`).
        Tested => "tested",
        /// Objects crossing the near plane, visible untested.
        Near => "near",
        /// Warped-depth texels no splat reached (`woc`).
        FarTexels => "far_texels",
        /// Occlusion queries issued.
        Queries => "queries",
        /// Query result read-backs.
        QueryBatches => "query_batches",
        /// Boxes drawn inside queries.
        QueryBoxes => "query_boxes",
        /// Host ms waiting for query results.
        WaitMs => "wait_ms",
        /// Draw calls handed to the host.
        DrawCalls => "draw_calls",
        /// CHC++ multiqueries.
        Multiqueries => "multiqueries",
        /// CHC++ randomized re-queries.
        Requeried => "requeried",
        /// Nodes rendered without a query.
        RenderedUnqueried => "rendered_unqueried",
        /// 1 when the frame was culled as after a camera cut (signalled or detected).
        Cut => "cut",
        /// 1 when HROC seeded V with its ray grid this frame.
        Seeded => "seeded",
        /// 1 when HROC's step 5 ran occluder filtering this frame (with OF,
        /// where its filter gate found that it changes the next V).
        Filtered => "filtered",
        /// 1 when HROC culled the frame by occlusion; 0 by the frustum
        /// alone, where its gate found that occlusion culls little in the
        /// view ([`crate::MethodOptions::hroc_frustum_below`]).
        Occlusion => "occlusion",
        /// `auto`: the method that culled the frame, as its index in `Method::ALL`.
        Chosen => "chosen",
        /// `auto`: 1 when the frame probed a method other than the choice.
        Probe => "probe",
        /// Mid-frame submits.
        Submits => "submits",
        /// Mid-frame waits for the GPU.
        Waits => "waits",
        /// Bytes read back to the CPU during the frame.
        BytesRead => "bytes_read",
        /// Command slots of the lists handed to the host: the sum of their
        /// `max_count`. With an emulated draw count the GPU walks every
        /// slot (on GL and Metal, one driver call each); with the indirect
        /// count, only those up to the GPU's count.
        CommandSlots => "command_slots",
        /// Passes over the object-ID target that mark the objects a list
        /// drew ([`crate::capabilities::Marks::Ids`]; 0 with early-Z marks).
        IdPasses => "id_passes",
        /// The frame's shape ([`crate::gpu::FrameShape`]): compute passes the culler opened.
        ComputePasses => "compute_passes",
        /// Render passes the culler opened (box tests, depth reductions).
        RenderPasses => "render_passes",
        /// Dispatches, direct and indirect.
        Dispatches => "dispatches",
        /// Of those, indirect.
        IndirectDispatches => "indirect_dispatches",
        /// Draw calls in the culler's own render passes.
        OwnDraws => "own_draws",
        /// Draw lists handed to the host.
        Lists => "lists",
        /// Buffer clears.
        Clears => "clears",
        /// Buffer copies, per-frame uploads among them.
        Copies => "copies",
        /// Timestamp and query writes, and query-set resolves.
        QueryOps => "query_ops",
        /// Bind groups and buffers created while recording.
        Created => "created",
        /// Buffers mapped for reading.
        Maps => "maps",
        /// CPU ms spent recording the frame (`View::cull`, the host's draw
        /// callbacks included).
        RecordMs => "record_ms",
    }
);
