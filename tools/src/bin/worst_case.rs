//! Prints the pair with the worst relative error of `triangle_distance` in a class (debugging aid).
use nearmiss::exact;
use nearmiss::kernels::triangle_distance;
use nearmiss::samples::{triangle_pairs, InputClass};
fn main() {
    let class = match std::env::args().nth(1).as_deref() {
        Some("coplanar") => InputClass::Coplanar,
        Some("degenerate") => InputClass::Degenerate,
        _ => InputClass::ParallelEdges,
    };
    let mut worst = (0.0, 0);
    let pairs = triangle_pairs(class, 1000, 1);
    for (i, (a, b)) in pairs.iter().enumerate() {
        let e = exact::triangle_distance_f64(a, b);
        let d = triangle_distance(a, b).distance;
        let r = if e > 0.0 { (d - e).abs() / e } else { d };
        if r > worst.0 {
            worst = (r, i);
        }
    }
    let (a, b) = &pairs[worst.1];
    println!(
        "rel {:e}\n{:?}\nexact {:e}\n{:?}\n{:?}",
        worst.0,
        triangle_distance(a, b),
        exact::triangle_distance_f64(a, b),
        a,
        b
    );
}
