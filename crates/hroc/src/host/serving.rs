//! What a [`Culler`] runs with on its device, and which methods it serves:
//! the capabilities it picked, the device limits each method's passes
//! need, and the refusal of a method by name with the reason.

use super::*;
use crate::capabilities::{Capabilities, Marks};
use crate::contract::Targets;
use crate::cull::{Method, MethodOptions};
use crate::error::{Error, Result};
use crate::frustum::DepthRange;
use crate::reflect::Layout;

/// Checks the device's limits against what `layouts` and the culler's
/// compute passes need.
pub(super) fn check_limits(limits: &wgpu::Limits, what: &str, layouts: &[Layout]) -> Result<()> {
    let storage = layouts.iter().map(|l| l.storage_buffers_per_stage()).max().unwrap_or(0) as u64;
    let needs = [
        ("max_storage_buffers_per_shader_stage", storage, limits.max_storage_buffers_per_shader_stage as u64),
        ("max_bind_groups", 1, limits.max_bind_groups as u64),
        ("max_compute_invocations_per_workgroup", 256, limits.max_compute_invocations_per_workgroup as u64),
        ("max_compute_workgroup_size_x", 256, limits.max_compute_workgroup_size_x as u64),
        ("max_compute_workgroup_size_y", 16, limits.max_compute_workgroup_size_y as u64),
    ];
    match needs.into_iter().find(|&(_, needed, have)| have < needed) {
        Some((limit, needed, have)) => Err(Error::DeviceLimit { what: what.to_string(), limit, needed, have }),
        None => Ok(()),
    }
}

/// What the culler runs with, and which methods it serves.
impl Culler {
    /// The capabilities the culler runs with.
    pub fn capabilities(&self) -> Capabilities {
        self.caps
    }

    /// `Ok` when this culler can serve `method` on its device; otherwise
    /// [`Error::MethodUnavailable`] with the reason (a capability it runs
    /// without, or a device limit, named with the value needed).
    pub fn serves(&self, method: Method) -> Result<()> {
        self.serves_with(method, &self.options)
    }

    /// [`Culler::serves`] for a view with `options` ([`Culler::view_with`]).
    pub fn serves_with(&self, method: Method, options: &MethodOptions) -> Result<()> {
        let refuse = |reason: String| Err(Error::MethodUnavailable { method: method.to_string(), reason });
        let rounds = options.hroc_rounds > 1 || options.hroc_occluder_rounds;
        if matches!(method, Method::Hroc(_)) && rounds && !self.caps.attached_box_tests(&self.gpu.device, true) {
            return refuse(
                "its rounds test boxes under forced early-Z against a depth attachment they also sample, which needs early-Z marks (SHADER_EARLY_DEPTH_TEST) and read-only depth attachments (READ_ONLY_DEPTH_STENCIL)"
                    .into(),
            );
        }
        match check_limits(&self.gpu.device.limits(), method.name(), method.layouts()) {
            Err(Error::DeviceLimit { limit, needed, have, .. }) => refuse(format!("it needs the device's {limit} to be at least {needed}, and it is {have}")),
            other => other,
        }
    }

    /// Errors when `method`'s views need what `t` lacks: the object-ID
    /// target (occluder filtering, or marks read with [`Marks::Ids`]), or
    /// standard depth.
    pub(super) fn check_targets(&self, method: Method, t: &Targets) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidTargets(m));
        if method.needs_ids() && t.ids.is_none() {
            return bad(format!("{method} filters occluders by the object-ID target (OF, HROC §4.2): pass ViewTargets::ids, or use hroc-cr / hroc-na"));
        }
        if self.caps.marks == Marks::Ids && method.reads_marks() && t.ids.is_none() {
            return bad(format!(
                "{method} reads which objects the host drew, and this culler marks them from the object-ID target (Marks::Ids, no forced early-Z): pass ViewTargets::ids"
            ));
        }
        if t.depth == DepthRange::Reversed && !method.supports_reversed_depth() {
            return bad(format!("{method} supports standard depth only"));
        }
        Ok(())
    }

    /// `auto`'s candidates for a view of targets `t` (none for another
    /// `method`): `noc`, `vfc`, `hzb` and HROC (`hroc` with an ID target,
    /// else `hroc-sf`), those the culler serves and the targets allow.
    pub(super) fn auto_candidates(&self, method: Method, t: &Targets, options: &MethodOptions) -> Vec<Method> {
        if method != Method::Auto {
            return Vec::new();
        }
        let hroc = if t.ids.is_some() { Method::HROC } else { Method::Hroc(crate::cull::Variant::SF) };
        [Method::Noc, Method::Vfc, Method::Hzb, hroc].into_iter().filter(|&m| self.serves_with(m, options).is_ok() && self.check_targets(m, t).is_ok()).collect()
    }

    /// The methods of [`Method::ALL`] this culler serves ([`Culler::serves`]).
    pub fn methods(&self) -> Vec<Method> {
        Method::ALL.into_iter().filter(|&m| self.serves(m).is_ok()).collect()
    }
}
