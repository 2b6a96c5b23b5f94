//! The batched kernels give bit-identical results to the scalar ones, at
//! every instruction-set level this CPU supports, on every input class.

use nearmiss::kernels::batch::{
    point_segment_distances_with, triangle_distances_with, PointsSoa, TrianglesSoa,
};
use nearmiss::kernels::{point_segment_distance_with, triangle_distance_with, PointEdgeFormula, SimdLevel};
use nearmiss::samples::{point_segment_queries, triangle_pairs, InputClass};

#[test]
fn triangle_batches_are_bit_identical() {
    for class in InputClass::ALL {
        let pairs = triangle_pairs(class, 500, 13);
        let (a, b) = TrianglesSoa::from_pairs(&pairs);
        let reference: Vec<f64> =
            pairs.iter().map(|(x, y)| triangle_distance_with(SimdLevel::Baseline, x, y).distance).collect();
        for level in SimdLevel::available() {
            let mut out = vec![f64::NAN; pairs.len()];
            triangle_distances_with(level, &a, &b, &mut out);
            for (i, (x, y)) in pairs.iter().enumerate() {
                let scalar = triangle_distance_with(level, x, y).distance;
                assert_eq!(scalar.to_bits(), reference[i].to_bits(), "{class:?} {level:?} scalar, pair {i}");
                assert_eq!(out[i].to_bits(), reference[i].to_bits(), "{class:?} {level:?} batch, pair {i}");
            }
        }
    }
}

#[test]
fn point_segment_batches_are_bit_identical() {
    for class in InputClass::ALL {
        let queries = point_segment_queries(class, 1000, 17);
        let (p, a, b) = PointsSoa::from_queries(&queries);
        for formula in PointEdgeFormula::ALL {
            for level in SimdLevel::available() {
                let mut out = vec![f64::NAN; queries.len()];
                point_segment_distances_with(level, &p, &a, &b, formula, &mut out);
                for (i, (qp, qa, qb)) in queries.iter().enumerate() {
                    let reference = point_segment_distance_with(SimdLevel::Baseline, qp, qa, qb, formula);
                    assert_eq!(
                        out[i].to_bits(),
                        reference.to_bits(),
                        "{class:?} {formula:?} {level:?} query {i}"
                    );
                }
            }
        }
    }
}

#[test]
fn short_outputs_and_empty_batches_are_fine() {
    let pairs = triangle_pairs(InputClass::WellConditioned, 3, 1);
    let (a, b) = TrianglesSoa::from_pairs(&pairs);
    let mut out = [0.0; 2];
    triangle_distances_with(SimdLevel::detect(), &a, &b, &mut out);
    assert!(out.iter().all(|d| *d > 0.0));
    triangle_distances_with(SimdLevel::detect(), &TrianglesSoa::default(), &b, &mut out);
}
