//! The seed paper's DyOP kernel: exact on its own setting, an upper bound
//! everywhere, and an over-estimate outside its setting.

use crate::bounds::formula_bound;
use nearmiss::exact;
use nearmiss::kernels::{dyop_distance, PointEdgeFormula};
use nearmiss::math::Point;
use nearmiss::samples::pair_extent;
use nearmiss::samples::{triangle_pairs, InputClass, Rng};

#[test]
fn exact_on_the_seeds_vertex_edge_setting() {
    // A's edge on the y axis, its third vertex far behind (x = -3); a vertex
    // of B at (gap, y0, 0), B's other vertices far ahead (x = gap + 3). A
    // lies in x ≤ 0 and B in x ≥ gap, and B's vertex is `gap` from the edge
    // point (0, y0, 0): the distance is `gap`, analytically. The DyOP keeps
    // A's edge and B's near vertex (the far vertices are over 3 away, the
    // near ones under 2.3), so its vertex–edge distance is that gap.
    let mut rng = Rng::new(42);
    for _ in 0..500 {
        let gap = rng.log_range(1e-9, 1e-1);
        let y0 = rng.range(-0.8, 0.8);
        let a = [
            Point::new(0.0, -1.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            Point::new(-3.0, rng.range(-1.0, 1.0), 0.5),
        ];
        let b = [
            Point::new(gap, y0, 0.0),
            Point::new(gap + 3.0, rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            Point::new(gap + 3.0, rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
        ];
        assert_eq!(exact::triangle_distance_squared(&a, &b), exact::rational(gap) * exact::rational(gap));
        for formula in PointEdgeFormula::ALL {
            let d = dyop_distance(&a, &b, formula);
            let bound = formula_bound(formula, gap, pair_extent(&a, &b));
            assert!((d - gap).abs() <= bound, "{formula:?}: {d:e} for gap {gap:e}");
        }
    }
}

#[test]
fn over_estimates_a_vertex_over_a_face() {
    // B's vertex hovers h above the interior of A; exactly h apart. DyOP
    // sees only A's vertices and edges, all at least 0.25 from that vertex.
    let a = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0), Point::new(0.0, 1.0, 0.0)];
    let h = 1e-3;
    let b = [Point::new(0.25, 0.25, h), Point::new(0.3, 0.2, 2.0), Point::new(0.2, 0.3, 2.0)];
    assert_eq!(exact::triangle_distance_squared(&a, &b), exact::rational(h) * exact::rational(h));
    for formula in PointEdgeFormula::ALL {
        assert!(dyop_distance(&a, &b, formula) >= 0.25, "{formula:?}");
    }
}

#[test]
fn never_under_estimates_beyond_the_formula_error() {
    // Every DyOP candidate is a distance between a point of each triangle,
    // so the kernel is an upper bound up to its formula's rounding.
    for class in InputClass::ALL {
        for (i, (a, b)) in triangle_pairs(class, 300, 9).iter().enumerate() {
            let expected = exact::triangle_distance_f64(a, b);
            for formula in PointEdgeFormula::ALL {
                let d = dyop_distance(a, b, formula);
                let bound = formula_bound(formula, expected, pair_extent(a, b));
                assert!(d >= expected - bound, "{class:?} pair {i} {formula:?}: {d:e} < exact {expected:e}");
            }
        }
    }
}
