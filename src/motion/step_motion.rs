//! The motion of a body within one step.

use nalgebra::{Translation3, UnitQuaternion};

use super::exponential::turn_exponential;
use crate::math::{Point, Pose, Real, Vector};

/// The largest rotation of an integrated body within one step (radians):
/// its motion within a step is interpolated with a constant angular
/// velocity taken the short way, which must be unambiguous. Checked at
/// load and at every step.
pub(crate) const MAX_TURN_PER_STEP: Real = std::f64::consts::FRAC_PI_2;

/// [`StepMotion::between_near`]: a turn between two poses whose quaternion's
/// vector part is at most this many ulps (of a unit quaternion) is a whole
/// number of turns to rounding, its axis rounding noise: the engine's spin
/// gives the axis. A turn of 4 ulps is about 2e-15 rad.
pub(crate) const TURN_ROUNDING_ULPS: Real = 4.0;

/// Constant linear velocity and constant angular velocity (world frame)
/// about the centre of mass.
///
/// The pose at time `s` after the step's start is
/// `x = x_ref + v (elapsed + s)`, `q = exp(ω (elapsed + s)) q_ref`: a free
/// body keeps its pose at time 0 as the reference and the time since then
/// as `elapsed`, so its path is one straight line and one exponential over
/// the whole run (no rounding jumps between steps), and two such bodies'
/// relative position is computed from the difference of their reference
/// positions ([`StepMotion::relative_pose`]): accurate relative to their
/// distance, not to their distance from the origin. An integrated body's
/// reference is its pose at the step's start.
///
/// The pose's translation is the centre of mass; mesh vertices are stored
/// relative to it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepMotion {
    /// The reference pose.
    pub reference: Pose,
    /// Time from the reference pose to the step's start.
    pub elapsed: Real,
    /// The linear velocity of the centre of mass.
    pub velocity: Vector,
    /// The angular velocity, world frame (radians per unit time).
    pub angular_velocity: Vector,
    /// Whether the step's end may differ from the next step's start by the
    /// rounding of the integrator's state (a few ulps of the coordinates):
    /// true for integrated bodies.
    pub integrated: bool,
}

impl StepMotion {
    /// A body at rest at `pose`.
    pub fn fixed(pose: Pose) -> StepMotion {
        StepMotion::new(pose, Vector::zeros(), Vector::zeros())
    }

    /// A body at `pose` at the step's start, moving with these velocities.
    pub fn new(pose: Pose, velocity: Vector, angular_velocity: Vector) -> StepMotion {
        StepMotion { reference: pose, elapsed: 0.0, velocity, angular_velocity, integrated: false }
    }

    /// The step of a free body (no forces, constant velocities) that starts
    /// at `time`, referred to its pose at time 0.
    pub fn free(pose_at_zero: &Pose, velocity: Vector, angular_velocity: Vector, time: Real) -> StepMotion {
        StepMotion { reference: *pose_at_zero, elapsed: time, velocity, angular_velocity, integrated: false }
    }

    /// The motion that takes `pose_t0` to `pose_t1` in time `dt` with constant
    /// velocities (the rotation taken the short way: less than π).
    pub fn between(pose_t0: &Pose, pose_t1: &Pose, dt: Real) -> StepMotion {
        let angular_velocity = StepMotion::turn_between(pose_t0, pose_t1, dt);
        StepMotion::between_turning(pose_t0, pose_t1, dt, angular_velocity)
    }

    /// The angular velocity of [`StepMotion::between`] the two poses.
    pub fn turn_between(pose_t0: &Pose, pose_t1: &Pose, dt: Real) -> Vector {
        let turn = pose_t1.rotation * pose_t0.rotation.inverse();
        turn.scaled_axis() / dt
    }

    /// [`StepMotion::between`] the two poses, given its angular velocity
    /// ([`StepMotion::turn_between`] them): for a caller that keeps the
    /// angular velocity rather than the whole motion.
    pub fn between_turning(pose_t0: &Pose, pose_t1: &Pose, dt: Real, angular_velocity: Vector) -> StepMotion {
        let velocity = (pose_t1.translation.vector - pose_t0.translation.vector) / dt;
        StepMotion { reference: *pose_t0, elapsed: 0.0, velocity, angular_velocity, integrated: true }
    }

    /// The motion that takes a body from `pose_t0` to `pose_t1` in time `dt`
    /// turning about its point `about` (in the body's own frame: a link's
    /// joint): constant angular velocity (the short way, less than π) and
    /// constant linear velocity of that point (zero for a joint that stays
    /// put), not of the frame's origin.
    ///
    /// It is the motion of the frame placed at `about` with the body's
    /// orientation, so it moves the body's mesh as that frame holds it:
    /// [`TriMesh::pivoted`](crate::mesh::TriMesh::pivoted) at `about`. The
    /// pair is exact for the time of impact, near misses and closest
    /// approach: at 0 and at `dt` every vertex is where the two poses put
    /// it, and between them it turns about `about`.
    pub fn between_about(pose_t0: &Pose, pose_t1: &Pose, dt: Real, about: &Point) -> StepMotion {
        let pivot_frame =
            |pose: &Pose| Pose::from_parts(Translation3::from((pose * about).coords), pose.rotation);
        let mut motion = StepMotion::between(&pivot_frame(pose_t0), &pivot_frame(pose_t1), dt);
        motion.integrated = false;
        motion
    }

    /// The motion that takes `pose_t0` to `pose_t1` in time `dt` with
    /// constant velocities, its rotation the one of the turns that do so
    /// (about the same axis, by the short angle plus whole turns, or the
    /// other way round) nearest `spin × dt`: for an engine that reports its
    /// angular velocity, so that a body turning more than π in a step is not
    /// swept the short way round.
    pub fn between_near(pose_t0: &Pose, pose_t1: &Pose, dt: Real, spin: &Vector) -> StepMotion {
        let velocity = (pose_t1.translation.vector - pose_t0.translation.vector) / dt;
        let mut motion = StepMotion {
            reference: *pose_t0,
            elapsed: 0.0,
            velocity,
            angular_velocity: Vector::zeros(),
            integrated: true,
        };
        // The short turn's axis and angle, as `UnitQuaternion::scaled_axis`
        // finds them (the same operations: the short turn is `between`'s to
        // the bit), from one square root.
        let turn = pose_t1.rotation * pose_t0.rotation.inverse();
        let q = turn.quaternion();
        let (imag, w) = if q.w >= 0.0 { (q.imag(), q.w) } else { (-q.imag(), -q.w) };
        let sine = imag.norm();
        let want = spin * dt;
        // A short turn at the rounding of the quaternion (a whole turn in
        // the step, or none) has no axis of its own: the spin's is taken.
        let (axis, angle) =
            if sine > TURN_ROUNDING_ULPS * Real::EPSILON || (sine > 0.0 && want == Vector::zeros()) {
                (imag / sine, sine.atan2(w) * 2.0)
            } else if want != Vector::zeros() {
                (want.normalize(), 0.0)
            } else {
                return motion;
            };
        // The turns that take pose_t0 to pose_t1: axis × (angle + 2πk). They
        // differ from `want` by the same part across the axis, so the
        // nearest is the one whose part along it is nearest: `angle + 2πk`
        // nearest `want · axis`.
        let tau = std::f64::consts::TAU;
        let k = ((want.dot(&axis) - angle) / tau).round();
        motion.angular_velocity = if k == 0.0 { axis * angle / dt } else { axis * (angle + tau * k) / dt };
        motion
    }

    /// The rotation at time `s` after the step's start.
    #[inline]
    pub fn rotation_at(&self, s: Real) -> UnitQuaternion<Real> {
        let turn = self.angular_velocity * (self.elapsed + s);
        if turn == Vector::zeros() {
            // The reference itself (the turn's exponential is the identity:
            // at the reference's time, or not turning).
            return self.reference.rotation;
        }
        turn_exponential(&turn) * self.reference.rotation
    }

    /// The pose at time `s` after the step's start.
    #[inline]
    pub fn pose_at(&self, s: Real) -> Pose {
        Pose::from_parts(Translation3::from(self.center_at(s).coords), self.rotation_at(s))
    }

    /// The pose at the step's start.
    #[inline]
    pub fn pose_t0(&self) -> Pose {
        self.pose_at(0.0)
    }

    /// The centre of mass at time `s`.
    #[inline]
    pub fn center_at(&self, s: Real) -> Point {
        Point::from(self.reference.translation.vector + self.velocity * (self.elapsed + s))
    }

    /// The pose of `b` in the frame of `a` at time `s` (parry's `pos12`),
    /// from the difference of the reference positions: its rounding is
    /// relative to the bodies' distance and displacements, not to their
    /// distance from the origin.
    #[inline]
    pub fn relative_pose(a: &StepMotion, b: &StepMotion, s: Real) -> Pose {
        StepMotion::relative_pose_turned((a, &a.rotation_at(s)), (b, &b.rotation_at(s)), s)
    }

    /// [`StepMotion::relative_pose`] given each body's orientation at `s`
    /// (its [`StepMotion::rotation_at`]), for callers that place one body
    /// in many pairs.
    #[inline]
    pub fn relative_pose_turned(
        (a, rotation_a): (&StepMotion, &UnitQuaternion<Real>),
        (b, rotation_b): (&StepMotion, &UnitQuaternion<Real>),
        s: Real,
    ) -> Pose {
        let translation = rotation_a.inverse_transform_vector(&StepMotion::center_offset(a, b, s));
        Pose::from_parts(Translation3::from(translation), rotation_a.inverse() * rotation_b)
    }

    /// `b`'s centre minus `a`'s at time `s` (world frame), from the
    /// difference of the reference positions.
    #[inline]
    pub fn center_offset(a: &StepMotion, b: &StepMotion, s: Real) -> Vector {
        let offset = b.reference.translation.vector - a.reference.translation.vector;
        let travel = if a.elapsed == b.elapsed {
            (b.velocity - a.velocity) * (a.elapsed + s)
        } else {
            b.velocity * (b.elapsed + s) - a.velocity * (a.elapsed + s)
        };
        offset + travel
    }

    /// The largest distance the centre travels from the reference, over the
    /// step of length `duration` (the scale of the rounding of `travel`).
    #[inline]
    pub fn travel(&self, duration: Real) -> Real {
        self.velocity.norm() * (self.elapsed + duration)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn between_reproduces_both_poses() {
        let pose_t0 = Pose::new(Vector::new(1.0, 2.0, 3.0), Vector::new(0.3, -0.2, 0.9));
        let pose_t1 = Pose::new(Vector::new(1.5, 1.0, 3.0), Vector::new(0.1, 0.4, 1.3));
        let motion = StepMotion::between(&pose_t0, &pose_t1, 0.25);
        let end = motion.pose_at(0.25);
        assert_relative_eq!(end.translation.vector, pose_t1.translation.vector, epsilon = 1e-15);
        assert!(end.rotation.angle_to(&pose_t1.rotation) < 1e-14);
    }

    /// An engine's body turning by `spin × dt` (more than π in the step,
    /// or a whole turn) is swept by that turn, not the short one; without
    /// a spin beyond π it is `between`'s short turn to the bit.
    #[test]
    fn between_near_takes_the_turn_nearest_the_spin() {
        let dt = 0.01;
        let pose_t0 = Pose::new(Vector::new(1.0, 2.0, 3.0), Vector::new(0.3, -0.2, 0.9));
        let axis = Vector::new(2.0, -1.0, 0.5).normalize();
        for angle in [0.3, 2.5, 4.0, -4.0, 7.0, 2.0 * std::f64::consts::PI, 13.0] {
            let spin = axis * (angle / dt);
            let turn = UnitQuaternion::from_scaled_axis(axis * angle);
            let pose_t1 = Pose::from_parts(
                (pose_t0.translation.vector + Vector::new(0.1, 0.0, -0.2)).into(),
                turn * pose_t0.rotation,
            );
            let motion = StepMotion::between_near(&pose_t0, &pose_t1, dt, &spin);
            // The spin itself, to rounding of the end pose's quaternion.
            assert_relative_eq!(motion.angular_velocity, spin, epsilon = 1e-12 / dt);
            let end = motion.pose_at(dt);
            assert_relative_eq!(end.translation.vector, pose_t1.translation.vector, epsilon = 1e-15);
            assert!(end.rotation.angle_to(&pose_t1.rotation) < 1e-13, "angle {angle}");
            if angle.abs() < std::f64::consts::PI {
                let short = StepMotion::between(&pose_t0, &pose_t1, dt);
                assert_eq!(motion.angular_velocity, short.angular_velocity);
            }
        }
        // Not turning, and no spin: no turn (to the rounding of q q⁻¹).
        let still = StepMotion::between_near(&pose_t0, &pose_t0, dt, &Vector::zeros());
        assert!(still.angular_velocity.norm() * dt < 1e-15, "{}", still.angular_velocity);
    }

    #[test]
    fn free_motion_is_the_exponential() {
        // A quarter turn about z in time 1 takes x to y.
        let motion = StepMotion::free(
            &Pose::identity(),
            Vector::zeros(),
            Vector::z() * std::f64::consts::FRAC_PI_2,
            0.5,
        );
        assert_relative_eq!(
            motion.pose_at(0.5) * Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            epsilon = 1e-15
        );
    }

    #[test]
    fn relative_pose_is_accurate_far_from_the_origin() {
        // Two bodies near 1e6: the relative pose is as accurate as at the origin.
        let far = Vector::new(1e6, -1e6, 1e6);
        let a = StepMotion::free(
            &Pose::new(far, Vector::zeros()),
            Vector::new(0.1, 0.0, 0.0),
            Vector::zeros(),
            3.0,
        );
        let b_pose = Pose::new(far + Vector::new(0.75, 0.0, 0.0), Vector::zeros());
        let b = StepMotion::free(&b_pose, Vector::new(-0.1, 0.0, 0.0), Vector::zeros(), 3.0);
        let relative = StepMotion::relative_pose(&a, &b, 0.25);
        // 0.75 - 0.2 × 3.25 = 0.1 (to the rounding of numbers near 1, not near 1e6).
        assert!((relative.translation.vector.x - 0.1).abs() <= 4.0 * f64::EPSILON);
    }
}
