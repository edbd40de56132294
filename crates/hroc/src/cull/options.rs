//! [`MethodOptions`]: the methods' parameters.

use std::str::FromStr;

use super::*;
use crate::error::{Error, Result};

/// Method parameters the command line can set (`hroc bench`/`render`).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOptions {
    /// `soq`: Kovalčík & Sochor 2005's BASE_TIME, in seconds.
    pub soq_base_time: f32,
    /// `chc++`: previously invisible nodes per query batch, b. The HROC
    /// paper ran b = 4000 on scenes of 7k–120k objects ("optimized for our
    /// scenes"); Lee's thesis 1000. Scenes here are scaled down, so 1000.
    pub chc_batch: usize,
    /// `chc++`: frames a visible leaf is assumed visible between queries, n_av.
    pub chc_nav: u32,
    /// `chc++`: tighter bounds from descendants down to d_max levels.
    pub chc_dmax: u32,
    /// `chc++`: tighter bounds only while their summed area is within s_max × the node's.
    pub chc_smax: f32,
    /// `ioc`: BVH depths [start, bottom] (root = 0); `None` picks
    /// [depth/2 - 1, depth/2 + 1] of the BVH (`ioc::cpu::default_range`).
    pub ioc_range: Option<(u32, u32)>,
    /// `hroc`: when a coarse grid of rays seeds the occluders V.
    pub hroc_seed: Seed,
    /// `hroc`: pixels per side of the blocks the batch occlusion test
    /// works on: one box fragment and one ray per block, against the
    /// block's farthest depth, with boxes padded for it (conservative at
    /// any scale). 2 casts a quarter of the rays at 640 × 360 for a little
    /// culling; the largest scale up to this one that divides the target's
    /// width and height is used, 1 being the paper's per-pixel test.
    pub hroc_test_scale: u32,
    /// `hroc` with OF: occluder filtering (§4.2) reads one pixel of the
    /// ID target in every `S × S` (1: every pixel, the paper's). Objects
    /// that cover no sampled pixel leave V: only speed and culling change,
    /// as V may be any set of objects. A sparser read costs 1/S² of the
    /// filter's threads and keeps small objects out of next frame's
    /// untested V, but measured fewer occluders cull less (BENCHMARKS.md),
    /// so the default reads every pixel.
    pub hroc_filter_stride: u32,
    /// `hroc`: rounds of occludee rendering, 1 to [`hroc::MAX_ROUNDS`]. 1
    /// is the paper's: every object the batch test marks (U) is drawn. With
    /// more, each round but the last draws the marked objects whose box is
    /// nearest at some block, and tests the rest again against the depth
    /// those draws left; objects hidden by what came into view this frame
    /// are then culled too. Rounds only change which of U are drawn, never
    /// what passes: every object they drop is behind drawn depth.
    pub hroc_rounds: u32,
    /// `hroc`: draw the occlusion map in one front-to-back round too: the
    /// objects of V whose box is nearest at some block first, then those
    /// whose box is still in front of the depth they left. V holds last
    /// frame's visible set, and on a moving camera many of them are hidden
    /// this frame behind others of V; left out, they are not occluders,
    /// and the batch test takes them with the other occludees. The hidden
    /// ones it culls leave the occluder set O, so G and next frame's V
    /// shrink too; every object that owns a pixel is still drawn.
    pub hroc_occluder_rounds: bool,
    /// `hroc`: in a view where occlusion culled less than this share of
    /// the objects in the frustum (a light's view of roofs), the frames
    /// between two measurements (one in eight, read back without a stall;
    /// in such a view half as often after each, down to one in 32) cull
    /// by the frustum alone: one compute pass and one list, where
    /// HROC's frame would cost its passes to cull a few objects. 0 always
    /// culls by occlusion. Conservative either way. `auto` keeps its HROC
    /// candidate whole (it chooses the frustum itself).
    pub hroc_frustum_below: f32,
    /// `hroc`: ... or, while it culled less than half of the frustum's
    /// objects, fewer triangles than this many per pixel of the view
    /// (each culled object counted as 64 at least, for its draw). HROC's
    /// frame costs work in proportion to the view's pixels (a ray per
    /// block in its test, a read of every pixel in its filter); what it
    /// saves is the culled objects' triangles and draws. In a view drawn
    /// depth only (a shadow map) a culled triangle saves no shading:
    /// [`DEPTH_ONLY_TRIANGLES`](crate::options::DEPTH_ONLY_TRIANGLES) is
    /// the bar for such views, which the bench's cascades and the Bevy
    /// plugin's light views take. A light's cascade of 512² that culls 50
    /// roofs of 80 triangles culls 0.015 per pixel. 0 (the default) leaves
    /// the share alone to decide: a camera in an interior measured as
    /// little (0.02-0.03 per pixel), and its shaded pixels pay for it.
    /// Above 0 the view also counts as drawn depth only: occlusion pays
    /// there only where the objects it culls hold more triangles than the
    /// boxes its test draws (12 for each object of the frustum it tests),
    /// and probes that find it not paying come ever further apart
    /// (`cull/hroc/gate.rs`).
    pub hroc_frustum_triangles: f32,
    /// Marks from boxes ([`crate::device::Marks::Boxes`]): pixels per side
    /// of the blocks they test, one pixel of each, where the device could
    /// test every pixel under early-Z against the attached depth (1, the
    /// default). Above 1 a mark pass costs 1/S² of the fragments (a
    /// light's 1024² shadow map: the Bevy plugin's light views take
    /// [`BOX_MARKS_SCALE_LIGHTS`](crate::options::BOX_MARKS_SCALE_LIGHTS)) and
    /// marks more or fewer objects than own a pixel; marks are conservative
    /// either way (`crate::cull::marks`). A device without that test uses
    /// 4 at least.
    pub box_marks_scale: u32,
    /// A frame whose view direction turned more than this many degrees
    /// since the last frame is culled as after a camera cut (the host need
    /// not say so): 45° is an eighth of a turn, past which most of last
    /// frame's visible set is off screen. `f32::INFINITY` turns it off.
    pub cut_turn_deg: f32,
    /// ... or whose eye (an orthographic view's central ray origin, which
    /// moves with its box) moved more than this fraction of the scene's
    /// diagonal (the BVH root's box): a tenth of a city is a new street.
    /// An orthographic view (a shadow cascade, refitted to the camera each
    /// frame) is cut only past half its smaller side too: until then it
    /// still holds most of what it saw.
    pub cut_move: f32,
}

/// When HROC seeds its occluders V with the objects a coarse grid of rays
/// meets first (`hroc_seed.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seed {
    /// On the first frame and after every camera cut, signalled or detected
    /// (the default): last frame's V is stale then. On every other frame
    /// the cells of the grid that V's depth left at the far plane cast
    /// their rays, and what they meet first is drawn with V: a V too weak
    /// to cull (the eye just left a building) does not collapse the frame.
    Cuts,
    /// On the first frame and after every camera cut only (no refill of
    /// holes: what the default was measured against).
    CutsOnly,
    /// Every frame, added to last frame's V.
    Always,
    /// Never: after a cut V is empty and the root is the one group (the
    /// paper's first frame), and no frame refills V.
    Never,
}

impl FromStr for Seed {
    type Err = Error;
    fn from_str(s: &str) -> Result<Seed> {
        match s {
            "cuts" => Ok(Seed::Cuts),
            "cuts-only" => Ok(Seed::CutsOnly),
            "always" => Ok(Seed::Always),
            "never" => Ok(Seed::Never),
            _ => Err(Error::Arg(format!("unknown seed '{s}': expected cuts, cuts-only, always or never"))),
        }
    }
}

impl MethodOptions {
    /// The most occludee rounds [`MethodOptions::hroc_rounds`] takes (more are clamped to it).
    pub const MAX_HROC_ROUNDS: u32 = super::hroc::MAX_ROUNDS;
}

impl Default for MethodOptions {
    fn default() -> Self {
        MethodOptions {
            soq_base_time: queries::soq::DEFAULT_BASE_TIME,
            chc_batch: 1000,
            chc_nav: 10,
            chc_dmax: 4,
            chc_smax: 1.4,
            ioc_range: None,
            hroc_seed: Seed::Cuts,
            hroc_test_scale: 2,
            hroc_filter_stride: 1,
            hroc_rounds: 1,
            hroc_occluder_rounds: false,
            hroc_frustum_below: 0.05,
            hroc_frustum_triangles: 0.0,
            box_marks_scale: 1,
            cut_turn_deg: 45.0,
            cut_move: 0.1,
        }
    }
}
