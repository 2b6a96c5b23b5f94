//! Distance-over-time records and their CSV writer.

use std::io::Write;

use crate::math::Real;

/// One distance sample of a traced pair.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TraceRecord {
    /// The step after which it was taken (0: the initial state).
    pub step: u64,
    /// The time.
    pub time: Real,
    /// The pair (body indices).
    pub pair: (usize, usize),
    /// The distance between the two meshes (by the scene's kernel).
    pub distance: Real,
    /// The exact distance (rational arithmetic on the closest triangle
    /// pair, rounded), when the trace asks for it.
    pub reference: Option<Real>,
}

/// Writes `step,time,body_a,body_b,distance` lines with a header; numbers
/// in the shortest form that reads back to the same `f64`.
pub fn write_trace_csv(
    records: &[TraceRecord],
    bodies: &[String],
    out: &mut impl Write,
) -> std::io::Result<()> {
    writeln!(out, "step,time,body_a,body_b,distance")?;
    for r in records {
        writeln!(out, "{},{:?},{},{},{:?}", r.step, r.time, bodies[r.pair.0], bodies[r.pair.1], r.distance)?;
    }
    Ok(())
}
