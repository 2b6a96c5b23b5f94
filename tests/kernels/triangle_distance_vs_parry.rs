//! `triangle_distance` against parry3d-f64's `query::distance` (GJK) on
//! 10,000 random nearly touching unit-size pairs, gaps 1e-12..1e-1.
//!
//! They must agree within 1e-12, or else the exact rational reference must
//! show that nearmiss is right (within its bound) and parry is the one off.

use nearmiss::exact;
use nearmiss::kernels::triangle_distance;
use nearmiss::samples::nearly_touching_pairs;
use nearmiss::samples::{pair_extent, parry_triangle_distance};

#[test]
fn agrees_with_parry_or_parry_is_wrong() {
    let pairs = nearly_touching_pairs(10_000, 1e-12, 1e-1, 99);
    let (mut disagreements, mut parry_wrong, mut parry_worst) = (0, 0, 0.0f64);
    for (i, (a, b)) in pairs.iter().enumerate() {
        let ours = triangle_distance(a, b).distance;
        let theirs = parry_triangle_distance(a, b);
        if (ours - theirs).abs() <= 1e-12 {
            continue;
        }
        disagreements += 1;
        let expected = exact::triangle_distance_f64(a, b);
        let our_error = (ours - expected).abs();
        let their_error = (theirs - expected).abs();
        assert!(
            our_error <= 1e-12 * expected + 4.0 * f64::EPSILON * f64::EPSILON * pair_extent(a, b),
            "pair {i}: nearmiss {ours:e}, parry {theirs:e}, exact {expected:e}"
        );
        if their_error > 1e-12 {
            parry_wrong += 1;
        }
        parry_worst = parry_worst.max(their_error);
    }
    println!("{disagreements} of {} pairs differ by more than 1e-12; parry off by > 1e-12 in {parry_wrong} (worst {parry_worst:e})", pairs.len());
    assert_eq!(disagreements, parry_wrong, "every disagreement is parry's error");
}

#[test]
fn agrees_with_parry_at_benchmark_gaps() {
    // The benchmark's inputs (gaps 1e-3..1e-1): same rule.
    let pairs = nearly_touching_pairs(10_000, 1e-3, 1e-1, 2024);
    for (i, (a, b)) in pairs.iter().enumerate() {
        let ours = triangle_distance(a, b).distance;
        let theirs = parry_triangle_distance(a, b);
        if (ours - theirs).abs() > 1e-12 {
            let expected = exact::triangle_distance_f64(a, b);
            assert!(
                (ours - expected).abs() <= 1e-12 * expected,
                "pair {i}: nearmiss {ours:e}, exact {expected:e}"
            );
            assert!((theirs - expected).abs() > 1e-12, "pair {i}");
        }
    }
}
