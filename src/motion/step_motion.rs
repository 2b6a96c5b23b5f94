//! The motion of a body within one step.

use nalgebra::{Translation3, UnitQuaternion};

use crate::math::{Point, Pose, Real, Vector};

/// Constant linear velocity and constant angular velocity (world frame)
/// about the centre of mass, from `pose_t0` at the step's start.
///
/// The pose's translation is the centre of mass; mesh vertices are stored
/// relative to it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepMotion {
    /// The pose at the start of the step.
    pub pose_t0: Pose,
    /// The linear velocity of the centre of mass.
    pub velocity: Vector,
    /// The angular velocity, world frame (radians per unit time).
    pub angular_velocity: Vector,
}

impl StepMotion {
    /// A body at rest at `pose`.
    pub fn fixed(pose: Pose) -> StepMotion {
        StepMotion { pose_t0: pose, velocity: Vector::zeros(), angular_velocity: Vector::zeros() }
    }

    /// The step of a free body (no forces, constant velocities) that starts
    /// at `time`, computed from its pose at time 0, not from the previous
    /// step, so rounding does not accumulate over steps.
    pub fn free(pose_at_zero: &Pose, velocity: Vector, angular_velocity: Vector, time: Real) -> StepMotion {
        let motion = StepMotion { pose_t0: *pose_at_zero, velocity, angular_velocity };
        StepMotion { pose_t0: motion.pose_at(time), velocity, angular_velocity }
    }

    /// The motion that takes `pose_t0` to `pose_t1` in time `dt` with constant
    /// velocities (the rotation taken the short way: less than π).
    pub fn between(pose_t0: &Pose, pose_t1: &Pose, dt: Real) -> StepMotion {
        let velocity = (pose_t1.translation.vector - pose_t0.translation.vector) / dt;
        let turn = pose_t1.rotation * pose_t0.rotation.inverse();
        StepMotion { pose_t0: *pose_t0, velocity, angular_velocity: turn.scaled_axis() / dt }
    }

    /// The pose at time `s` after the step's start.
    #[inline]
    pub fn pose_at(&self, s: Real) -> Pose {
        let translation = Translation3::from(self.pose_t0.translation.vector + self.velocity * s);
        let rotation = UnitQuaternion::from_scaled_axis(self.angular_velocity * s) * self.pose_t0.rotation;
        Pose::from_parts(translation, rotation)
    }

    /// The centre of mass at time `s`.
    #[inline]
    pub fn center_at(&self, s: Real) -> Point {
        Point::from(self.pose_t0.translation.vector + self.velocity * s)
    }

    /// An upper bound on the speed of any point within `radius` of the
    /// centre of mass: `|v| + |ω| r`.
    #[inline]
    pub fn max_point_speed(&self, radius: Real) -> Real {
        self.velocity.norm() + self.angular_velocity.norm() * radius
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

    #[test]
    fn free_motion_is_the_exponential() {
        // A quarter turn about z in time 1 takes x to y.
        let motion = StepMotion::free(
            &Pose::identity(),
            Vector::zeros(),
            Vector::z() * std::f64::consts::FRAC_PI_2,
            0.0,
        );
        assert_relative_eq!(
            motion.pose_at(1.0) * Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            epsilon = 1e-15
        );
    }
}
