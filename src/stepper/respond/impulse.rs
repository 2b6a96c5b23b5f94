//! One impulse along the contact normal between two rigid bodies (the
//! impulse of `on_contact: Bounce`).
//!
//! With `n` the unit normal from `a` to `b`, `r` each contact point's
//! offset from its body's centre of mass and `u = (v_b + ω_b × r_b) −
//! (v_a + ω_a × r_a)` the relative velocity of the contact points, an
//! approaching contact (`u·n < 0`) gets the impulse `j n` on `b` and `−j n`
//! on `a` with
//!
//! ```text
//! j = −(1 + e) u·n / (1/m_a + 1/m_b + n·((I_a⁻¹ (r_a × n)) × r_a) + n·((I_b⁻¹ (r_b × n)) × r_b)),
//! ```
//!
//! `e` the coefficient of restitution, `I⁻¹` the inverse inertia in the
//! world. Linear and angular momentum are conserved, the normal approach
//! speed of the contact points is reversed and scaled by `e`, and kinetic
//! energy is conserved for `e = 1` (lost otherwise). A body that cannot be
//! pushed (fixed or kinematic) has `1/m = 0` and `I⁻¹ = 0`. A contact that
//! is already separating gets no impulse.

use nalgebra::Matrix3;

use crate::math::{Point, Real, Vector};

/// A body's side of a contact.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ImpactBody {
    /// The centre of mass at the contact.
    pub center: Point,
    /// `1 / mass` (0: cannot be pushed).
    pub inverse_mass: Real,
    /// The inverse inertia tensor in the world frame at the contact (zero:
    /// cannot be turned).
    pub inverse_inertia: Matrix3<Real>,
    /// The velocity of the centre of mass.
    pub velocity: Vector,
    /// The angular velocity (world frame).
    pub angular_velocity: Vector,
}

impl ImpactBody {
    /// The velocity of the body's point `p`.
    #[inline]
    fn point_velocity(&self, p: &Point) -> Vector {
        self.velocity + self.angular_velocity.cross(&(p - self.center))
    }

    /// Applies the impulse `impulse` at point `p`.
    #[inline]
    fn push(&mut self, p: &Point, impulse: &Vector) {
        self.velocity += impulse * self.inverse_mass;
        self.angular_velocity += self.inverse_inertia * (p - self.center).cross(impulse);
    }
}

/// The contact point (midpoint of the closest points) and the unit normal
/// from `a` to `b` (along the closest points, or between the centres when
/// they coincide).
pub fn contact_frame(point_a: &Point, point_b: &Point, a: &ImpactBody, b: &ImpactBody) -> (Point, Vector) {
    let between = point_b - point_a;
    let normal = if between.norm() > 0.0 { between.normalize() } else { (b.center - a.center).normalize() };
    (Point::from((point_a.coords + point_b.coords) / 2.0), normal)
}

/// The normal speed of `b`'s point relative to `a`'s at `point` (negative:
/// approaching).
pub fn approach_speed(a: &ImpactBody, b: &ImpactBody, point: &Point, normal: &Vector) -> Real {
    (b.point_velocity(point) - a.point_velocity(point)).dot(normal)
}

/// Applies the contact impulse (see the module) to `a` and `b` touching at
/// `point` (the midpoint of the two closest points) with unit normal `normal`
/// from `a` to `b`. Returns the impulse's magnitude `j` (0 if the contact
/// was separating or neither body can be pushed).
pub fn apply_impulse(
    a: &mut ImpactBody,
    b: &mut ImpactBody,
    point: &Point,
    normal: &Vector,
    restitution: Real,
) -> Real {
    let approach = approach_speed(a, b, point, normal);
    if approach >= 0.0 {
        return 0.0;
    }
    let angular = |body: &ImpactBody| {
        let r = point - body.center;
        normal.dot(&(body.inverse_inertia * r.cross(normal)).cross(&r))
    };
    let effective = a.inverse_mass + b.inverse_mass + angular(a) + angular(b);
    if effective <= 0.0 {
        return 0.0;
    }
    let j = -(1.0 + restitution) * approach / effective;
    a.push(point, &(-j * normal));
    b.push(point, &(j * normal));
    j
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::Rng;

    fn random_body(rng: &mut Rng, center: Vector) -> (ImpactBody, Matrix3<Real>) {
        // A random symmetric positive definite inertia and its inverse.
        let m = Matrix3::from_fn(|_, _| rng.uniform() - 0.5);
        let inertia = m * m.transpose() + Matrix3::identity() * 0.2;
        let body = ImpactBody {
            center: Point::from(center),
            inverse_mass: 0.5 + rng.uniform(),
            inverse_inertia: inertia.try_inverse().unwrap(),
            velocity: rng.in_unit_ball() * 3.0,
            angular_velocity: rng.in_unit_ball() * 3.0,
        };
        (body, inertia)
    }

    #[test]
    fn conserves_momentum_and_reverses_the_normal_speed() {
        let mut rng = Rng::new(9);
        let mut pushed = 0;
        for _ in 0..200 {
            let (mut a, inertia_a) = random_body(&mut rng, Vector::new(-1.0, 0.0, 0.0));
            let (mut b, inertia_b) = random_body(&mut rng, Vector::new(1.0, 0.0, 0.0));
            let point = Point::from(rng.in_unit_ball() * 0.3);
            let normal = (Vector::x() + rng.in_unit_ball() * 0.5).normalize();
            let e = rng.uniform();
            let momentum =
                |a: &ImpactBody, b: &ImpactBody| a.velocity / a.inverse_mass + b.velocity / b.inverse_mass;
            // Angular momentum about the origin: I ω + c × m v.
            let angular_momentum = |a: &ImpactBody, b: &ImpactBody| {
                inertia_a * a.angular_velocity
                    + a.center.coords.cross(&(a.velocity / a.inverse_mass))
                    + inertia_b * b.angular_velocity
                    + b.center.coords.cross(&(b.velocity / b.inverse_mass))
            };
            let energy = |a: &ImpactBody, b: &ImpactBody| {
                0.5 * (a.velocity.norm_squared() / a.inverse_mass
                    + b.velocity.norm_squared() / b.inverse_mass
                    + a.angular_velocity.dot(&(inertia_a * a.angular_velocity))
                    + b.angular_velocity.dot(&(inertia_b * b.angular_velocity)))
            };
            let approach = |a: &ImpactBody, b: &ImpactBody| {
                (b.point_velocity(&point) - a.point_velocity(&point)).dot(&normal)
            };
            let (p0, l0, e0, u0) =
                (momentum(&a, &b), angular_momentum(&a, &b), energy(&a, &b), approach(&a, &b));
            let j = apply_impulse(&mut a, &mut b, &point, &normal, e);
            if u0 >= 0.0 {
                assert_eq!(j, 0.0);
                continue;
            }
            pushed += 1;
            assert!(j > 0.0);
            assert!((momentum(&a, &b) - p0).norm() <= 1e-12 * (1.0 + p0.norm()));
            assert!((angular_momentum(&a, &b) - l0).norm() <= 1e-12 * (1.0 + l0.norm()));
            // The normal speed is reversed and scaled by e.
            assert!((approach(&a, &b) + e * u0).abs() <= 1e-12);
            // Energy never grows; elastic keeps it (checked below).
            assert!(energy(&a, &b) <= e0 * (1.0 + 1e-12));
        }
        assert!(pushed > 50);
    }

    #[test]
    fn elastic_keeps_energy_and_a_wall_reflects() {
        // A unit point mass (no spin) into a fixed wall along x: v_x flips.
        let mut ball = ImpactBody {
            center: Point::new(-0.5, 0.0, 0.0),
            inverse_mass: 1.0,
            inverse_inertia: Matrix3::zeros(),
            velocity: Vector::new(2.0, 1.0, 0.0),
            angular_velocity: Vector::zeros(),
        };
        let mut wall = ImpactBody {
            center: Point::new(1.0, 0.0, 0.0),
            inverse_mass: 0.0,
            inverse_inertia: Matrix3::zeros(),
            velocity: Vector::zeros(),
            angular_velocity: Vector::zeros(),
        };
        let j = apply_impulse(&mut ball, &mut wall, &Point::origin(), &Vector::x(), 1.0);
        assert_eq!(j, 4.0);
        assert_eq!(ball.velocity, Vector::new(-2.0, 1.0, 0.0));
        assert_eq!(wall.velocity, Vector::zeros());
    }
}
