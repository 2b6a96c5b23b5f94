//! Fixed-step integrators of rigid bodies under gravity, springs and the
//! gyroscopic torque of anisotropic inertia.

use nalgebra::{Matrix3, Quaternion, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::classify::inertia_is_isotropic;
use super::exponential::turn_exponential;
use super::gyroscopic::implicit_gyroscopic_step;
use crate::math::{Point, Pose, Real, Vector};

/// The integrator of bodies with forces.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Integrator {
    /// Semi-implicit (symplectic) Euler: velocities first, then positions
    /// with the new velocities; the rotation uses the [`Gyroscopic`] choice
    /// (the orientation renormalised after each step). First order, but
    /// energy stays bounded for oscillators with `ω dt < 2`. The default.
    #[default]
    SymplecticEuler,
    /// Explicit Euler: positions and velocities from the old state. First
    /// order, gains energy every step (for comparison).
    ExplicitEuler,
    /// The classical fourth-order Runge–Kutta method on the whole state
    /// (quaternion renormalised after each step).
    Rk4,
}

/// How [`Integrator::SymplecticEuler`] advances the angular velocity.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Gyroscopic {
    /// The implicit midpoint rule on Euler's equations
    /// ([`super::implicit_gyroscopic_step`]): energy and `|L|` kept. The default.
    #[default]
    Implicit,
    /// Explicit Euler on Euler's equations (for comparison).
    Explicit,
}

/// The state of a rigid body.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidState {
    /// The centre of mass.
    pub position: Point,
    /// The orientation.
    pub orientation: UnitQuaternion<Real>,
    /// The velocity of the centre of mass.
    pub velocity: Vector,
    /// The angular velocity, world frame.
    pub angular_velocity: Vector,
}

impl RigidState {
    /// The pose (translation = centre of mass).
    pub fn pose(&self) -> Pose {
        Pose::from_parts(Translation3::from(self.position.coords), self.orientation)
    }

    /// Whether every component is finite: `x × 0` is 0 for a finite `x`
    /// and NaN otherwise, so the sum of these products is 0 exactly when
    /// every component is finite (checked at every step of every body:
    /// no branch per component).
    #[inline]
    pub fn is_finite(&self) -> bool {
        let zeros = |xs: &[Real]| xs.iter().map(|x| x * 0.0).sum::<Real>();
        let sum = zeros(self.position.coords.as_slice())
            + zeros(self.orientation.coords.as_slice())
            + zeros(self.velocity.as_slice())
            + zeros(self.angular_velocity.as_slice());
        sum == 0.0
    }
}

/// A linear spring from a point of a body to a fixed world anchor, with
/// viscous damping.
///
/// Force on the body, with `r` = attachment point − anchor and `v` the
/// attachment point's velocity: `−k r − c v` when `rest_length` is 0,
/// otherwise `−k (|r| − rest_length) r̂ − c (v·r̂) r̂`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Spring {
    /// The attachment point, body frame, relative to the centre of mass.
    pub point: Vector,
    /// The world anchor.
    pub anchor: Point,
    /// Stiffness `k` (force per length).
    pub stiffness: Real,
    /// Damping `c` (force per speed).
    pub damping: Real,
    /// Rest length.
    pub rest_length: Real,
}

impl Spring {
    /// The force on the body in a state (centre of mass `position`,
    /// `orientation`, `velocity`, world angular velocity `omega`) and the
    /// attachment's arm from the centre of mass (world frame).
    pub fn force(
        &self,
        position: &Point,
        orientation: &UnitQuaternion<Real>,
        velocity: &Vector,
        omega: &Vector,
    ) -> (Vector, Vector) {
        let arm = orientation * self.point;
        let r = position + arm - self.anchor;
        let point_velocity = velocity + omega.cross(&arm);
        let force = if self.rest_length == 0.0 {
            -self.stiffness * r - self.damping * point_velocity
        } else {
            let length = r.norm();
            if length > 0.0 {
                let direction = r / length;
                direction
                    * (-self.stiffness * (length - self.rest_length)
                        - self.damping * point_velocity.dot(&direction))
            } else {
                Vector::zeros()
            }
        };
        (force, arm)
    }
}

/// What an integrated body's step needs: its mass properties and what
/// acts on it. A view, borrowed from where each is kept (a scene's body
/// keeps its mass, inertia and springs, the scene its gravity:
/// [`Body::dynamics`](crate::scene::Body::dynamics)), made when the body is
/// stepped, so that nothing is stored twice.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Dynamics<'a> {
    /// `1 / mass` (0 when the body has no mass: only gravity then acts).
    pub inverse_mass: Real,
    /// The inertia tensor about the centre of mass, body frame; `None`
    /// keeps the angular velocity constant (no torque can act).
    pub inertia: Option<&'a Matrix3<Real>>,
    /// Uniform gravitational acceleration.
    pub gravity: Vector,
    /// Springs attached to the body.
    pub springs: &'a [Spring],
}

impl Dynamics<'_> {
    /// Linear acceleration and body-frame torque in a state.
    fn loads(
        &self,
        position: &Point,
        orientation: &UnitQuaternion<Real>,
        velocity: &Vector,
        omega: &Vector,
    ) -> (Vector, Vector) {
        let mut force = Vector::zeros();
        let mut torque = Vector::zeros();
        if self.springs.is_empty() {
            // Turning the zero torque into the body frame gives +0 in every
            // coordinate (nalgebra's rotation ends by adding the vector
            // turned, here +0, and ±0 + +0 is +0): the turn is skipped, the
            // result the same to the bit.
            return (self.gravity + force * self.inverse_mass, torque);
        }
        for spring in self.springs {
            let (f, arm) = spring.force(position, orientation, velocity, omega);
            force += f;
            torque += arm.cross(&f);
        }
        (self.gravity + force * self.inverse_mass, orientation.inverse_transform_vector(&torque))
    }

    /// Body-frame angular acceleration `I⁻¹ (τ − ω × I ω)`.
    fn angular_acceleration(&self, omega_body: &Vector, torque_body: &Vector) -> Vector {
        match self.inertia {
            Some(inertia) => inertia
                .lu()
                .solve(&(torque_body - omega_body.cross(&(inertia * omega_body))))
                .unwrap_or_else(Vector::zeros),
            None => Vector::zeros(),
        }
    }
}

impl Dynamics<'_> {
    /// The mass used for energies: the body's mass, or 1 for a massless
    /// body under gravity only (its energy is then per unit mass).
    fn energy_mass(&self) -> Real {
        if self.inverse_mass > 0.0 {
            1.0 / self.inverse_mass
        } else {
            1.0
        }
    }

    /// Mechanical energy in a state: kinetic (linear and rotational), the
    /// springs' potential and gravity's (`−m g·x`). Constant for an
    /// undamped body under exact integration.
    pub fn energy(&self, state: &RigidState) -> Real {
        self.energy_terms(state).iter().sum()
    }

    /// The energy's scale: the sum of the magnitudes of its terms (so a
    /// relative drift is meaningful when the terms cancel).
    pub fn energy_scale(&self, state: &RigidState) -> Real {
        self.energy_terms(state).iter().map(|e| e.abs()).sum()
    }

    fn energy_terms(&self, state: &RigidState) -> [Real; 4] {
        let mass = self.energy_mass();
        let linear = 0.5 * mass * state.velocity.norm_squared();
        let omega_body = state.orientation.inverse_transform_vector(&state.angular_velocity);
        let rotational = self.inertia.map_or(0.0, |inertia| 0.5 * omega_body.dot(&(inertia * omega_body)));
        let springs = self
            .springs
            .iter()
            .map(|spring| {
                let r = state.position + state.orientation * spring.point - spring.anchor;
                let stretch =
                    if spring.rest_length == 0.0 { r.norm() } else { r.norm() - spring.rest_length };
                0.5 * spring.stiffness * stretch * stretch
            })
            .sum::<Real>();
        let gravity = -mass * self.gravity.dot(&state.position.coords);
        [linear, rotational, springs, gravity]
    }

    /// The largest step with which `integrator` keeps this body's springs
    /// stable (undamped linear analysis, `ω = sqrt(Σk / m)`): `2 / ω` for
    /// semi-implicit Euler, `2√2 / ω` for RK4, and none for explicit Euler
    /// (it gains energy at every step). `None` without springs.
    pub fn stable_step_limit(&self, integrator: Integrator) -> Option<Real> {
        let stiffness: Real = self.springs.iter().map(|s| s.stiffness).sum();
        if stiffness <= 0.0 || self.inverse_mass <= 0.0 {
            return None;
        }
        let omega = (stiffness * self.inverse_mass).sqrt();
        match integrator {
            Integrator::SymplecticEuler => Some(2.0 / omega),
            Integrator::Rk4 => Some(2.0 * Real::sqrt(2.0) / omega),
            Integrator::ExplicitEuler => Some(0.0),
        }
    }
}

/// Advances `state` by `dt`. Returns the new state and whether the implicit
/// gyroscopic solve (when used) converged.
pub fn integrate(
    state: &RigidState,
    dynamics: &Dynamics,
    integrator: Integrator,
    gyroscopic: Gyroscopic,
    dt: Real,
) -> (RigidState, bool) {
    let step = integrate_turning(state, dynamics, integrator, gyroscopic, dt);
    (step.next, step.converged)
}

/// `q` turned by `exp(ω_b)` (`ω_b` a body-frame rotation vector), brought
/// back to unit length. The product of two unit quaternions is one only to
/// rounding: left alone, the orientation's norm walks away from 1 by a few
/// ulps a step, and a body's angular velocity, turned into the body frame
/// and back each step, is scaled by its square: on a tumbling handle
/// (`scenes/stability/dzhanibekov_long.ron`, 100,000 steps) the energy
/// drifted by 2.8e-9 that way, against 1.4e-11 renormalised.
///
/// The renormalisation is first order (`(3 − n²) / 2`, exact to rounding
/// this close to 1), with `n² = |q|² |exp|²`, the product's norm found from
/// its factors': it is ready when the product is, not after it (a fifth of
/// the step's time, measured, when it waited for the product). The
/// product's own rounding is taken out at the next step, so the norm stays
/// within a few ulps of 1 rather than walking.
#[inline]
fn turned(q: &UnitQuaternion<Real>, rotation: &Vector) -> UnitQuaternion<Real> {
    unit_product(q, &turn_exponential(rotation))
}

/// `q` turned by `exp(ω)` (`ω` a world-frame rotation vector), `exp(ω) q`,
/// brought back to unit length as [`turned`] does.
#[inline]
fn turned_world(q: &UnitQuaternion<Real>, rotation: &Vector) -> UnitQuaternion<Real> {
    unit_product(&turn_exponential(rotation), q)
}

/// `a b`, renormalised to first order from its factors' norms (see
/// [`turned`]).
#[inline]
fn unit_product(a: &UnitQuaternion<Real>, b: &UnitQuaternion<Real>) -> UnitQuaternion<Real> {
    let size = a.as_ref().norm_squared() * b.as_ref().norm_squared();
    let product = a.quaternion() * b.quaternion();
    UnitQuaternion::new_unchecked(product * (0.5 * (3.0 - size)))
}

/// Whether a body's angular velocity stays what it is through a semi-
/// implicit Euler step: no spring can turn it (gravity acts at the centre
/// of mass) and it feels no gyroscopic torque (no inertia, or an isotropic
/// one under the implicit rule, which drops the torque of such a body).
#[inline]
pub(crate) fn spins_steadily(dynamics: &Dynamics, gyroscopic: Gyroscopic) -> bool {
    dynamics.springs.is_empty()
        && dynamics
            .inertia
            .is_none_or(|inertia| gyroscopic == Gyroscopic::Implicit && inertia_is_isotropic(inertia))
}

/// A semi-implicit Euler step of a body whose angular velocity `ω` stays
/// (see [`spins_steadily`]): it turns by `exp(ω dt)` in the world frame,
/// which is the body-frame `q exp(ω_b dt)` of the general step without
/// taking `ω` into the body frame and back (whose rounding walked `ω` by
/// an ulp or so a step, where it now stays as it is).
#[inline(always)]
pub(crate) fn steady_spin_step(state: &RigidState, gravity: &Vector, dt: Real) -> IntegratorStep {
    let velocity = state.velocity + gravity * dt;
    let omega = state.angular_velocity;
    let next = RigidState {
        position: state.position + velocity * dt,
        orientation: turned_world(&state.orientation, &(omega * dt)),
        velocity,
        angular_velocity: omega,
    };
    IntegratorStep { next, turn: omega, converged: true }
}

/// One integrator step ([`integrate_turning`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct IntegratorStep {
    /// The state at the step's end.
    pub next: RigidState,
    /// The constant angular velocity (world frame) that turns the
    /// orientation at the step's start into the one at its end over `dt`:
    /// the one the integrator turned the body by, as a rotation vector over
    /// `dt` (not folded to the short way, so `|turn| dt` is the angle the
    /// body turned).
    pub turn: Vector,
    /// Whether the implicit gyroscopic solve (when used) converged.
    pub converged: bool,
}

/// [`integrate`], with the angular velocity of the step's turn: semi-
/// implicit and explicit Euler turn the body by one exponential, `q' = q
/// exp(ω_b dt)` (`ω_b` body frame), which is the world-frame `q ω_b` over
/// `dt`; RK4's turn is read back from the two orientations
/// ([`StepMotion::turn_between`](super::StepMotion::turn_between)).
///
/// Always inlined: returned through memory, its result was read back in
/// wider loads than it was written with (each a stalled store-to-load
/// forward: under `perf`, a quarter of the stepper's integration closure's
/// samples sat on one such load).
#[inline(always)]
pub fn integrate_turning(
    state: &RigidState,
    dynamics: &Dynamics,
    integrator: Integrator,
    gyroscopic: Gyroscopic,
    dt: Real,
) -> IntegratorStep {
    let q = state.orientation;
    if integrator == Integrator::SymplecticEuler && spins_steadily(dynamics, gyroscopic) {
        return steady_spin_step(state, &dynamics.gravity, dt);
    }
    let omega_body = q.inverse_transform_vector(&state.angular_velocity);
    match integrator {
        Integrator::ExplicitEuler => {
            let (acceleration, torque) =
                dynamics.loads(&state.position, &q, &state.velocity, &state.angular_velocity);
            let omega_next = omega_body + dt * dynamics.angular_acceleration(&omega_body, &torque);
            let orientation = turned(&q, &(omega_body * dt));
            let next = RigidState {
                position: state.position + state.velocity * dt,
                orientation,
                velocity: state.velocity + acceleration * dt,
                angular_velocity: orientation * omega_next,
            };
            // q exp(ω_b dt) = exp(ω dt) q: the world-frame turn is the state's own ω.
            IntegratorStep { next, turn: state.angular_velocity, converged: true }
        }
        Integrator::SymplecticEuler => {
            let (acceleration, torque) =
                dynamics.loads(&state.position, &q, &state.velocity, &state.angular_velocity);
            let velocity = state.velocity + acceleration * dt;
            let (omega_next, turn, converged) = match (dynamics.inertia, gyroscopic) {
                (Some(inertia), Gyroscopic::Implicit) if inertia_is_isotropic(inertia) => {
                    // No gyroscopic torque: the implicit midpoint rule is
                    // `I (ω' − ω) = dt τ`, and with no torque `ω' = ω`.
                    let next = if torque == Vector::zeros() {
                        omega_body
                    } else {
                        omega_body + dt * inertia.lu().solve(&torque).unwrap_or_else(Vector::zeros)
                    };
                    (next, (omega_body + next) / 2.0, true)
                }
                (Some(inertia), Gyroscopic::Implicit) => {
                    let solve = implicit_gyroscopic_step(inertia, &omega_body, &torque, dt);
                    (solve.angular_velocity, solve.midpoint, solve.converged)
                }
                _ => {
                    let next = omega_body + dt * dynamics.angular_acceleration(&omega_body, &torque);
                    (next, next, true)
                }
            };
            let orientation = turned(&q, &(turn * dt));
            let next = RigidState {
                position: state.position + velocity * dt,
                orientation,
                velocity,
                angular_velocity: orientation * omega_next,
            };
            IntegratorStep { next, turn: q * turn, converged }
        }
        Integrator::Rk4 => {
            let next = rk4(state, dynamics, dt);
            let turn = super::StepMotion::turn_between(&state.pose(), &next.pose(), dt);
            IntegratorStep { next, turn, converged: true }
        }
    }
}

/// The state as RK4 sees it: orientation as a raw quaternion, angular
/// velocity in the body frame.
#[derive(Copy, Clone)]
struct Flat {
    position: Vector,
    velocity: Vector,
    orientation: Quaternion<Real>,
    omega_body: Vector,
}

impl Flat {
    fn plus(&self, k: &Flat, h: Real) -> Flat {
        Flat {
            position: self.position + k.position * h,
            velocity: self.velocity + k.velocity * h,
            orientation: self.orientation + k.orientation * h,
            omega_body: self.omega_body + k.omega_body * h,
        }
    }
}

fn rk4(state: &RigidState, dynamics: &Dynamics, dt: Real) -> RigidState {
    let derivative = |y: &Flat| {
        let q = UnitQuaternion::new_normalize(y.orientation);
        let omega_world = q * y.omega_body;
        let (acceleration, torque) = dynamics.loads(&Point::from(y.position), &q, &y.velocity, &omega_world);
        Flat {
            position: y.velocity,
            velocity: acceleration,
            orientation: y.orientation * Quaternion::from_imag(y.omega_body) * 0.5,
            omega_body: dynamics.angular_acceleration(&y.omega_body, &torque),
        }
    };
    let y = Flat {
        position: state.position.coords,
        velocity: state.velocity,
        orientation: *state.orientation.quaternion(),
        omega_body: state.orientation.inverse_transform_vector(&state.angular_velocity),
    };
    let k1 = derivative(&y);
    let k2 = derivative(&y.plus(&k1, dt / 2.0));
    let k3 = derivative(&y.plus(&k2, dt / 2.0));
    let k4 = derivative(&y.plus(&k3, dt));
    let sum = Flat {
        position: k1.position + 2.0 * k2.position + 2.0 * k3.position + k4.position,
        velocity: k1.velocity + 2.0 * k2.velocity + 2.0 * k3.velocity + k4.velocity,
        orientation: k1.orientation + k2.orientation * 2.0 + k3.orientation * 2.0 + k4.orientation,
        omega_body: k1.omega_body + 2.0 * k2.omega_body + 2.0 * k3.omega_body + k4.omega_body,
    };
    let next = y.plus(&sum, dt / 6.0);
    let orientation = UnitQuaternion::new_normalize(next.orientation);
    RigidState {
        position: Point::from(next.position),
        orientation,
        velocity: next.velocity,
        angular_velocity: orientation * next.omega_body,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn oscillator() -> (RigidState, Spring) {
        let state = RigidState {
            position: Point::new(1.0, 0.0, 0.0),
            orientation: UnitQuaternion::identity(),
            velocity: Vector::zeros(),
            angular_velocity: Vector::zeros(),
        };
        let spring = Spring {
            point: Vector::zeros(),
            anchor: Point::origin(),
            stiffness: 4.0,
            damping: 0.0,
            rest_length: 0.0,
        };
        (state, spring)
    }

    /// A unit mass held by `springs`, with `inertia`, no gravity.
    fn held<'a>(inertia: Option<&'a Matrix3<Real>>, springs: &'a [Spring]) -> Dynamics<'a> {
        Dynamics { inverse_mass: 1.0, inertia, gravity: Vector::zeros(), springs }
    }

    /// x(t) = cos(2t): the error at t = 1 shrinks with the method's order.
    #[test]
    fn orders_of_accuracy_on_a_harmonic_oscillator() {
        let error = |integrator: Integrator, steps: usize| {
            let (mut state, spring) = oscillator();
            let springs = [spring];
            let dynamics = held(None, &springs);
            let dt = 1.0 / steps as Real;
            for _ in 0..steps {
                state = integrate(&state, &dynamics, integrator, Gyroscopic::Implicit, dt).0;
            }
            (state.position.x - Real::cos(2.0)).abs()
        };
        for (integrator, order) in
            [(Integrator::ExplicitEuler, 1.0), (Integrator::SymplecticEuler, 1.0), (Integrator::Rk4, 4.0)]
        {
            let ratio = error(integrator, 200) / error(integrator, 400);
            let observed = ratio.log2();
            assert!((observed - order).abs() < 0.2, "{integrator:?}: observed order {observed}");
        }
    }

    /// The turn `integrate_turning` reports takes the step's first
    /// orientation to its last over `dt` (world frame: `exp(turn dt) q0`), to
    /// rounding, for every integrator, on a tumbling box under a spring.
    #[test]
    fn the_reported_turn_takes_one_orientation_to_the_next() {
        let (mut state, mut spring) = oscillator();
        let inertia = Matrix3::from_diagonal(&Vector::new(0.1, 0.2, 0.3));
        spring.point = Vector::new(0.0, 0.3, 0.1);
        let springs = [spring];
        let dynamics = held(Some(&inertia), &springs);
        state.angular_velocity = Vector::new(1.0, 7.0, -3.0);
        for integrator in [Integrator::SymplecticEuler, Integrator::ExplicitEuler, Integrator::Rk4] {
            for gyroscopic in [Gyroscopic::Implicit, Gyroscopic::Explicit] {
                let mut s = state;
                for _ in 0..200 {
                    let step = integrate_turning(&s, &dynamics, integrator, gyroscopic, 0.01);
                    let reached = UnitQuaternion::from_scaled_axis(step.turn * 0.01) * s.orientation;
                    let gap = reached.angle_to(&step.next.orientation);
                    assert!(gap < 1e-14, "{integrator:?} {gyroscopic:?}: {gap:e}");
                    assert_eq!(step.next, integrate(&s, &dynamics, integrator, gyroscopic, 0.01).0);
                    s = step.next;
                }
            }
        }
    }

    /// A body whose inertia is isotropic to rounding (an icosphere's) keeps a
    /// torque-free spin exactly, turning by it, and with a torque turns as
    /// the full gyroscopic solve does, to that solve's tolerance.
    #[test]
    fn an_isotropic_body_needs_no_gyroscopic_solve() {
        // An icosphere's inertia, within an ulp or two of isotropic.
        let inertia = Matrix3::new(
            3.844671806821603e-3,
            1e-19,
            -2e-19,
            1e-19,
            3.844671806821602e-3,
            0.0,
            -2e-19,
            0.0,
            3.844671806821604e-3,
        );
        let mut rng = crate::samples::Rng::new(7);
        for _ in 0..1000 {
            let state = RigidState {
                position: Point::origin(),
                orientation: UnitQuaternion::from_scaled_axis(rng.in_unit_ball() * 3.0),
                velocity: Vector::zeros(),
                angular_velocity: rng.in_unit_ball() * 8.0,
            };
            let free = held(Some(&inertia), &[]);
            let step =
                integrate_turning(&state, &free, Integrator::SymplecticEuler, Gyroscopic::Implicit, 0.01);
            let spin = state.angular_velocity;
            assert_eq!((step.next.angular_velocity, step.turn), (spin, spin));
            let omega_body = state.orientation.inverse_transform_vector(&spin);
            // With a spring's torque: beside the full solve.
            let spring = Spring {
                point: rng.in_unit_ball(),
                anchor: Point::from(rng.in_unit_ball() * 2.0),
                stiffness: 3.0,
                damping: 0.0,
                rest_length: 0.0,
            };
            let springs = [spring];
            let held = Dynamics { springs: &springs, ..free };
            let step =
                integrate_turning(&state, &held, Integrator::SymplecticEuler, Gyroscopic::Implicit, 0.01);
            let (_, torque) =
                held.loads(&state.position, &state.orientation, &state.velocity, &state.angular_velocity);
            // (The full solve may stop short of its 4 ulps of |ω| when the
            // torque's change is much larger than ω: compared by the change.)
            let full = implicit_gyroscopic_step(&inertia, &omega_body, &torque, 0.01);
            let turned = step.next.orientation.inverse_transform_vector(&step.next.angular_velocity);
            let tolerance = 16.0 * Real::EPSILON * omega_body.norm().max(turned.norm());
            let tolerance = tolerance.max(1e-12 * (turned - omega_body).norm());
            assert!(
                (turned - full.angular_velocity).norm() <= tolerance,
                "{turned} {}",
                full.angular_velocity
            );
        }
    }

    /// A torque-free spin of an isotropic body over 10,000 steps (a
    /// hundred seconds at 8 rad/s, 127 turns) against its exact motion,
    /// `exp(ω t) q₀`: within 1e-11 rad, the steps' rounding.
    #[test]
    fn an_isotropic_spin_follows_its_exact_motion() {
        let inertia = Matrix3::from_diagonal_element(0.004);
        let dynamics = held(Some(&inertia), &[]);
        let mut rng = crate::samples::Rng::new(11);
        for _ in 0..4 {
            let start = RigidState {
                position: Point::origin(),
                orientation: UnitQuaternion::from_scaled_axis(rng.in_unit_ball() * 3.0),
                velocity: Vector::zeros(),
                angular_velocity: rng.in_unit_ball().normalize() * 8.0,
            };
            let mut state = start;
            for _ in 0..10_000 {
                state = integrate_turning(
                    &state,
                    &dynamics,
                    Integrator::SymplecticEuler,
                    Gyroscopic::Implicit,
                    0.01,
                )
                .next;
            }
            let exact = UnitQuaternion::from_scaled_axis(start.angular_velocity * 100.0) * start.orientation;
            let gap = exact.angle_to(&state.orientation);
            assert!(gap < 1e-11, "{gap:e}");
            assert!((state.orientation.norm() - 1.0).abs() < 4.0 * Real::EPSILON);
        }
    }

    #[test]
    fn rk4_falls_exactly_under_gravity() {
        let state = RigidState {
            position: Point::new(0.0, 10.0, 0.0),
            orientation: UnitQuaternion::identity(),
            velocity: Vector::new(1.0, 0.0, 0.0),
            angular_velocity: Vector::new(0.0, 0.0, 3.0),
        };
        let dynamics = Dynamics {
            inverse_mass: 0.0,
            inertia: None,
            gravity: Vector::new(0.0, -9.81, 0.0),
            springs: &[],
        };
        let mut s = state;
        for _ in 0..100 {
            s = integrate(&s, &dynamics, Integrator::Rk4, Gyroscopic::Implicit, 0.01).0;
        }
        assert_relative_eq!(s.position, Point::new(1.0, 10.0 - 9.81 / 2.0, 0.0), epsilon = 1e-12);
        // The rotation is fourth order: about (ω dt)⁵ / 5! per step, 2e-8 in all.
        let angle_error =
            s.orientation.angle_to(&UnitQuaternion::from_scaled_axis(Vector::new(0.0, 0.0, 3.0)));
        assert!(angle_error < 1e-7, "{angle_error}");
    }
}
