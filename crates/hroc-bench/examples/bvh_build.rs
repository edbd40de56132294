//! Builds the object BVH over random boxes with every split and prints build
//! time and SAH cost (sum over nodes of area / root area), the
//! numbers compared against obvhs's presets.
//!
//! `cargo run --release --example bvh_build -- [--objects 120000] [--runs 9]`

use clap::Parser;
use hroc_bench::bvh::{Bvh, Split};

#[path = "shared/random_boxes.rs"]
mod random_boxes;
use random_boxes::{random_boxes, Dist};

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
