//! `hroc report`: a small report is complete (every table, plot and heat
//! map), its numbers are conservative, and the HTML renders in headless
//! Chromium with every image loaded and no script error.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hroc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hroc")).args(args).env("XDG_RUNTIME_DIR", std::env::temp_dir()).output().expect("run hroc")
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hroc-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Every section of the default report, scaled to seconds on lavapipe.
fn small_report(out: &Path) -> Output {
    hroc(&[
        "report",
        "--out",
        out.to_str().unwrap(),
        "--scenes",
        "radial-city,factory",
        "--objects",
        "500",
        "--frames",
        "10",
        "--methods",
        "noc,vfc,ref,roc,hzb,hroc-na,hroc-cr,hroc-of,hroc-cr+of",
        "--splits",
        "sah,mid",
        "--sweep",
        "250,500",
        "--sweep-frames",
        "3",
        "--hires",
        "1280x720",
        "--hires-methods",
        "noc,hroc",
        "--hires-frames",
        "2",
        "--motion",
        "0,0.5",
        "--motion-methods",
        "noc,vfc,roc,hzb,hroc",
        "--clusters",
        "64",
    ])
}

fn chromium() -> PathBuf {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|b| std::env::var_os("PATH").and_then(|p| std::env::split_paths(&p).map(|d| d.join(b)).find(|f| f.is_file())));
    found.expect("Chromium not found: run scripts/ensure-test-deps.sh (installs Debian's chromium)")
}

/// Loads the page headless and returns (DOM after load, browser log).
fn render_in_chromium(page: &Path) -> (String, String) {
    let profile = out_dir("chromium-profile");
    // The flags of a closed-network machine: no background connections.
    let out = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=10000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.canonicalize().unwrap().display()))
        .output()
        .expect("run chromium");
    let _ = std::fs::remove_dir_all(&profile);
    assert!(out.status.success(), "chromium failed: {}", String::from_utf8_lossy(&out.stderr));
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn report_is_complete_and_renders_in_chromium() {
    let out = out_dir("small");
    let r = small_report(&out);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "report failed: {err}");

    for f in ["index.html", "report.md", "data.json"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    for stem in ["frames-radial-city", "frames-factory", "stages-radial-city", "stages-factory", "sweep-frame", "sweep-culling"] {
        for ext in ["svg", "png"] {
            let p = out.join("plots").join(format!("{stem}.{ext}"));
            assert!(std::fs::metadata(&p).map(|m| m.len() > 500).unwrap_or(false), "{} missing or empty", p.display());
        }
    }
    for m in ["roc", "hroc", "ref", "hroc-minus-ref", "roc-minus-hroc"] {
        let p = out.join("images").join(format!("overdraw-{m}.png"));
        let img = image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert_eq!((img.width(), img.height()), (640, 360));
    }

    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for h in [
        "Frame time (HROC paper Table 1)",
        "HROC accelerations",
        "BVH splits",
        "Culling efficiency",
        "Frame time along the path",
        "per-stage GPU time",
        "The frame's shape",
        "Overdraw",
        "Scale sweep",
        "High resolution",
        "Scenes (Lee's thesis, Table 1)",
        "Moving objects",
        "Clusters",
    ] {
        assert!(md.contains(h), "report.md lacks '{h}'");
    }

    // Every method here is conservative: the report's own checks say 0.
    let data: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("data.json")).unwrap()).unwrap();
    let mut reports: Vec<&serde_json::Value> = Vec::new();
    for s in data["scenes"].as_array().unwrap() {
        reports.push(&s["main"]);
        reports.extend(s["splits"].as_array().unwrap());
    }
    reports.extend(data["sweep"].as_array().unwrap().iter().map(|p| &p["report"]));
    reports.push(&data["hires"]);
    reports.extend(data["motion"].as_array().unwrap());
    reports.extend(data["clusters"].as_array().unwrap().iter().map(|c| &c["report"]));
    assert_eq!(reports.len(), 2 * 2 + 2 + 1 + 2 + 2);
    assert_eq!(data["clusters"][1]["triangles"], 64);
    assert!(data["clusters"][1]["report"]["objects"].as_u64() > data["clusters"][0]["report"]["objects"].as_u64(), "clusters split nothing");
    assert_eq!(data["motion"][1]["moving"], 0.5);
    for rep in reports {
        for row in rep["rows"].as_array().unwrap() {
            assert_eq!(row["false_negatives"], 0, "{} {}: false negatives", rep["scene"], row["method"]);
            assert_eq!(row["missing_pixels"], 0, "{} {}: missing pixels", rep["scene"], row["method"]);
        }
    }
    assert_eq!(data["hires"]["resolution"], "1280x720");

    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let images = html.matches("<img ").count();
    assert!(images >= 6 + 5, "{images} images in index.html");
    let (dom, log) = render_in_chromium(&out.join("index.html"));
    assert!(dom.contains(&format!("data-images-loaded=\"{images}\"")), "not every image loaded; body: {}", dom.lines().find(|l| l.contains("<body")).unwrap_or(""));
    assert!(dom.contains("data-images-failed=\"0\""));
    for bad in ["Uncaught", "ERR_FILE_NOT_FOUND", "Not allowed to load"] {
        assert!(!log.contains(bad), "browser log has '{bad}': {log}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_report_arguments_are_clean_errors() {
    let out = out_dir("bad");
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["--scenes", "atlantis"], "unknown scene 'atlantis'"),
        (vec!["--scenes", "/nonexistent/city.glb"], "file not found"),
        (vec!["--frames", "0"], "--frames must be at least 1"),
        (vec!["--sweep", "100,lots"], "'lots' is not an object count"),
        (vec!["--splits", "sah,best"], "unknown split 'best'"),
        (vec!["--heat-frame", "99"], "past the last frame"),
        (vec!["--motion", "0,1.5"], "'1.5' is not a fraction from 0 to 1"),
        (vec!["--motion-methods", "noc,chc++"], "chc++ takes static scenes only"),
    ] {
        let mut a = vec!["report", "--out", o];
        a.extend(args);
        let r = hroc(&a);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success() && !err.contains("panicked"), "{a:?}: {err}");
        assert!(err.contains(needle), "{a:?}: '{needle}' not in {err}");
    }
    // Arguments are checked before anything is written.
    assert!(!out.exists());
}
