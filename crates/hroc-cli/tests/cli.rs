//! The `hroc` binary: every bad input is one clear line on stderr and a
//! non-zero exit, never a panic; `scene info` works for every scene.

use std::path::PathBuf;
use std::process::{Command, Output};

fn hroc(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hroc"));
    c.args(args).env("XDG_RUNTIME_DIR", std::env::temp_dir());
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run hroc")
}

fn tmp(name: &str, contents: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hroc-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, contents).unwrap();
    p
}

/// Fails with a one-line error mentioning `needle`.
fn assert_clean_error(out: &Output, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure, got success; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    let lines: Vec<_> = err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(lines.len(), 1, "want one error line: {err}");
    assert!(lines[0].to_lowercase().contains(&needle.to_lowercase()), "'{needle}' not in: {err}");
}

#[test]
fn unknown_scene_key() {
    assert_clean_error(&hroc(&["bench", "--scene", "atlantis"], &[]), "unknown scene 'atlantis'");
    assert_clean_error(&hroc(&["scene", "info", "atlantis"], &[]), "unknown scene");
}

#[test]
fn missing_files() {
    assert_clean_error(&hroc(&["scene", "info", "/nonexistent/city.glb"], &[]), "file not found");
    assert_clean_error(&hroc(&["bench", "--scene", "nowhere.obj"], &[]), "file not found");
    assert_clean_error(&hroc(&["bench", "--camera-path", "/nonexistent/path.json"], &[]), "file not found");
}

#[test]
fn malformed_camera_paths() {
    for (name, text, needle) in [
        ("trunc.json", r#"{"keys":[{"t":0,"eye":[0,1"#, "malformed camera path"),
        ("empty.json", r#"{"keys":[]}"#, "no keys"),
        ("order.json", r#"{"keys":[{"t":5,"eye":[0,1,0],"target":[0,1,1]},{"t":1,"eye":[0,1,0],"target":[0,1,1]}]}"#, "before previous"),
        ("same.json", r#"{"keys":[{"t":0,"eye":[0,1,0],"target":[0,1,0]}]}"#, "eye equals target"),
        ("fov.json", r#"{"keys":[{"t":0,"eye":[0,1,0],"target":[0,1,1],"fov_y_deg":0}]}"#, "fov_y_deg"),
        ("up.json", r#"{"keys":[{"t":0,"eye":[0,0,0],"target":[0,1,0]}]}"#, "parallel"),
        ("nan.json", r#"{"keys":[{"t":0,"eye":[0,1e999,0],"target":[0,1,1]}]}"#, "malformed camera path"),
    ] {
        let p = tmp(name, text);
        assert_clean_error(&hroc(&["bench", "--camera-path", p.to_str().unwrap()], &[]), needle);
    }
}

#[test]
fn bad_arguments() {
    assert_clean_error(&hroc(&["bench", "--methods", "noc,magic"], &[]), "unknown method 'magic'");
    assert_clean_error(&hroc(&["bench", "--frames", "0"], &[]), "--frames");
    let out = hroc(&["bench", "--resolution", "0x10"], &[]);
    assert!(!out.status.success() && !String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn empty_and_invalid_obj_scenes() {
    let empty = tmp("empty.obj", "# nothing here\n");
    assert_clean_error(&hroc(&["scene", "info", empty.to_str().unwrap()], &[]), "empty scene");
    let nan = tmp("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    let out = hroc(&["bench", "--scene", nan.to_str().unwrap()], &[]);
    assert_clean_error(&out, "");
}

#[test]
fn no_vulkan_adapter_says_how_to_get_lavapipe() {
    // Point the Vulkan loader at a driver list that does not exist.
    let out = hroc(&["bench", "--objects", "10", "--frames", "1"], &[("VK_ICD_FILENAMES", "/nonexistent/icd.json"), ("VK_DRIVER_FILES", "/nonexistent/icd.json")]);
    assert_clean_error(&out, "mesa-vulkan-drivers");
}

#[test]
fn scene_info_for_every_builtin_scene_and_a_gltf_file() {
    let mut specs: Vec<String> = hroc_scene::generators::keys().iter().map(|s| s.to_string()).collect();
    specs.push(concat!(env!("CARGO_MANIFEST_DIR"), "/../hroc-scene/tests/data/gltf-samples/Duck.gltf").to_string());
    for spec in specs {
        let small = ["scene", "info", spec.as_str(), "--objects", "500"];
        let args: &[&str] = if spec.ends_with(".gltf") { &small[..3] } else { &small };
        let out = hroc(args, &[]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{spec}: {}", String::from_utf8_lossy(&out.stderr));
        for needle in ["objects", "triangles", "vertices", "sah", "mid", "eq", "build ms", "depth"] {
            assert!(text.contains(needle), "{spec}: '{needle}' missing from\n{text}");
        }
    }
}

#[test]
fn bench_writes_json_with_the_documented_fields() {
    let dir = std::env::temp_dir().join(format!("hroc-json-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("r.json");
    let out = hroc(
        &["bench", "--scene", "radial-city", "--objects", "600", "--frames", "4", "--resolution", "128x72", "--methods", "noc,vfc,ref", "--json", json.to_str().unwrap()],
        &[],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = String::from_utf8_lossy(&out.stdout);
    for m in ["noc", "vfc", "ref"] {
        assert!(table.lines().any(|l| l.starts_with(m)), "no {m} row:\n{table}");
    }
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for k in ["scene", "objects", "triangles", "resolution", "adapter", "frames", "rows"] {
        assert!(v.get(k).is_some(), "missing {k}");
    }
    assert_eq!(v["frames"], 4);
    assert_eq!(v["resolution"], "128x72");
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for r in rows {
        for k in ["method", "ms_mean", "ms_p95", "gpu_ms_mean", "c_over_n", "c_over_r", "false_negatives", "missing_pixels"] {
            assert!(r.get(k).is_some(), "row missing {k}: {r}");
        }
        assert_eq!(r["false_negatives"], 0);
        assert_eq!(r["missing_pixels"], 0);
    }
    let reference = rows.iter().find(|r| r["method"] == "ref").unwrap();
    assert_eq!(reference["c_over_r"], 1.0);
    assert!(table.contains("not validated") && v["validated"] == false, "{table}");
}

/// `--validate`: every view's draws are checked, and the table says so.
#[test]
fn bench_validates_when_asked() {
    let args = ["bench", "--scene", "radial-city", "--objects", "600", "--frames", "6", "--resolution", "128x72", "--methods", "noc,hzb,hroc,auto"];
    let out = hroc(&[&args[..], &["--validate", "--shadow-cascades", "1"]].concat(), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("validated: no finding"), "{table}");
}

fn hroc_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_hroc")).args(args).env("XDG_RUNTIME_DIR", std::env::temp_dir()).output().expect("run hroc")
}

#[test]
fn bench_rows_and_options_on_the_command_line() {
    let json = std::env::temp_dir().join(format!("hroc-queries-{}.json", std::process::id()));
    let out = hroc_cli(&[
        "bench",
        "--scene",
        "radial-city",
        "--objects",
        "300",
        "--frames",
        "3",
        "--resolution",
        "96x64",
        "--methods",
        "noc,oq,soq,chc++",
        "--soq-base-time",
        "0.25",
        "--chc-batch",
        "8",
        "--chc-nav",
        "3",
        "--chc-dmax",
        "2",
        "--chc-smax",
        "1.2",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let _ = std::fs::remove_file(&json);
    let rows = v["rows"].as_array().unwrap();
    for m in ["oq", "soq", "chc++"] {
        let r = rows.iter().find(|r| r["method"] == m).unwrap_or_else(|| panic!("no {m} row"));
        assert_eq!((r["false_negatives"].as_u64(), r["missing_pixels"].as_u64()), (Some(0), Some(0)), "{m}");
        for k in ["queries", "query_batches", "wait_ms"] {
            assert!(r["stats"][k].as_f64().is_some(), "{m}: no stats.{k}: {r}");
        }
        assert!(r["stats"]["queries"].as_f64().unwrap() > 0.0, "{m} issued no queries");
    }
    for bad in [["--chc-nav", "0"], ["--soq-base-time", "0"], ["--chc-batch", "0"], ["--chc-smax", "nan"]] {
        let out = hroc_cli(&["bench", "--methods", "chc++", "--frames", "1", bad[0], bad[1]]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(bad[0]) && !err.contains("panicked"), "{bad:?}: {err}");
    }
    let methods = String::from_utf8_lossy(&hroc_cli(&["methods"]).stdout).to_string();
    for m in ["oq ", "soq ", "chc++ "] {
        assert!(methods.lines().any(|l| l.starts_with(m)), "{m} not listed:\n{methods}");
    }
}

#[test]
fn the_cli_takes_an_ioc_range() {
    let hroc = |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_hroc")).args(args).env("XDG_RUNTIME_DIR", std::env::temp_dir()).output().unwrap();
    let out = hroc(&["bench", "--methods", "ioc", "--ioc-range", "5:2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("5:2") && !err.contains("panicked"), "{err}");
    let out = hroc(&["bench", "--methods", "noc,ioc", "--ioc-range", "2:4", "--scene", "rooms", "--objects", "300", "--frames", "3", "--resolution", "64x48"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.lines().any(|l| l.starts_with("ioc ")), "{text}");
}

#[test]
fn bench_moves_objects_and_refuses_what_cannot_follow() {
    let json = std::env::temp_dir().join(format!("hroc-moving-{}.json", std::process::id()));
    let out = hroc_cli(&[
        "bench",
        "--scene",
        "radial-city",
        "--objects",
        "600",
        "--frames",
        "6",
        "--resolution",
        "96x64",
        "--methods",
        "noc,vfc,roc,hzb,hroc",
        "--moving",
        "0.3",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("moving 30%") && text.contains("BVH refit"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let _ = std::fs::remove_file(&json);
    assert!(v["moved_objects"].as_u64().unwrap() > 100, "{v}");
    for r in v["rows"].as_array().unwrap() {
        assert_eq!((r["false_negatives"].as_u64(), r["missing_pixels"].as_u64()), (Some(0), Some(0)), "{r}");
    }
    for (bad, want) in [("--moving=1.5", "--moving 1.5"), ("--moving=-0.1", "--moving -0.1")] {
        let out = hroc_cli(&["bench", "--frames", "1", bad]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(want) && !err.contains("panicked"), "{err}");
    }
    let out = hroc_cli(&["bench", "--frames", "1", "--methods", "noc,chc++", "--moving", "0.1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("chc++") && err.contains("static scenes only"), "{err}");
}
