//! The defaults stated in the docs are the ones in the code.

use nearmiss::kernels::{PointEdgeFormula, REFINE_BELOW_EXTENT, REFINE_TIE_BAND_ULPS};

#[test]
fn documented_defaults_are_the_real_ones() {
    // kernels::point_segment: "Vector ... (default)".
    assert_eq!(PointEdgeFormula::default(), PointEdgeFormula::Vector);
    // kernels::refine: "Default `1e-3`" and "Default `16`".
    assert_eq!(REFINE_BELOW_EXTENT, 1e-3);
    assert_eq!(REFINE_TIE_BAND_ULPS, 16.0);
}
