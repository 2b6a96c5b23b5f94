//! The kernels at the ends of the f64 range against the exact rational
//! reference: uniform scales from 2^-1060 to 2^1000 and size ratios, with
//! what `within_range` says. A measuring aid for issue 13 §2.
use nearmiss::exact;
use nearmiss::kernels::triangle_distance;
use nearmiss::math::Point;

fn main() {
    let unit = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
    let above = unit.map(|p| p + nearmiss::math::Vector::new(0.1, 0.1, 1.0));
    println!("uniform scale: two parallel unit triangles 1 apart, scaled by 2^k");
    for k in [-1060, -1040, -1000, -600, -300, -150, 0, 150, 300, 600, 900, 1000, 1020] {
        let s = 2f64.powi(k / 2) * 2f64.powi(k - k / 2);
        let (a, b) = (unit.map(|p| p * s), above.map(|p| p * s));
        let d = triangle_distance(&a, &b);
        let exact = exact::triangle_distance_f64(&a, &b);
        println!(
            "  2^{k:5}: {:e} vs exact {:e}, rel err {:.1e}, within_range {}",
            d.distance,
            exact,
            ((d.distance - exact) / exact).abs(),
            d.within_range
        );
    }
    println!("ratio: a unit triangle 1 above a triangle of size 2^k (and size 2^k triangles 1 apart)");
    for k in [50, 100, 150, 190, 200, 210, 250, 300, 500, 1000] {
        let s = 2f64.powi(k);
        let big = [Point::new(-s, -s, 0.0), Point::new(s, -s, 0.0), Point::new(0.0, s, 0.0)];
        let d = triangle_distance(&big, &above);
        let exact = exact::triangle_distance_f64(&big, &above);
        let far = big.map(|p| p + nearmiss::math::Vector::new(0.0, 0.0, 1.0));
        let d2 = triangle_distance(&big, &far);
        let exact2 = exact::triangle_distance_f64(&big, &far);
        println!(
            "  2^{k:5}: {:e} vs {:e} (within {}) | parallel: {:e} vs {:e} (within {})",
            d.distance, exact, d.within_range, d2.distance, exact2, d2.within_range
        );
    }
}
