//! Exact reference of what two triangles share and how deep they are, on
//! the exact values of the f64 inputs.
//!
//! The shared set is found by a method independent of the kernel's: `a`'s
//! vertices, as a polygon, clipped in exact arithmetic by the half-spaces
//! whose intersection is `b` (its plane from both sides, then the three
//! half-spaces through its edges along its normal), so no line, interval or
//! projection is involved. The depth is the least reach of the Minkowski
//! difference over its candidate facet normals (the kernel's definition,
//! in exact arithmetic): squared, it is rational.

use super::triangle_triangle::triangle_distance_squared;
use super::vector::{Rational, RationalVector};
use crate::math::Triangle;
use num_traits::{Signed, Zero};

/// The polygon (vertices in order, possibly repeated) that triangles `a`
/// and `b` share, exactly; empty when they do not meet. `None` when `b` is
/// degenerate (collinear vertices): clip by the other triangle then.
pub fn triangle_intersection_polygon(a: &Triangle, b: &Triangle) -> Option<Vec<RationalVector>> {
    let a = a.map(|v| RationalVector::from_point(&v));
    let b = b.map(|v| RationalVector::from_point(&v));
    let normal = b[1].sub(&b[0]).cross(&b[2].sub(&b[0]));
    if normal.is_zero() {
        return None;
    }
    let mut polygon = a.to_vec();
    // The plane, from both sides.
    for n in [normal.clone(), normal.negated()] {
        polygon = clip(&polygon, |x| n.dot(&x.sub(&b[0])));
    }
    // The edges: normal × edge points into the triangle.
    for i in 0..3 {
        let inward = normal.cross(&b[(i + 1) % 3].sub(&b[i]));
        polygon = clip(&polygon, |x| inward.dot(&x.sub(&b[i])));
    }
    Some(polygon)
}

/// The squared penetration depth of `a` and `b`, exactly; `None` when they
/// do not meet.
pub fn triangle_penetration_depth_squared(a: &Triangle, b: &Triangle) -> Option<Rational> {
    if !triangle_distance_squared(a, b).is_zero() {
        return None;
    }
    let a = a.map(|v| RationalVector::from_point(&v));
    let b = b.map(|v| RationalVector::from_point(&v));
    let edges = |t: &[RationalVector; 3]| [0, 1, 2].map(|i| t[(i + 1) % 3].sub(&t[i]));
    let (edges_a, edges_b) = (edges(&a), edges(&b));
    let mut candidates = vec![edges_a[0].cross(&edges_a[1]), edges_b[0].cross(&edges_b[1])];
    for ea in &edges_a {
        for eb in &edges_b {
            candidates.push(ea.cross(eb));
        }
    }
    let mut best: Option<Rational> = None;
    for c in candidates.iter().filter(|c| !c.is_zero()) {
        let project = |t: &[RationalVector; 3]| t.iter().map(|p| p.dot(c)).collect::<Vec<_>>();
        let (pa, pb) = (project(&a), project(&b));
        let max = |v: &[Rational]| v.iter().max().cloned().unwrap_or_else(Rational::zero);
        let min = |v: &[Rational]| v.iter().min().cloned().unwrap_or_else(Rational::zero);
        for reach in [max(&pa) - min(&pb), max(&pb) - min(&pa)] {
            let reach = if reach.is_negative() { Rational::zero() } else { reach };
            let squared = &reach * &reach / c.norm_squared();
            if best.as_ref().is_none_or(|b| squared < *b) {
                best = Some(squared);
            }
        }
    }
    Some(best.unwrap_or_else(Rational::zero))
}

/// The part of `polygon` where `side` is not negative (Sutherland–Hodgman).
fn clip(polygon: &[RationalVector], side: impl Fn(&RationalVector) -> Rational) -> Vec<RationalVector> {
    let mut out = Vec::new();
    for (i, p) in polygon.iter().enumerate() {
        let q = &polygon[(i + 1) % polygon.len()];
        let (sp, sq) = (side(p), side(q));
        if !sp.is_negative() {
            out.push(p.clone());
        }
        if (&sp * &sq).is_negative() {
            let k = &sp / (&sp - &sq);
            out.push(p.add_scaled(&q.sub(p), &k));
        }
    }
    out
}
