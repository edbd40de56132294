//! # hroc: GPU occlusion culling for any wgpu renderer
//!
//! Hierarchical Raster Occlusion Culling (HROC; Lee et al. 2021, cited in
//! full with the other papers under References in README.md) and
//! the methods it is measured against, behind one API. The host keeps its
//! device, pipelines, materials, vertex layout and render targets; hroc
//! decides which of its objects to draw, and hands the host GPU draw lists.
//!
//! ## The frame
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, depth: &wgpu::Texture, ids: &wgpu::Texture,
//! #          objects: &[hroc::ObjectDesc], view: glam::Mat4, proj: glam::Mat4,
//! #          draw_with_my_pipeline: &mut dyn FnMut(&mut wgpu::CommandEncoder, &hroc::Draw)) -> hroc::Result<()> {
//! use hroc::{Culler, CullerDesc, DepthRange, FrameInput, Method, ViewDesc, ViewTargets};
//! // The device was requested with hroc::device::features(&adapter) and hroc::device::limits(&adapter).
//! // Once: the objects (world box + the host's own indexed draw each), then a view.
//! let culler = Culler::new(device, queue, &CullerDesc::new(objects))?;
//! let targets = ViewTargets::new(depth, DepthRange::Standard).with_ids(ids);
//! let mut main_view = culler.view(Method::HROC, &targets)?;
//! // Every frame: clear the targets, cull, draw what comes back, submit.
//! let mut encoder = device.create_command_encoder(&Default::default());
//! let input = FrameInput { view: ViewDesc { view, proj, unclipped_depth: false }, cut: false, time: 0.0 };
//! main_view.cull(&culler, &mut encoder, &input, &mut |enc: &mut wgpu::CommandEncoder, draw: &hroc::Draw| {
//!     draw_with_my_pipeline(enc, draw) // multi_draw_indexed_indirect_count(draw.commands, draw.count)
//! })?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```
//!
//! ## The host contract
//! What every method needs from the host's pipelines. Break one and a method
//! may cull a visible object.
//! - **Device.** Request [`device::features`] and [`device::limits`] of the adapter. Every
//!   culler needs [`device::REQUIRED_FEATURES`] (`first_instance` in indirect
//!   draws: Vulkan, DX12, Metal, desktop GL 4.2+; not GLES or WebGL). It
//!   runs with the [`device::Capabilities`] the device allows (or those asked for
//!   in [`CullerDesc::capabilities`]): the indirect draw count where it
//!   exists, else an emulated one ([`device::DrawCount`]); visibility marks from
//!   the host's fragment shaders under forced early-Z where it exists,
//!   else from the object-ID target ([`device::Marks`]); box tests against a
//!   read-only depth attachment, or against depth they load
//!   ([`device::Capabilities::read_only_depth`]). Which backend gives which of
//!   these, what each lacks and what its host provides is tabled once, in
//!   README.md's "Backends and tiers" section.
//!   [`device::Capabilities::PORTABLE`] (an emulated count, ID marks) runs on any
//!   of them. `ioc` needs 10 storage buffers per shader stage (wgpu's
//!   default limit is 8). [`Culler::serves`] refuses what a culler cannot
//!   run by name, with the reason, and [`Culler::methods`] lists what it
//!   serves. [`Culler::new`] and [`Culler::view`] name any missing
//!   feature, and any device limit below what is needed with the value
//!   needed. [`device::TIMESTAMP_FEATURES`] add per-stage GPU times and
//!   [`device::PIPELINE_STATISTICS_FEATURES`] per-stage shader invocations
//!   (counted in the host's draws when it records them with
//!   [`Draw::record`]).
//! - **Objects.** Object `i` is one indexed draw of the host's index buffer
//!   ([`ObjectDesc`]) with a world box that holds every vertex it can
//!   rasterize this frame. The culler hands back
//!   `DrawIndexedIndirectArgs` with `first_instance = i` and
//!   `instance_count` 1 or 0: the host's vertex shader reads its per-object
//!   data (transform, material) at `@builtin(instance_index)`.
//!   Optionally, an object also has a box in its own frame
//!   ([`ObjectDesc::oriented`], an [`geometry::OrientedBox`]) that holds the same
//!   geometry: HROC then tests where both boxes meet, which for rotated
//!   panels, rings and beams is far less than the world box alone.
//! - **Draws.** For each [`Draw`], in the order handed over, the host records
//!   `multi_draw_indexed_indirect_count(commands, 0, count, 0, max_count)`
//!   (with [`device::DrawCount::Emulated`], `multi_draw_indexed_indirect(commands,
//!   0, max_count)`) into a render pass on the view's depth attachment, before returning
//!   ([`Draw::record`]). Object order within a list is kept; the host must
//!   not reorder, split or skip a list, because the culler's next pass reads
//!   the depth it left. A phase may come several times in one frame (HROC's
//!   occludee rounds, [`MethodOptions::hroc_rounds`], and occluder rounds,
//!   [`MethodOptions::hroc_occluder_rounds`]; the stall-free overflow
//!   lists): draw every list when it comes.
//! - **Depth.** Every occluding phase ([`Phase::occludes`]) writes depth with
//!   the depth test of its [`DepthRange`] (`Less`/`LessEqual` standard,
//!   `Greater`/`GreaterEqual` reversed), depth bias only away from the
//!   viewer (constant and slope-scaled bias ≥ 0 standard, ≤ 0 reversed, as
//!   shadow passes use: a farther depth only lets more boxes pass), depth
//!   clamped rather than clipped at the near plane only when the view says
//!   so ([`ViewDesc::unclipped_depth`]), and only for
//!   geometry inside the object's box. The depth texture has usage
//!   `RENDER_ATTACHMENT | TEXTURE_BINDING`, one sample or several (MSAA);
//!   the culler binds it read-only between the host's draws (box tests,
//!   rasterized at its sample count, exact per sample) and loads it in
//!   compute and fragment passes (Hi-Z, HROC's occlusion map, box tests
//!   that compare depth themselves), which keep a pixel's farthest
//!   sample. An object whose fragments may leave samples they cover
//!   unwritten (`discard`, alpha-to-coverage, a sample-mask output)
//!   occludes where it writes depth, and cannot force early-Z: flag it
//!   [`ObjectFlags::CUTOUT`], and draw the lists of such objects
//!   ([`Draw::cutout`]) with its own pipeline, without forced early-Z and
//!   without marking.
//! - **Clearing.** Clear the depth target to its far value (1 standard,
//!   0 reversed) and the ID target to 0 once per
//!   frame, before [`View::cull`]: in a pass of its own, or with
//!   `LoadOp::Clear` in any pass recorded into the encoder before the
//!   call. Every [`Draw`]'s pass loads (`LoadOp::Load`): a phase may come
//!   several times in a frame, each list draws over the depth the one
//!   before left, and the query methods test boxes against the depth
//!   before their first list, so a clear inside the frame makes the
//!   culler's next test cull what it would have hidden.
//! - **Marks.** Methods that read which objects a list drew visibly
//!   ([`Method::reads_marks`]: `roc`, `ioc`, HROC) learn it one of two ways
//!   ([`device::Capabilities::marks`]):
//!   - [`device::Marks::EarlyZ`]: the fragment shader of every occluding phase is
//!     declared `@early_depth_test(force)` and calls `hroc_mark(object)`
//!     from [`device::marks_wgsl`] when [`Draw::mark`] is set, with the
//!     [`Draw::marks`] bind group at the group it names ([`device::marks_layout`],
//!     from the device alone: pipelines come before the culler). To draw
//!     its own objects through the same pipelines, the host binds
//!     [`Culler::sink_marks`] there, which keeps no mark. Forced early-Z
//!     keeps hidden fragments from running at all, so a mark means "owns a
//!     fragment that passed" (HROC §3.1). A shader that discards (alpha
//!     testing) cannot force early-Z: flag such objects
//!     [`ObjectFlags::CUTOUT`]; the culler marks them by their boxes.
//!   - [`device::Marks::Ids`]: [`Draw::mark`] is never set and the host's shaders
//!     need no hroc line; the culler reads the object-ID target after each
//!     occluding list whose marks it reads, so views of those methods need
//!     one ([`ViewTargets::ids`]).
//!   - [`device::Marks::Boxes`] (asked for in [`CullerDesc::capabilities`]):
//!     [`Draw::mark`] is never set, the host's shaders need no hroc line,
//!     and no ID target is read for marks; the culler rasterizes the boxes
//!     of each such list's objects against the depth the list left. A
//!     fragment that discards (alpha testing, cutout foliage) then occludes
//!     too, drawn without early-Z in the same phase: its object needs no
//!     flag.
//! - **Object IDs.** For HROC with occluder filtering (OF, §4.2; the default
//!   [`Method::HROC`]), and with [`device::Marks::Ids`] for every method that reads
//!   marks, the host writes `object index + 1` to an `R32Uint` target (or,
//!   split in 16-bit halves, to an `Rg16Uint` one, which every backend can
//!   multisample; [`ViewTargets::ids`], of which the culler reads layer 0,
//!   mip 0, every sample) in the pass of every occluding [`Draw`],
//!   depth-tested as the depth is, at the depth's sample count, and
//!   clears it to 0 each frame. Otherwise `hroc-na`, `hroc-cr` and `hroc-sf` need no ID
//!   target.
//! - **Encoders.** A view records everything a frame writes into the
//!   encoder it is handed (copies from a staging belt, never
//!   `Queue::write_buffer`), and maps its read-backs when that encoder is
//!   submitted. So frames of a view may share an encoder, be submitted
//!   late or in another order, or be dropped unsubmitted (that frame is
//!   simply lost). The default [`Method::HROC`] (`hroc` = `hroc-sf+of`) and
//!   `hroc-sf` use stall-free counters (HROC §6): they never submit or
//!   wait, and take earlier frames' counts when they arrive. They may hand
//!   the host two lists in one phase (the estimate, then the overflow):
//!   draw both.
//! - **Mid-frame submits.** Methods with counter read-back
//!   ([`Method::submits_mid_frame`]: `hroc-cr+of`, `hroc-cr`, `ioc`, `oq`,
//!   `soq`, `chc++`) submit the host's encoder in the middle of
//!   [`View::cull`], wait for the GPU, and continue in a new encoder left in
//!   the host's `&mut CommandEncoder`. Record nothing before the cull that
//!   must not be submitted yet, and keep no debug group open across it.
//!   Cull such a view into the encoder its previous frame ended in, or
//!   after that encoder was submitted or dropped: otherwise its submit
//!   would run ahead of the previous frame's end, and the cull fails with
//!   [`Error::SubmitOrder`], submitting nothing.
//! - **Views.** Right-handed projections (the box tests rasterize the
//!   faces a right-handed view sees in front): perspective, symmetric or
//!   off-centre, finite or infinite far plane; or orthographic (a
//!   directional light's shadow cascade: HROC then casts parallel rays,
//!   one per pixel, and pads boxes by a pixel's constant size), its near
//!   plane anywhere; standard or reversed depth. The depth range is stated
//!   once, with the view's targets ([`ViewTargets::depth_range`]); each
//!   frame's projection must map near to it ([`ViewDesc::geometry`]
//!   derives the projection's, and refuses left-handed and mirrored
//!   views; [`View::cull`] refuses a projection whose range is not the
//!   targets'). Every
//!   conservative method serves both kinds (`woc` is measured on
//!   perspective views only).
//!   Each [`View`] keeps its own temporal state; all views share the
//!   culler's BVH and object buffers. A [`Culler`] is `Send + Sync` (an
//!   engine's shared resource) and a [`View`] is `Send`. Set [`FrameInput::cut`] on a camera
//!   cut; a view also treats a frame as a cut when its central ray turned
//!   or moved past [`MethodOptions::cut_turn_deg`] or
//!   [`MethodOptions::cut_move`] (an orthographic cascade's moves with its
//!   box, which follows the camera), and HROC then seeds its occluders
//!   from a coarse ray grid ([`MethodOptions::hroc_seed`]).
//!   A view draws into one layer and one mip of a depth texture
//!   ([`ViewTargets::at`]: a cascade of an array, a cube face, a mip),
//!   sized by that mip, single-sample or multisampled. The targets are
//!   given once, when the view is created ([`Culler::view`]);
//!   [`View::resize`] hands it others (a new size, or a host that
//!   alternates two depth textures: where size, format and samples stay,
//!   the view keeps its visible set; else it starts over as after a cut). A
//!   directional light's cascades are views of their own, each culled
//!   against its own depth: never cull casters against the camera's
//!   depth, since a caster hidden from the camera can still cast a visible
//!   shadow. A depth-only shadow pass usually has no ID target: cull it
//!   with a method that needs none (`hzb`; `hroc-na` or `roc` with
//!   early-Z marks, whose depth-only pipelines then need a marking
//!   fragment stage).
//! - **Non-occluders.** [`ObjectFlags::NOT_OCCLUDER`] objects (blended
//!   glass, particles) are culled like any other object but never enter the
//!   occlusion map: they come back in [`Phase::NonOccluders`], last, to draw
//!   with depth test on, depth writes off, and no ID writes.
//!   [`ObjectFlags::NEVER_CULL`] objects come back in [`Phase::Always`], first
//!   (or, when also not occluders, in [`Phase::NonOccluders`]).
//! - **Moving, added and removed objects.** An object's box must hold it
//!   on every frame it is drawn: change boxes before the frame that draws
//!   the new transforms, with [`Culler::set_bounds`] (from the CPU) or
//!   [`Culler::set_bounds_gpu`] (from a buffer the host fills on the GPU,
//!   recorded into the host's encoder). Both drop the moved objects'
//!   oriented boxes ([`Culler::set_bounds_gpu`] drops all of them): give
//!   the new ones with [`Culler::set_oriented`]. [`Culler::add_objects`] hands out
//!   slots (lowest free first; reserve room with [`CullerDesc::capacity`]),
//!   and [`Culler::remove_objects`] empties them; an object's index is its
//!   slot for as long as it lives. Static objects that move are refit into
//!   the BVH, which is rebuilt by the [`options::MotionOptions`] policy;
//!   [`ObjectFlags::DYNAMIC`] objects stay out of the tree and are tested on
//!   their own box (HROC §6's hybrid), so moving them costs only their box.
//!   Set or clear the flag at any time ([`Culler::set_flags`]: a door that
//!   starts to move). Views follow every change on their next frame; a
//!   method that cannot says so ([`Method::takes_motion`],
//!   [`Method::takes_dynamic`]) and refuses the frame.
//! - **Validation.** [`CullerDesc::validation`] (on in debug builds)
//!   checks on the GPU that the host's draws keep this contract, and turns
//!   each mistake that would cull a visible object into an
//!   [`Error::Validation`] of a later [`View::cull`], returned after that
//!   frame is recorded in full, so a finding costs no frame (README.md's
//!   "Validation" tables what it sees, and why ties at equal depth are no
//!   miss). Lists read for marks are in object order, which the check of
//!   hidden marks relies on.
//!
//! ## Engines that draw their own frame
//! An engine that runs its own passes and builds its own draws (per
//! material, from its own indirect parameters; Bevy) culls a view with
//! [`View::steps`] in place of [`View::cull`]: no draw lists, but three
//! command buffers it submits around its early and late depth passes
//! ([`Steps`]), and [`View::visibility`], a buffer its shaders read
//! ([`device::visibility_wgsl`]) to tell which objects each pass draws.
//! The contract above holds for its passes as for the lists' (depth,
//! clearing, IDs); its shaders need no hroc line with
//! [`device::Marks::Boxes`]. [`View::steps`] says which methods run
//! stepwise and what each step holds.
//!
//! ## Methods
//! [`Method`] is the one registry. Every method fits the contract except
//! `ref`, the benchmark's ideal culler, which needs `noc`'s ID image before
//! the frame ([`View::set_oracle`]); `woc` takes standard depth only and is
//! not conservative.
//!
//! HROC's occluder filtering (OF, in [`Method::HROC`]) runs in each view
//! only where it changes the result: one frame in eight, the filter also
//! counts the objects it keeps against those the merge (O ∪ D) would keep,
//! read back without a stall, and until the next count arrives the view
//! filters only if the last one kept at most nine tenths (a camera in a
//! city), else merges (a light looking down on roofs, where every drawn
//! object owns a pixel). Either next V is conservative, as V only orders
//! the frame. Where D is not marked (ID or box marks) the view always
//! filters. [`View::stats`]' `filtered` says what a frame ran.
//!
//! [`Method::Auto`] is the culler to leave on: each frame of each view, the
//! cheapest of `noc`, `vfc`, `hzb` and HROC (`hroc` with an ID target, else
//! `hroc-sf`) on this device, scene and path, chosen by a cost model that
//! GPU timestamps calibrate (two in every frame of a probe or a switch, in
//! one steady frame in four), read back without a stall
//! ([`stats::FrameStats::gpu_ns`]; without `TIMESTAMP_QUERY`, which [`device::features`]
//! requests where the adapter has it, the CPU clock's frame period between
//! the view's frames stands in: a GPU-bound host's frame time). Each frame
//! is one candidate's whole frame, and a candidate taking over starts from
//! the last `hzb` or HROC frame's visible set (which only orders its work)
//! or as after a cut, so `auto` is as conservative as they are and takes
//! what they take (motion, flags, MSAA, layers, every tier). [`View::culled_by`]
//! says which ran. Its first frames calibrate (about ten: every plausible
//! candidate runs); it then probes a stale estimate at most one frame in
//! thirty, and an occlusion method after a change of view (a camera cut,
//! or a frustum three times fuller or emptier) at most one frame in five
//! and while the probes cost under 4 % of the time.
//!
//! ## Public API
//! Everything a host touches, at the crate root (`tests/api_list.rs`
//! checks this list against what the crate exports, and caps it):
//! - the culler and its views: [`Culler`], [`CullerDesc`], [`View`],
//!   [`ViewDesc`], [`ViewTargets`], [`DepthRange`], [`FrameInput`]; a
//!   frame's views culled as a set ([`Culler::cull_views`]: a camera, its
//!   light's cascades, a point light's faces);
//! - objects: [`ObjectDesc`], [`ObjectFlags`], [`Aabb`];
//! - the draws handed to the host: [`Draw`], [`DrawHost`], [`Phase`];
//! - an engine's own frame: [`Steps`] ([`View::steps`], with
//!   [`View::visibility`]);
//! - methods: [`Method`], [`MethodOptions`];
//! - errors: [`Error`], [`Result`];
//! - and the modules [`device`] (features, limits, capabilities, the marks
//!   shaders' WGSL and layout), [`stats`] (what a view measures),
//!   [`options`] (HROC's variants, motion), [`geometry`] (oriented boxes,
//!   view conventions) and [`bvh`] (the object BVH: [`CullerDesc::split`],
//!   [`Culler::bvh`]).
//!
//! The internals (the methods' state, their CPU references and debug
//! read-backs, the WGSL sources and their Rust mirrors, GPU helpers) sit
//! in layers below the facade, each resting only on those below it
//! (`tests/layers.rs`), and are reachable for hroc's own tests and tools
//! through a hidden `testing` module that is not part of the API.

#![deny(missing_docs)]

mod aabb;
pub mod bvh;
mod capabilities;
mod compact;
mod contract;
mod cull;
pub mod device;
mod error;
mod flag_split;
mod frustum;
pub mod geometry;
mod gpu;
mod host;
mod id_marks;
mod layout;
mod list_pass;
mod metrics;
mod objects;
pub mod options;
mod reflect;
mod set_frustum;
mod shaders;
pub mod stats;
mod tally;
#[doc(hidden)]
pub mod testing;
mod validation;
mod visibility;

pub use aabb::Aabb;
pub use cull::{Method, MethodOptions};
pub use error::{Error, Result};
pub use frustum::{DepthRange, ViewDesc};
pub use host::{Culler, CullerDesc, Draw, DrawHost, FrameInput, ObjectDesc, ObjectFlags, Phase, Steps, View, ViewTargets};
