//! Volume, centre of mass and inertia of a closed triangle surface, by the
//! divergence theorem: the solid is the signed sum of the tetrahedra that
//! join the origin to each triangle (Tonon 2004, "Explicit exact formulas for
//! the 3-D tetrahedron inertia tensor in terms of its vertex coordinates").

use nalgebra::Matrix3;

use crate::math::{Point, Real};

/// The mass properties of a closed mesh at unit density.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// The enclosed volume (positive for outward-facing triangles).
    pub volume: Real,
    /// The centre of mass, in the mesh's frame.
    pub center_of_mass: Point,
    /// The inertia tensor about the centre of mass, axes of the mesh's
    /// frame, at unit density (multiply by the density).
    pub inertia: Matrix3<Real>,
}

impl MassProperties {
    /// The mass properties of the solid bounded by the triangles, or `None`
    /// when the signed volume is not positive (an open or inward-facing
    /// surface).
    pub fn of_surface(vertices: &[Point], triangles: &[[u32; 3]]) -> Option<MassProperties> {
        let mut volume6 = 0.0; // six times the volume
        let mut first = nalgebra::Vector3::zeros(); // 24 × first moment
        let mut second = Matrix3::zeros(); // 120 × second moment ∫ x xᵀ
        for t in triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize].coords);
            let det = a.dot(&b.cross(&c));
            let sum = a + b + c;
            volume6 += det;
            first += det * sum;
            // ∫ x xᵀ over the tetrahedron (0, a, b, c) is
            // det/120 (a aᵀ + b bᵀ + c cᵀ + s sᵀ) with s = a + b + c.
            second +=
                det * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
        }
        let volume = volume6 / 6.0;
        if volume.is_nan() || volume <= 0.0 {
            return None;
        }
        let center = first / (24.0 * volume);
        let covariance = second / 120.0 - volume * center * center.transpose();
        let inertia = Matrix3::identity() * covariance.trace() - covariance;
        Some(MassProperties { volume, center_of_mass: Point::from(center), inertia })
    }
}

#[cfg(test)]
mod tests {
    use super::super::primitives::box_mesh;
    use crate::math::Vector;
    use approx::assert_relative_eq;

    #[test]
    fn box_inertia_matches_the_formula() {
        // A box with half extents (a, b, c): I_xx = m (b² + c²) / 3.
        let (a, b, c) = (1.0, 2.0, 3.0);
        let mesh = box_mesh(&Vector::new(a, b, c)).unwrap();
        let shifted = mesh.recentered(&crate::math::Point::new(-5.0, 1.0, 2.0));
        let props = shifted.mass_properties().unwrap();
        let m = 8.0 * a * b * c;
        assert_relative_eq!(props.volume, m, max_relative = 1e-14);
        assert_relative_eq!(props.center_of_mass.coords, Vector::new(5.0, -1.0, -2.0), epsilon = 1e-13);
        let expected = nalgebra::Matrix3::from_diagonal(&Vector::new(
            m * (b * b + c * c) / 3.0,
            m * (a * a + c * c) / 3.0,
            m * (a * a + b * b) / 3.0,
        ));
        assert_relative_eq!(props.inertia, expected, epsilon = 1e-11);
    }
}
