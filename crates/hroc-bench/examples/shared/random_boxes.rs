//! Random boxes for the BVH benchmarks (`bvh_build`, and the guard's
//! 4M-object build).

use glam::Vec3;
use hroc_bench::scene::rng::Rng;
use hroc_bench::scene::Aabb;

/// A point in the unit cube.
fn vec(rng: &mut Rng) -> Vec3 {
    Vec3::new(rng.f32(), rng.f32(), rng.f32())
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

/// `n` boxes drawn from `seed`: the same boxes for the same arguments.
pub fn random_boxes(n: usize, seed: u64, dist: Dist) -> Vec<Aabb> {
    let mut rng = Rng::new(seed);
    let clusters: Vec<Vec3> = (0..64).map(|_| vec(&mut rng) * 100.0).collect();
    (0..n)
        .map(|i| {
            let c = match dist {
                Dist::Clustered => clusters[i % clusters.len()] + (vec(&mut rng) - 0.5) * 8.0,
                _ => vec(&mut rng) * 100.0,
            };
            let h = match dist {
                Dist::Varied => Vec3::splat(0.05 * 100f32.powf(rng.f32())) * (Vec3::splat(0.5) + vec(&mut rng)) * 0.5,
                _ => (Vec3::splat(0.1) + vec(&mut rng) * 1.9) * 0.5,
            };
            Aabb::new(c - h, c + h)
        })
        .collect()
}
