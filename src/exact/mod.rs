//! Exact rational reference distances, on the exact values of the f64
//! inputs (every finite f64 is a rational number). Squared distances are
//! rational, so they are computed with no rounding at all.
//!
//! This is the oracle of the tests and reports. It is slow (big-integer
//! arithmetic, milliseconds per triangle pair) and stays out of hot paths.

mod point_segment;
mod triangle_overlap;
mod triangle_triangle;
mod vector;

pub use point_segment::point_segment_distance_squared;
pub use triangle_overlap::{triangle_intersection_polygon, triangle_penetration_depth_squared};
pub use triangle_triangle::{
    point_triangle_distance_squared, rational_triangle_distance_squared, segment_segment_distance_squared,
    triangle_distance_f64, triangle_distance_squared,
};
pub use vector::{rational, to_f64, Rational, RationalVector};
