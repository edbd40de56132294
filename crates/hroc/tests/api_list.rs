//! GPU-free: the crate exports exactly the public API its docs list (the
//! crate docs' "Public API" section), and none of its internals.

use std::collections::BTreeSet;

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
    assert!(exported.len() > 25, "{exported:?}");
    let undocumented: Vec<_> = exported.difference(&documented).collect();
    let missing: Vec<_> = documented.difference(&exported).collect();
    assert!(undocumented.is_empty(), "exported but not in the Public API list of the crate docs: {undocumented:?}");
    assert!(missing.is_empty(), "listed in the crate docs but not exported: {missing:?}");
    for internal in ["gpu", "layout", "shaders", "rng", "cull", "compact", "host"] {
        assert!(!exported.contains(internal), "the internal module {internal} is exported");
    }
}
