//! GPU-free: the core crate stays in layers of files of one idea. No
//! top-level module imports, directly or in a circle, one that imports it
//! (`crate::x` paths in code, comments left out), and no source file of
//! any crate of the workspace (sources, tests, examples) is over 600 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 600;

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() && p.file_name().is_some_and(|n| n == "target") {
            continue;
        } else if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The `crate::name` paths of `code` with a lower-case first segment.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let name: String = code[i + 7..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '_' || c.is_ascii_digit()).collect();
        if !name.is_empty() {
            out.insert(name);
        }
    }
    out
}

#[test]
fn every_crate_s_files_stay_small() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    for dir in ["crates", "examples"] {
        sources(&root.join(dir), &mut files);
    }
    assert!(files.len() > 100, "{} Rust files under crates/ and examples/", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).unwrap().lines().count();
            (lines > MAX_LINES).then(|| format!("{} ({lines} lines)", f.strip_prefix(&root).unwrap().display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines, split them by idea: {long:?}");
}

#[test]
fn modules_form_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut deps: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(&src).unwrap();
        let top = rel.components().next().unwrap().as_os_str().to_string_lossy().trim_end_matches(".rs").to_string();
        if top == "lib" {
            continue;
        }
        let code: String = text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
        let d = deps.entry(top.clone()).or_default();
        d.extend(crate_paths(&code).into_iter().filter(|m| *m != top));
    }
    assert!(deps.len() > 10, "modules found: {:?}", deps.keys());
    // Depth-first search for a path from each module back to itself.
    fn reaches(deps: &BTreeMap<String, BTreeSet<String>>, from: &str, to: &str, seen: &mut BTreeSet<String>, path: &mut Vec<String>) -> bool {
        for d in deps.get(from).into_iter().flatten() {
            if d == to {
                return true;
            }
            if deps.contains_key(d) && seen.insert(d.clone()) {
                path.push(d.clone());
                if reaches(deps, d, to, seen, path) {
                    return true;
                }
                path.pop();
            }
        }
        false
    }
    for m in deps.keys() {
        let mut path = vec![m.clone()];
        assert!(!reaches(&deps, m, m, &mut BTreeSet::new(), &mut path), "modules import each other in a circle: {} -> {m}", path.join(" -> "));
    }
}
