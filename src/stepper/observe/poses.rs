//! The bodies' poses over time (`poses.csv`), when a scene asks for them
//! (`poses: (every: n)`): each body's centre of mass and orientation after
//! every `n` steps (and at the start, the last step and a contact that ends
//! the run), so that a run can be replayed, checked or loaded into another
//! tool. A body's mesh vertices are relative to its centre of mass (for a
//! mesh with `density`, the file's origin is offset by the centre of mass).

use std::io::Write;

use crate::math::{Point, Real};
use crate::motion::StepMotion;
use nalgebra::UnitQuaternion;

/// One body's pose after a step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PoseRecord {
    /// The steps done (0: the initial state).
    pub step: u64,
    /// The time.
    pub time: Real,
    /// The body (index into the scene's bodies).
    pub body: usize,
    /// Its centre of mass.
    pub position: Point,
    /// Its orientation.
    pub orientation: UnitQuaternion<Real>,
}

/// Samples a run's poses.
#[derive(Debug)]
pub struct PoseObserver {
    every: u64,
    last_step: u64,
    records: Vec<PoseRecord>,
}

impl PoseObserver {
    /// The observer of a run of `steps` steps that records every `every`.
    pub fn new(every: u64, steps: u64) -> PoseObserver {
        PoseObserver { every: every.max(1), last_step: steps, records: Vec::new() }
    }

    /// After `step` steps (ending at `time`, the bodies at `s` into their
    /// step motions): records if the cadence asks for it.
    pub fn step_done(&mut self, step: u64, time: Real, s: Real, motions: &[StepMotion]) {
        if step.is_multiple_of(self.every) || step == self.last_step {
            self.sample(step, time, s, motions);
        }
    }

    /// Records every body at `s` into its step motion.
    pub fn sample(&mut self, step: u64, time: Real, s: Real, motions: &[StepMotion]) {
        for (body, motion) in motions.iter().enumerate() {
            let pose = motion.pose_at(s);
            self.records.push(PoseRecord {
                step,
                time,
                body,
                position: Point::from(pose.translation.vector),
                orientation: pose.rotation,
            });
        }
    }

    /// The samples taken.
    pub fn into_records(self) -> Vec<PoseRecord> {
        self.records
    }
}

/// Writes `step,time,body,x,y,z,qw,qx,qy,qz` lines with a header; numbers in
/// the shortest form that reads back to the same `f64`.
pub fn write_poses_csv(
    records: &[PoseRecord],
    bodies: &[String],
    out: &mut impl Write,
) -> std::io::Result<()> {
    writeln!(out, "step,time,body,x,y,z,qw,qx,qy,qz")?;
    for r in records {
        let (p, q) = (&r.position, r.orientation.quaternion());
        writeln!(
            out,
            "{},{:?},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
            r.step, r.time, bodies[r.body], p.x, p.y, p.z, q.w, q.i, q.j, q.k
        )?;
    }
    Ok(())
}
