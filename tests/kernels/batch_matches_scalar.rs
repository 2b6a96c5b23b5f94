//! The batched kernels give bit-identical results to the scalar ones, and
//! the single-pair kernel the same result (distance, points, features) at
//! every instruction-set level this CPU supports, on every input class.

use nearmiss::kernels::batch::{
    point_segment_distances_with, triangle_distances_with, PointsSoa, TrianglesSoa,
};
use nearmiss::kernels::{
    point_segment_distance_with, triangle_distance_with, PointEdgeFormula, SimdLevel, TriangleDistance,
};
use nearmiss::math::Point;
use nearmiss::samples::{
    nearly_touching_pairs, point_segment_queries, tied_pairs, triangle_pairs, InputClass, Rng,
};

#[test]
fn triangle_batches_are_bit_identical() {
    // Each class, and pairs 1e-12..1e-3 apart: refined, nine in ten through
    // the tie path, which the batch reads from its pass's kept candidates
    // and the baseline single pair recomputes.
    let sets = InputClass::ALL
        .into_iter()
        .map(|class| (format!("{class:?}"), triangle_pairs(class, 500, 13)))
        .chain([("refined".to_string(), nearly_touching_pairs(2000, 1e-12, 1e-3, 2026))]);
    for (class, pairs) in sets {
        let (a, b) = TrianglesSoa::from_pairs(&pairs);
        let reference: Vec<f64> =
            pairs.iter().map(|(x, y)| triangle_distance_with(SimdLevel::Baseline, x, y).distance).collect();
        for level in SimdLevel::available() {
            let mut out = vec![f64::NAN; pairs.len()];
            triangle_distances_with(level, &a, &b, &mut out);
            for (i, (x, y)) in pairs.iter().enumerate() {
                let scalar = triangle_distance_with(level, x, y).distance;
                assert_eq!(scalar.to_bits(), reference[i].to_bits(), "{class} {level:?} scalar, pair {i}");
                assert_eq!(out[i].to_bits(), reference[i].to_bits(), "{class} {level:?} batch, pair {i}");
            }
        }
    }
}

/// Every field of a triangle distance, as bits.
fn bits(d: &TriangleDistance) -> (u64, [u64; 6], String, bool) {
    let (p, q) = (d.point_a, d.point_b);
    let points = [p.x, p.y, p.z, q.x, q.y, q.z].map(f64::to_bits);
    (d.distance.to_bits(), points, format!("{:?} {:?}", d.feature_a, d.feature_b), d.within_range)
}

#[test]
fn every_level_gives_the_same_points_and_features() {
    let mut pairs = tied_pairs();
    for class in InputClass::ALL {
        pairs.extend(triangle_pairs(class, 2000, 29));
    }
    pairs.extend(nearly_touching_pairs(2000, 1e-3, 1e-1, 2024));
    // Refined, most through the tie path (which the single pair from AVX2
    // on reads from its pass's table, the baseline recomputes).
    pairs.extend(nearly_touching_pairs(2000, 1e-12, 1e-3, 2025));
    for (i, (x, y)) in pairs.iter().enumerate() {
        let reference = bits(&triangle_distance_with(SimdLevel::Baseline, x, y));
        for level in SimdLevel::available() {
            assert_eq!(
                bits(&triangle_distance_with(level, x, y)),
                reference,
                "{level:?}, pair {i}: {x:?} {y:?}"
            );
            // Swapped, the same pair seen from the other side.
            let swapped = bits(&triangle_distance_with(level, y, x));
            assert_eq!(
                swapped,
                bits(&triangle_distance_with(SimdLevel::Baseline, y, x)),
                "{level:?}, pair {i} swapped"
            );
        }
    }
}

/// A coordinate drawn from extremes: zeros of both signs, subnormals,
/// tiny, unit, huge and near-overflow magnitudes; with `non_finite`, also
/// NaN and infinities.
fn extreme(rng: &mut Rng, non_finite: bool) -> f64 {
    const FINITE: [f64; 10] = [0.0, -0.0, 5e-324, -1e-310, 1e-300, 1.0, -0.75, 3e150, -1e300, f64::MAX];
    const OTHERS: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    let k = rng.index(if non_finite { FINITE.len() + OTHERS.len() } else { FINITE.len() });
    let base = if k < FINITE.len() { FINITE[k] } else { OTHERS[k - FINITE.len()] };
    // Mostly the value shrunk a little (never past the finite range),
    // sometimes exactly it (ties, repeats).
    if rng.index(3) == 0 {
        base
    } else {
        base * rng.range(0.25, 1.0)
    }
}

#[test]
fn every_level_agrees_on_extreme_and_non_finite_input() {
    let mut rng = Rng::new(77);
    let triangle = |rng: &mut Rng, non_finite: bool| {
        [0, 1, 2]
            .map(|_| Point::new(extreme(rng, non_finite), extreme(rng, non_finite), extreme(rng, non_finite)))
    };
    for i in 0..20_000 {
        let non_finite = i % 2 == 1;
        let (a, b) = (triangle(&mut rng, non_finite), triangle(&mut rng, non_finite));
        let reference = triangle_distance_with(SimdLevel::Baseline, &a, &b);
        for level in SimdLevel::available() {
            let found = triangle_distance_with(level, &a, &b);
            assert_eq!(bits(&found), bits(&reference), "{level:?}, pair {i}: {a:?} {b:?}");
            if !non_finite {
                assert!(found.distance >= 0.0, "{level:?}, pair {i}: {found:?}");
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
