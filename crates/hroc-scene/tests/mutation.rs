//! Bounded mutation test of the loaders (the CI-sized sibling of the
//! cargo-fuzz targets in `fuzz/`): 10,000 mutated variants of real glTF,
//! GLB, OBJ and camera-path files. Every variant must load or fail with a
//! one-line error: no panic, no hang (each variant well under a second), and
//! no live heap above [`HEAP_CAP`] while it loads.

use hroc_scene::rng::Rng;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The most heap a loader may hold for one of these small files. A mutated
/// count or length must be refused before it is allocated.
const HEAP_CAP: usize = 256 << 20;
/// Variants in CI; `HROC_MUTATION_VARIANTS` runs more (a deeper local search).
const VARIANTS: usize = 10_000;

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        if !q.is_null() {
            if new >= l.size() {
                let now = LIVE.fetch_add(new - l.size(), Ordering::Relaxed) + new - l.size();
                PEAK.fetch_max(now, Ordering::Relaxed);
            } else {
                LIVE.fetch_sub(l.size() - new, Ordering::Relaxed);
            }
        }
        q
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[derive(Clone, Copy, Debug)]
enum Kind {
    Gltf,
    Obj,
    Path,
}

/// Values that break parsers: signs, huge counts, quotes, separators.
const TOKENS: [&[u8]; 12] = [b"-1", b"4294967295", b"1e38", b"NaN", b"\"", b"{", b"]", b"0", b"999999999999", b"\n", b"/", b"."];

fn mutate(src: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut v = src.to_vec();
    for _ in 0..1 + rng.below(2) {
        let at = rng.below(v.len() + 1);
        match rng.below(7) {
            0 if !v.is_empty() => {
                let i = at.min(v.len() - 1);
                v[i] ^= 1 << rng.below(8);
            }
            1 if !v.is_empty() => {
                let i = at.min(v.len() - 1);
                v[i] = rng.next_u64() as u8;
            }
            2 => v.truncate(at),
            3 => {
                let end = (at + 1 + rng.below(64)).min(v.len());
                v.drain(at.min(end)..end);
            }
            4 => {
                let len = 1 + rng.below(64);
                let from = rng.below(v.len().saturating_sub(len) + 1);
                let chunk: Vec<u8> = v[from..(from + len).min(v.len())].to_vec();
                v.splice(at..at, chunk);
            }
            5 => {
                // Replace a run of digits (a count, a length, an index).
                let digits: Vec<usize> = (0..v.len()).filter(|&i| v[i].is_ascii_digit()).collect();
                if !digits.is_empty() {
                    let i = digits[rng.below(digits.len())];
                    let end = (i..v.len()).find(|&j| !v[j].is_ascii_digit()).unwrap_or(v.len());
                    let t = TOKENS[rng.below(TOKENS.len())];
                    v.splice(i..end, t.iter().copied());
                }
            }
            _ => {
                let t = TOKENS[rng.below(TOKENS.len())];
                v.splice(at..at, t.iter().copied());
            }
        }
    }
    v
}

fn load(kind: Kind, bytes: &[u8], path: &Path) -> hroc_scene::Result<()> {
    match kind {
        Kind::Gltf => hroc_scene::gltf::load_bytes(bytes, path).map(|_| ()),
        Kind::Obj => hroc_scene::obj::load_bytes(bytes, path).map(|_| ()),
        Kind::Path => hroc_scene::CameraPath::from_json(&String::from_utf8_lossy(bytes), path).map(|_| ()),
    }
}

/// The seed files: the glTF samples, a GLB, an OBJ and a camera path
/// written out from a generated scene.
fn seeds(dir: &Path) -> Vec<(Kind, PathBuf, Vec<u8>)> {
    let samples = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf-samples");
    let mut out = Vec::new();
    let mut names: Vec<PathBuf> = std::fs::read_dir(&samples).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "gltf")).collect();
    names.sort();
    for p in names {
        let bytes = std::fs::read(&p).unwrap();
        out.push((Kind::Gltf, p, bytes));
    }
    let scene = hroc_scene::load("rooms", Some(8), 1).unwrap();
    for name in ["rooms.glb", "rooms.obj"] {
        let p = dir.join(name);
        hroc_scene::export::write(&scene, &p).unwrap();
        let kind = if name.ends_with("obj") { Kind::Obj } else { Kind::Gltf };
        out.push((kind, p.clone(), std::fs::read(&p).unwrap()));
    }
    let p = dir.join("path.json");
    hroc_scene::export::write_path(&scene.path, &p).unwrap();
    out.push((Kind::Path, p.clone(), std::fs::read(&p).unwrap()));
    out
}

#[test]
fn ten_thousand_mutated_files_fail_cleanly() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mutation");
    std::fs::create_dir_all(&dir).unwrap();
    let seeds = seeds(&dir);
    for (kind, path, bytes) in &seeds {
        load(*kind, bytes, path).unwrap_or_else(|e| panic!("seed {} does not load: {e}", path.display()));
    }
    let variants = std::env::var("HROC_MUTATION_VARIANTS").ok().and_then(|v| v.parse().ok()).unwrap_or(VARIANTS);
    let start = std::time::Instant::now();
    let (mut ok, mut refused, mut slowest) = (0, 0, (0.0f64, 0usize));
    for k in 0..variants {
        // Seeded per variant, so a failing one can be replayed.
        let mut rng = Rng::new(k as u64);
        let (kind, path, src) = &seeds[rng.below(seeds.len())];
        let bytes = mutate(src, &mut rng);
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let t = std::time::Instant::now();
        let r = std::panic::catch_unwind(|| load(*kind, &bytes, path));
        let secs = t.elapsed().as_secs_f64();
        let heap = PEAK.load(Ordering::Relaxed).saturating_sub(base);
        let what = format!("variant {k} of {} ({kind:?})", path.display());
        match r {
            Err(_) => panic!("{what}: the loader panicked"),
            Ok(Ok(())) => ok += 1,
            Ok(Err(e)) => {
                let m = e.to_string();
                assert!(!m.is_empty() && !m.contains('\n'), "{what}: unclear error {m:?}");
                refused += 1;
            }
        }
        assert!(heap <= HEAP_CAP, "{what}: {heap} bytes of heap while loading (cap {HEAP_CAP})");
        // A hang, not a speed measurement: these files load in microseconds.
        assert!(secs < 5.0, "{what}: {secs:.1} s to load");
        if secs > slowest.0 {
            slowest = (secs, k);
        }
    }
    println!("{variants} variants in {:.1} s: {ok} loaded, {refused} refused; slowest variant {} ({:.3} s)", start.elapsed().as_secs_f64(), slowest.1, slowest.0);
    assert!(ok > 0 && refused > 0, "the mutations are too weak or too strong: {ok} loaded, {refused} refused");
}
