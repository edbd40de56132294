//! `hroc bench`: every method over the same camera path in one process,
//! side by side per frame, checked against `noc`. A run
//! ([`run_scene`]) reads as its steps: update the objects, draw the truth,
//! run each method (and its cascades), then the rows.

mod check;
mod marks_cost;
mod options;
pub mod plot;
pub mod report;
mod rows;
mod run;
pub mod session;
pub mod table;
mod validation_cost;

use crate::error::Result;
pub use check::{Check, Truth};
use hroc::Method;
pub use marks_cost::{marks_cost, MarksCost};
pub use options::BenchOptions;
pub use rows::{BenchReport, InvocationsMean, MethodRow};
pub use run::{frame_count, load_inputs, load_path, run, run_scene, warmup_frames};
pub use session::{FrameResult, Projection, Session, SessionDesc};
pub use validation_cost::{validation_cost, ValidationCost};

/// Methods as lists name them: `a,b,c` (in the order given, without
/// repeats) or `all` ([`Method::ALL`]), written back as their names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MethodList(pub Vec<Method>);

impl std::str::FromStr for MethodList {
    type Err = crate::Error;
    fn from_str(spec: &str) -> Result<MethodList> {
        if spec.trim() == "all" {
            return Ok(MethodList(Method::ALL.to_vec()));
        }
        let mut out = Vec::new();
        for m in spec.split(',').map(str::trim).filter(|m| !m.is_empty()) {
            let m: Method = m.parse().map_err(|e| match e {
                hroc::Error::Arg(msg) => crate::Error::Options(format!("{msg}; or all, alone, for every method")),
                e => e.into(),
            })?;
            if !out.contains(&m) {
                out.push(m);
            }
        }
        if out.is_empty() {
            return Err(crate::Error::Options("no methods given".into()));
        }
        Ok(MethodList(out))
    }
}

impl std::fmt::Display for MethodList {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0.iter().map(|m| m.name()).collect::<Vec<_>>().join(","))
    }
}

/// Parses `a,b,c` or `all` into methods ([`MethodList`]).
pub fn parse_methods(spec: &str) -> Result<Vec<Method>> {
    Ok(spec.parse::<MethodList>()?.0)
}

/// Year, month, day of a day count since 1970-01-01 (H. Hinnant's `civil_from_days`).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// `WxH`, both sides positive (clap value parser).
pub fn parse_resolution(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s.split_once('x').ok_or_else(|| format!("resolution '{s}' is not WxH"))?;
    let w: u32 = w.parse().map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h.parse().map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 {
        return Err(format!("resolution '{s}' has a zero side"));
    }
    Ok((w, h))
}

pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Nearest-rank percentile.
pub fn percentile(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let rank = ((p * s.len() as f64).ceil() as usize).clamp(1, s.len());
    s[rank - 1]
}

/// The tier's name ([`crate::gpu::Tier`]), or the three capabilities
/// (draw count, marks, read-only depth).
pub fn capabilities_name(c: hroc::device::Capabilities) -> String {
    match crate::gpu::Tier::ALL.into_iter().find(|t| t.capabilities() == c) {
        Some(t) => t.name().into(),
        None => format!("{:?} draw count, {:?} marks, {} read-only depth", c.draw_count, c.marks, if c.read_only_depth { "with" } else { "without" }),
    }
}

#[cfg(test)]
mod tests {
    use super::civil_from_days;

    #[test]
    fn method_lists_parse_in_order_without_repeats() {
        use hroc::{options::Variant, Method};
        let list = |s: &str| super::parse_methods(s);
        assert_eq!(list("vfc, hroc-cr+of,vfc").unwrap(), [Method::Vfc, Method::Hroc(Variant::CR_OF)]);
        assert_eq!(list("hroc,hroc-sf+of").unwrap(), [Method::HROC]);
        assert_eq!(list("all").unwrap(), Method::ALL);
        assert!(list(" ").is_err());
    }

    #[test]
    fn days_become_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }
}
