//! GPU-free: the crate exports exactly the public API its docs list (the
//! crate docs' "Public API" section), at most 23 names at its root (the
//! rest in the modules `device`, `stats`, `options`, `geometry` and
//! `bvh`), and none of its internals.

use std::collections::BTreeSet;

/// What a host touches, at most: glyphon serves text with about 8 names;
/// hroc serves two kinds of host (draw lists, and engines that draw their
/// own frame from visibility as data).
const MAX_ROOT_NAMES: usize = 23;

fn lib_rs() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/lib.rs")).unwrap()
}

/// Names the crate root exports: `pub use` items and `pub mod`s, but the
/// hidden `testing` module.
fn exported(lib: &str) -> BTreeSet<String> {
    let code: String = lib.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
    let mut out = BTreeSet::new();
    for stmt in code.split(';') {
        // Attributes (`#![...]`, `#[doc(hidden)]`) are not part of the item.
        let stmt = stmt.lines().filter(|l| !l.trim_start().starts_with('#')).collect::<Vec<_>>().join(" ");
        let stmt = stmt.trim();
        if let Some(rest) = stmt.strip_prefix("pub mod ") {
            out.insert(rest.trim().to_string());
        } else if let Some(rest) = stmt.strip_prefix("pub use ") {
            let list = match (rest.find('{'), rest.rfind('}')) {
                (Some(a), Some(b)) => rest[a + 1..b].to_string(),
                _ => rest.rsplit("::").next().unwrap().to_string(),
            };
            out.extend(list.split(',').map(|n| n.trim().rsplit(' ').next().unwrap().to_string()).filter(|n| !n.is_empty()));
        }
    }
    out.remove("testing");
    out
}

/// The names the "Public API" section of the crate docs links.
fn documented(lib: &str) -> BTreeSet<String> {
    let start = lib.find("//! ## Public API").expect("a Public API section");
    let section: String = lib[start..].lines().skip(1).take_while(|l| l.starts_with("//!") && !l.starts_with("//! ##")).collect::<Vec<_>>().join(" ");
    let mut out = BTreeSet::new();
    for part in section.split("[`").skip(1) {
        let name = part.split('`').next().unwrap();
        out.insert(name.split("::").next().unwrap().to_string());
    }
    out
}

#[test]
fn the_crate_exports_its_documented_api_and_no_internals() {
    let lib = lib_rs();
    let (exported, documented) = (exported(&lib), documented(&lib));
    assert!(exported.len() <= MAX_ROOT_NAMES, "{} names at the root (at most {MAX_ROOT_NAMES}): {exported:?}", exported.len());
    for module in ["device", "stats", "options", "geometry", "bvh"] {
        assert!(exported.contains(module), "the module {module} is exported");
    }
    let undocumented: Vec<_> = exported.difference(&documented).collect();
    let missing: Vec<_> = documented.difference(&exported).collect();
    assert!(undocumented.is_empty(), "exported but not in the Public API list of the crate docs: {undocumented:?}");
    assert!(missing.is_empty(), "listed in the crate docs but not exported: {missing:?}");
    for internal in ["gpu", "layout", "shaders", "rng", "cull", "compact", "host", "aabb", "frustum", "error", "capabilities", "tally", "DrawList", "Targets"] {
        assert!(!exported.contains(internal), "the internal module {internal} is exported");
    }
}

/// An engine keeps the culler in a resource shared by its systems and
/// moves views between threads.
#[test]
fn the_culler_is_shared_and_views_move_across_threads() {
    fn shared<T: Send + Sync>() -> usize {
        std::mem::size_of::<T>()
    }
    fn movable<T: Send>() -> usize {
        std::mem::size_of::<T>()
    }
    assert!(shared::<hroc::Culler>() > 0 && movable::<hroc::View>() > 0);
}
