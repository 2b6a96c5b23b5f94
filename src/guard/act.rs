//! What the guard does to rapier's bodies between its sweeps: reads them
//! into motions, moves the world back to a contact, stops a pair at one
//! (an inelastic impulse there; a body touching a kinematic one carried
//! along), and pushes apart pairs the depth watch finds too deep.

use super::bodies::RapierBodies;
use super::depth::Deep;
use super::thickness::pair_tolerance;
use super::views::{body_pose, center_pose, BodyKind, BodyView};
use super::{Guard, GuardEvent, PUSHED_DEPTH_FRACTION};
use crate::math::{Point, Pose, Real, Vector};
use crate::motion::StepMotion;
use crate::stepper::respond::{apply_impulse, ImpactBody};
use crate::stepper::GuardHit;

impl<B: RapierBodies> Guard<B> {
    /// The depth watch after the step's last sweep (`scale`: its length over
    /// `dt`; the step's contacts from `contacts_before` on): touching pairs
    /// that rapier let sink deeper than the tolerated depth are pushed
    /// apart, each an [`GuardEvent::Overlap`].
    pub(super) fn watch_depths(&mut self, bodies: &mut B, scale: Real, contacts_before: usize) {
        let Some(watch) = self.depth.as_mut() else { return };
        self.deep.clear();
        let model = self.stepper.model();
        let solved = |a: usize, b: usize| self.solved.solves(a, b);
        let tolerated = |a: usize, b: usize| pair_tolerance(self.tolerated_depth, &self.thickness, a, b);
        let new = &self.world.contacts[contacts_before..];
        watch.measure(model, &self.world, new, &tolerated, &solved, &mut self.deep);
        if !self.deep.is_empty() {
            self.forget_bounds();
        }
        for k in 0..self.deep.len() {
            let deep = self.deep[k];
            let pushed_apart = self.push_apart(bodies, &deep, scale);
            let (a, b) = (self.handles[deep.a], self.handles[deep.b]);
            self.events.push(GuardEvent::Overlap { a, b, depth: deep.depth, pushed_apart });
        }
    }

    /// Moves the dynamic bodies of a pair found too deep apart along its
    /// direction, by their inverse masses, to [`PUSHED_DEPTH_FRACTION`] of
    /// the tolerated depth, and stops their approach there (an inelastic
    /// impulse where they meet). `false` when neither is dynamic.
    fn push_apart(&mut self, bodies: &mut B, deep: &Deep, scale: Real) -> bool {
        let weight = |i: usize| {
            bodies
                .view(self.handles[i])
                .map_or(0.0, |view| if self.stoppable[i] { view.inverse_mass } else { 0.0 })
        };
        let (wa, wb) = (weight(deep.a), weight(deep.b));
        if wa + wb <= 0.0 {
            return false;
        }
        let tolerated = pair_tolerance(self.tolerated_depth, &self.thickness, deep.a, deep.b);
        let excess = deep.depth - PUSHED_DEPTH_FRACTION * tolerated;
        let u = deep.direction;
        // b moves along u, a against it.
        for (i, sign, w) in [(deep.a, -1.0, wa), (deep.b, 1.0, wb)] {
            let Some(view) = bodies.view(self.handles[i]).filter(|_| w > 0.0) else { continue };
            let end = self.world.motions[i].pose_at(self.dt);
            let shift = u * (sign * excess * w / (wa + wb));
            let moved = Pose::from_parts((end.translation.vector + shift).into(), end.rotation);
            bodies.set_pose(self.handles[i], &body_pose(&moved, &self.centers[i]), false);
            self.world.motions[i] =
                StepMotion::between_near(&self.start[i], &moved, self.dt, &(view.angvel * scale));
        }
        self.inelastic_impulse(bodies, [deep.a, deep.b], &deep.point, &u);
        true
    }

    /// Each body's motion over the rest of the step from `elapsed`: from its
    /// pose at the sweep's start to where rapier left it, stretched over
    /// `dt` (the CCD's path is the same; its times map back linearly).
    pub(super) fn set_motions(&mut self, bodies: &B, elapsed: Real) {
        let scale = (self.dt - elapsed) / self.dt;
        for (i, handle) in self.handles.iter().enumerate() {
            let Some(body) = bodies.view(*handle) else { continue };
            let end = center_pose(&body.pose, &self.centers[i]);
            self.world.motions[i] = if body.kind == BodyKind::Fixed {
                StepMotion::fixed(end)
            } else {
                let spin = body.angvel * scale;
                StepMotion::between_near(&self.start[i], &end, self.dt, &spin)
            };
        }
    }

    /// Moves every moving body back to its pose at `at` into the current
    /// sweep (velocities interpolated between the sweep's ends, so that the
    /// forces of the step are applied once), kinematic bodies still bound
    /// for the step's end, and wakes the pair `hit`.
    pub(super) fn rewind(&mut self, bodies: &mut B, at: Real, hit: [usize; 2]) {
        let fraction = at / self.dt;
        for (i, &handle) in self.handles.iter().enumerate() {
            let Some(body) = bodies.view(handle) else { continue };
            let woken = hit.contains(&i);
            let pose = self.world.motions[i].pose_at(at);
            match body.kind {
                BodyKind::Fixed => continue,
                BodyKind::Kinematic { position_based } => {
                    bodies.set_pose(handle, &body_pose(&pose, &self.centers[i]), woken);
                    if position_based {
                        bodies.set_next_kinematic_pose(handle, &body.pose);
                    }
                }
                BodyKind::Dynamic { sleeping } => {
                    if sleeping && !woken {
                        continue;
                    }
                    let (v0, w0) = self.velocities[i];
                    let (v1, w1) = (body.linvel, body.angvel);
                    let (v, w) = (v0 + (v1 - v0) * fraction, w0 + (w1 - w0) * fraction);
                    bodies.set_pose(handle, &body_pose(&pose, &self.centers[i]), false);
                    bodies.set_velocities(handle, &v, &w, false);
                    if woken {
                        bodies.wake_up(handle);
                    }
                    self.velocities[i] = (v, w);
                }
            }
            self.start[i] = pose;
        }
        self.forget_bounds();
    }

    /// The pairs' distance bounds at the sweep's end, carried to the next
    /// sweep or step, are dropped: the guard moved bodies from there.
    fn forget_bounds(&mut self) {
        for pair in &mut self.world.pairs {
            pair.lower_bound = None;
        }
    }

    /// The dynamic bodies of the sweep's `stops` stay at their poses at
    /// their earliest stop for the rest of the step (or are carried by a
    /// kinematic body they touch, [`hold_or_carry`](Guard::hold_or_carry)),
    /// and each stopped pair takes an inelastic impulse at its contact (its
    /// two points' approach along the normal removed, by the bodies' masses
    /// and inertias: a bullet stopped at a corner turns about it). Returns
    /// whether a body stopped. `scale`: the sweep's real length over `dt`.
    pub(super) fn stop_bodies(&mut self, bodies: &mut B, stops: &[GuardHit], scale: Real) -> bool {
        if stops.is_empty() {
            return false;
        }
        let mut stopped = false;
        for i in 0..self.stoppable.len() {
            let first = stops.iter().filter(|s| s.a == i || s.b == i).map(|s| s.time).reduce(Real::min);
            if let (true, Some(at)) = (self.stoppable[i], first) {
                self.hold_or_carry(bodies, i, at.min(self.dt), scale);
                stopped = true;
            }
        }
        if !stopped {
            return false;
        }
        self.forget_bounds();
        for stop in stops {
            if let (Some(normal), Some(point)) = (stop.normal, stop.point) {
                self.inelastic_impulse(bodies, [stop.a, stop.b], &point, &normal);
            }
        }
        true
    }

    /// An inelastic impulse between bodies `a` and `b` at `point` along
    /// `normal` (from `a` towards `b`): the two bodies' points there stop
    /// approaching along it, by the dynamic bodies' masses and inertias
    /// (their turns change with it; a body the guard may not stop takes
    /// nothing).
    pub(super) fn inelastic_impulse(
        &self,
        bodies: &mut B,
        [a, b]: [usize; 2],
        point: &Point,
        normal: &Vector,
    ) {
        let (Some(view_a), Some(view_b)) = (bodies.view(self.handles[a]), bodies.view(self.handles[b]))
        else {
            return;
        };
        let impact = |i: usize, view: &BodyView| {
            let stoppable = self.stoppable[i];
            ImpactBody {
                // Where the body is now (the guard may just have moved it).
                center: Point::from(view.center_pose().translation.vector),
                inverse_mass: if stoppable { view.inverse_mass } else { 0.0 },
                inverse_inertia: if stoppable { view.inverse_inertia } else { nalgebra::Matrix3::zeros() },
                velocity: view.linvel,
                angular_velocity: view.angvel,
            }
        };
        let (mut body_a, mut body_b) = (impact(a, &view_a), impact(b, &view_b));
        if apply_impulse(&mut body_a, &mut body_b, point, normal, 0.0) > 0.0 {
            for (i, body) in [(a, body_a), (b, body_b)] {
                if self.stoppable[i] {
                    bodies.set_velocities(self.handles[i], &body.velocity, &body.angular_velocity, false);
                }
            }
        }
    }

    /// Body `i`, clamped at `at` into the sweep: held at its pose then, or,
    /// when it touches a kinematic body (which has infinite mass and goes
    /// on), carried by it from then to the step's end (their relative pose
    /// kept, velocities the kinematic body's), so it is pushed, not passed
    /// through. `scale`: the sweep's real length over `dt`.
    fn hold_or_carry(&mut self, bodies: &mut B, i: usize, at: Real, scale: Real) {
        let held = self.world.motions[i].pose_at(at);
        // A kinematic body in contact with it, and that body's view.
        let carrier = self.world.pairs.iter().filter(|p| p.touching.is_some()).find_map(|p| {
            let other = if p.a == i {
                p.b
            } else if p.b == i {
                p.a
            } else {
                return None;
            };
            let body = bodies.view(self.handles[other])?;
            matches!(body.kind, BodyKind::Kinematic { .. }).then_some((other, body))
        });
        let Some((k, carrier)) = carrier else {
            bodies.set_pose(self.handles[i], &body_pose(&held, &self.centers[i]), true);
            return;
        };
        let (k_at, k_end) = (self.world.motions[k].pose_at(at), self.world.motions[k].pose_at(self.dt));
        let carried = k_end * k_at.inverse() * held;
        let (v_k, w_k) = (carrier.linvel, carrier.angvel);
        let velocity = v_k + w_k.cross(&(carried.translation.vector - k_end.translation.vector));
        self.world.motions[i] = StepMotion::between_near(&self.start[i], &carried, self.dt, &(w_k * scale));
        bodies.set_pose(self.handles[i], &body_pose(&carried, &self.centers[i]), true);
        bodies.set_velocities(self.handles[i], &velocity, &w_k, true);
    }
}

/// Whether the body `handle` is kinematic.
pub(super) fn is_kinematic<B: RapierBodies>(bodies: &B, handle: B::Handle) -> bool {
    bodies.view(handle).is_some_and(|body| matches!(body.kind, BodyKind::Kinematic { .. }))
}
