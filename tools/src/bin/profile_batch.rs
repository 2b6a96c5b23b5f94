//! Runs the batched triangle kernel in a loop, for profilers.
use nearmiss::kernels::batch::{triangle_distances, TrianglesSoa};
use nearmiss::samples::nearly_touching_pairs;
fn main() {
    let pairs = nearly_touching_pairs(10_000, 1e-3, 1e-1, 2024);
    let a = TrianglesSoa::from_triangles(&pairs.iter().map(|p| p.0).collect::<Vec<_>>());
    let b = TrianglesSoa::from_triangles(&pairs.iter().map(|p| p.1).collect::<Vec<_>>());
    let mut out = vec![0.0; pairs.len()];
    let mut sum = 0.0;
    let repeats: usize = std::env::var("REPEATS").ok().and_then(|r| r.parse().ok()).unwrap_or(300);
    for _ in 0..repeats {
        triangle_distances(&a, &b, &mut out);
        sum += out.iter().sum::<f64>();
    }
    println!("{sum}");
}
