//! Which bodies move exactly and which are integrated.
//!
//! A body that is neither fixed nor kinematic moves exactly (constant
//! velocities, [`StepMotion::free`](super::StepMotion::free)) when nothing
//! acts on it: no gravity, no spring, no contact response that pushes it,
//! and a spin that does not precess. Otherwise it is integrated.

use nalgebra::Matrix3;

use crate::math::{Real, Vector};

/// A torque-free spin is taken as steady (no precession) when `|L × ω|` is
/// at most this many ulps of `|L| |ω|` (`L = I ω`, body frame): a spin
/// about a principal axis, to rounding. `64`.
pub(crate) const STEADY_SPIN_ULPS: Real = 64.0;

/// What acts on a body that is neither fixed nor kinematic.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Influences {
    /// Gravity is not zero.
    pub gravity: bool,
    /// At least one spring holds it.
    pub springs: bool,
    /// The contact response pushes it (its spin then changes at every
    /// contact, so it is integrated and precesses).
    pub pushed_by_contacts: bool,
}

/// Whether the torque-free spin `omega_body` (body frame) of a body with
/// inertia `inertia` precesses (see [`STEADY_SPIN_ULPS`]).
pub fn spin_precesses(inertia: &Matrix3<Real>, omega_body: &Vector) -> bool {
    let momentum = inertia * omega_body;
    momentum.cross(omega_body).norm() > STEADY_SPIN_ULPS * Real::EPSILON * momentum.norm() * omega_body.norm()
}

/// Whether every torque-free spin of a body with inertia `inertia` is
/// steady: the inertia is isotropic to rounding (a sphere's or a cube's,
/// computed from its triangles), `‖I − c 1‖ ≤ STEADY_SPIN_ULPS ε c` with
/// `c = tr I / 3` (Frobenius norm, which bounds `|L × ω| = |(I − c 1) ω ×
/// ω|` by the same ulps of `c |ω|²`). Such a body feels no gyroscopic
/// torque, so its integration needs no gyroscopic solve.
pub fn inertia_is_isotropic(inertia: &Matrix3<Real>) -> bool {
    let c = inertia.trace() / 3.0;
    let deviation = (inertia - Matrix3::from_diagonal_element(c)).norm_squared();
    let bound = STEADY_SPIN_ULPS * Real::EPSILON * c;
    c > 0.0 && deviation <= bound * bound
}

/// Whether a body under `influences`, whose spin precesses or not, must be
/// integrated (otherwise it moves exactly).
pub fn needs_integration(influences: Influences, precesses: bool) -> bool {
    influences.gravity || influences.springs || influences.pushed_by_contacts || precesses
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere's and a cube's inertia computed from their triangles are
    /// isotropic to rounding; a box's, or a sphere's off by 1e-12, are not.
    #[test]
    fn isotropic_inertia_is_recognised() {
        use crate::mesh::{box_mesh, icosphere, TriMesh};
        let inertia = |mesh: TriMesh| mesh.mass_properties().expect("closed").inertia;
        for subdivisions in 0..4 {
            assert!(inertia_is_isotropic(&inertia(icosphere(0.3, subdivisions).unwrap())));
        }
        assert!(inertia_is_isotropic(&inertia(box_mesh(&Vector::new(0.3, 0.3, 0.3)).unwrap())));
        assert!(!inertia_is_isotropic(&inertia(box_mesh(&Vector::new(0.3, 0.2, 0.25)).unwrap())));
        let mut off = Matrix3::from_diagonal_element(1.0);
        off[(0, 0)] += 1e-12;
        assert!(!inertia_is_isotropic(&off));
        assert!(!inertia_is_isotropic(&Matrix3::zeros()));
        assert!(!inertia_is_isotropic(&Matrix3::from_diagonal_element(Real::NAN)));
    }
}
