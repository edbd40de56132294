//! What a method is and what it needs and takes ([`Facts`]), stated once
//! in the method's own file and read through [`super::Method`]'s queries.
//! A new method states its facts there and takes one line in
//! [`super::Method::ALL`] and one in each of `Method::facts` and
//! `Method::create`.

use crate::reflect::Layout;

/// One method's facts.
#[derive(Clone, Copy, Debug)]
pub struct Facts {
    /// Its name on the command line and in tables.
    pub name: &'static str,
    /// One line on what it does.
    pub description: &'static str,
    /// It never culls a visible object (`woc` may).
    pub conservative: bool,
    /// It reads the host's object-ID target every frame (HROC with OF).
    pub needs_ids: bool,
    /// It reads counts back mid-frame: submits the host's encoder and waits.
    pub submits_mid_frame: bool,
    /// It reads which objects the host's draws left visible (marks).
    pub reads_marks: bool,
    /// It follows objects that move (it reads the culler's boxes and BVH on the GPU).
    pub takes_motion: bool,
    /// It culls objects outside the BVH too (`DYNAMIC` ones, those added since the build).
    pub takes_dynamic: bool,
    /// Its per-view state holds the BVH's shape: its views start over after a rebuild.
    pub keeps_tree: bool,
    /// It takes reversed depth.
    pub reversed_depth: bool,
    /// Only the benchmark can feed it (`ref`, with `View::set_oracle`).
    pub benchmark_only: bool,
    /// The bind-group layouts of its own passes (the device limits they need).
    pub layouts: &'static [Layout],
}

impl Facts {
    /// A conservative GPU method that takes motion, objects outside the
    /// tree and reversed depth, reads neither IDs nor marks, never
    /// submits mid-frame and keeps no copy of the tree: what each
    /// method's own facts start from.
    pub const GPU: Facts = Facts {
        name: "",
        description: "",
        conservative: true,
        needs_ids: false,
        submits_mid_frame: false,
        reads_marks: false,
        takes_motion: true,
        takes_dynamic: true,
        keeps_tree: false,
        reversed_depth: true,
        benchmark_only: false,
        layouts: &[],
    };

    /// A query method (`oq`, `soq`, `chc++`): front-to-back occlusion
    /// queries read back mid-frame over a CPU copy of the BVH, so it takes
    /// static scenes only.
    pub const QUERIES: Facts = Facts { submits_mid_frame: true, takes_motion: false, takes_dynamic: false, keeps_tree: true, layouts: &[Layout::QueryBoxes], ..Facts::GPU };
}
