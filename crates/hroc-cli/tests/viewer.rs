//! `hroc view` in a window: under a private Xvfb it renders a few frames,
//! saves a screenshot and exits 0. Needs Xvfb (`scripts/ensure-test-deps.sh`)
//! and Vulkan (`scripts/ensure-vulkan.sh`).

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

const HROC: &str = env!("CARGO_BIN_EXE_hroc");
/// `hroc view`'s default --resolution: the window's size and the screenshot's.
const WINDOW: (u32, u32) = (960, 540);

/// A scratch folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("hroc-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A private X server, killed when dropped, also when the test fails.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start(log: &Path) -> Xvfb {
        let installed = std::env::var_os("PATH").is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("Xvfb").is_file()));
        assert!(installed, "Xvfb is not installed: run scripts/ensure-test-deps.sh");
        // -displayfd: Xvfb picks a free display number and writes it once it accepts clients.
        let mut child = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(File::create(log).unwrap())
            .spawn()
            .expect("cannot start Xvfb");
        let mut line = String::new();
        let read = BufReader::new(child.stdout.take().unwrap()).read_line(&mut line);
        let number = line.trim().to_string();
        let x = Xvfb { child, display: format!(":{number}") };
        if read.is_err() || number.parse::<u32>().is_err() {
            panic!("Xvfb did not start: {}", std::fs::read_to_string(log).unwrap_or_default());
        }
        x
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM lets Xvfb remove its socket and lock file; SIGKILL if it lingers.
        let _ = Command::new("kill").arg(self.child.id().to_string()).status();
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Runs `hroc` on X11 display `display` (none: no display at all) within
/// `limit`; its exit status and output.
fn hroc(dir: &Path, args: &[&str], display: Option<&str>, limit: Duration) -> (ExitStatus, String) {
    let (out, err) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    let mut cmd = Command::new(HROC);
    cmd.args(args).stdin(Stdio::null()).stdout(File::create(&out).unwrap()).stderr(File::create(&err).unwrap());
    // X11 only: a Wayland session of the caller must not be picked first.
    cmd.env_remove("WAYLAND_DISPLAY").env_remove("WAYLAND_SOCKET");
    match display {
        Some(d) => cmd.env("DISPLAY", d),
        None => cmd.env_remove("DISPLAY"),
    };
    let mut child = cmd.spawn().expect("cannot run hroc");
    let deadline = Instant::now() + limit;
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("hroc {args:?} ran past {limit:?}: {}", std::fs::read_to_string(&err).unwrap_or_default());
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let text = std::fs::read_to_string(&out).unwrap_or_default() + &std::fs::read_to_string(&err).unwrap_or_default();
    (status, text)
}

#[test]
fn viewer_renders_frames_and_saves_a_screenshot_under_xvfb() {
    let dir = TempDir::new("viewer");
    let x = Xvfb::start(&dir.0.join("xvfb.log"));
    // Vulkan with the most it allows, and GL on the portable tier.
    for (name, device) in [("vulkan", &[][..]), ("gl-portable", &["--backend", "gl", "--tier", "portable"][..])] {
        let shot = dir.0.join(format!("shot-{name}.png"));
        let mut args = vec!["view", "radial-city", "--objects", "2000", "--frames", "10", "--screenshot", shot.to_str().unwrap()];
        args.extend_from_slice(device);
        let (status, output) = hroc(&dir.0, &args, Some(&x.display), Duration::from_secs(300));
        assert!(status.success(), "hroc view {name} failed ({status}): {output}");

        let img = image::open(&shot).unwrap_or_else(|e| panic!("{}: {e}", shot.display())).to_rgba8();
        assert_eq!(img.dimensions(), WINDOW, "{name}: screenshot is not the window's size");
        // The scene was drawn: sky, ground and many buildings, not one flat colour.
        let mut colours: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() >= 8, "{name}: screenshot has {} colours", colours.len());
    }
}

#[test]
fn viewer_without_a_display_fails_clearly() {
    let dir = TempDir::new("viewer-no-display");
    let (status, output) = hroc(&dir.0, &["view", "radial-city", "--objects", "200", "--frames", "1"], None, Duration::from_secs(120));
    assert!(!status.success());
    assert!(output.contains("no display"), "{output}");
    assert!(!output.contains("panicked"), "{output}");
}
