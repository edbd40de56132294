//! Builds the object BVH over random boxes with every split and prints build
//! time and SAH cost (sum over nodes of area / root area), the
//! numbers compared against obvhs's presets.
//!
//! `cargo run --release --example bvh_build -- [--objects 120000] [--runs 9]`

use clap::Parser;
use glam::Vec3;
use hroc_bench::bvh::{Bvh, Split};
use hroc_bench::scene::Aabb;

#[derive(Parser)]
struct Args {
    /// Number of boxes.
    #[arg(long, default_value_t = 120_000)]
    objects: usize,
    /// Timed builds per split (after one warm-up); the median is reported.
    #[arg(long, default_value_t = 9)]
    runs: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Box distribution.
    #[arg(long, value_enum, default_value_t = Dist::Uniform)]
    dist: Dist,
    /// Only this split (default: all).
    #[arg(long)]
    split: Option<Split>,
}

/// SplitMix64: deterministic, dependency-free.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vec(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next())
    }
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Dist {
    /// Centres uniform in a 100³ cube, sides uniform in [0.1, 2].
    Uniform,
    /// The same boxes gathered around 64 random cluster centres.
    Clustered,
    /// Uniform centres, sizes log-uniform over two decades (0.05–5), like
    /// the `satellites` scene's mix of small and large objects.
    Varied,
}

pub fn random_boxes(n: usize, seed: u64, dist: Dist) -> Vec<Aabb> {
    let mut rng = Rng(seed);
    let clusters: Vec<Vec3> = (0..64).map(|_| rng.vec() * 100.0).collect();
    (0..n)
        .map(|i| {
            let c = match dist {
                Dist::Clustered => clusters[i % clusters.len()] + (rng.vec() - 0.5) * 8.0,
                _ => rng.vec() * 100.0,
            };
            let h = match dist {
                Dist::Varied => Vec3::splat(0.05 * 100f32.powf(rng.next())) * (Vec3::splat(0.5) + rng.vec()) * 0.5,
                _ => (Vec3::splat(0.1) + rng.vec() * 1.9) * 0.5,
            };
            Aabb::new(c - h, c + h)
        })
        .collect()
}

fn main() {
    let args = Args::parse();
    let boxes = random_boxes(args.objects, args.seed, args.dist);
    println!("{} {:?} boxes, {} threads, median of {} builds", args.objects, args.dist, rayon::current_num_threads(), args.runs);
    println!("{:<5} {:>10} {:>10} {:>10} {:>6} {:>9}", "split", "median ms", "min ms", "SAH cost", "depth", "nodes");
    for split in args.split.map_or(Split::ALL.to_vec(), |s| vec![s]) {
        let bvh = Bvh::build(&boxes, split); // warm-up (thread pool, page faults)
        bvh.validate(&boxes).expect("invalid BVH");
        let mut ms: Vec<f64> = (0..args.runs.max(1)).map(|_| Bvh::build(&boxes, split).build_ms).collect();
        ms.sort_by(f64::total_cmp);
        println!("{:<5} {:>10.2} {:>10.2} {:>10.1} {:>6} {:>9}", split, ms[ms.len() / 2], ms[0], bvh.sah_cost(), bvh.depth(), bvh.nodes.len());
    }
}
