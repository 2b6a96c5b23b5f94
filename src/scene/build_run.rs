//! What a scene's run does and records: its contact response and
//! materials, its trace, near misses and expectation, each checked.

use super::file::{
    BodySettings, ColliderSettings, ExpectSettings, OnContact, SceneFile, TracePairs, TraceSettings,
};
use super::{Body, BodyMotion, Expectation, TraceSpec};
use crate::math::shortest;
use crate::math::Real;

use super::build::{Builder, Names, Result, MAX_SKIN, MAX_SOLVER_ITERATIONS};

impl Builder<'_> {
    /// Whether the response pushes bodies (`Bounce`, `Simulate`), with its
    /// settings checked.
    pub(super) fn response(&self, on_contact: &OnContact) -> Result<bool> {
        match *on_contact {
            OnContact::Bounce { restitution } => {
                self.restitution("on_contact.restitution", restitution)?;
                Ok(true)
            }
            OnContact::Simulate { restitution, friction, solver_iterations, skin } => {
                if !cfg!(feature = "rapier") {
                    return self.invalid(
                        "on_contact",
                        "`Simulate` solves contacts with rapier3d: build nearmiss with the `rapier` feature (on by default)",
                    );
                }
                self.restitution("on_contact.restitution", restitution)?;
                self.non_negative("on_contact.friction", friction)?;
                if !(0.0..=MAX_SKIN).contains(&skin) {
                    return self.invalid(
                        "on_contact.skin",
                        format!(
                            "{} is not a contact skin: give a multiple of rapier's allowed linear error in [0, {MAX_SKIN}] (0: no skin)",
                            shortest(skin)
                        ),
                    );
                }
                if !(1..=MAX_SOLVER_ITERATIONS).contains(&solver_iterations) {
                    return self.invalid(
                        "on_contact.solver_iterations",
                        format!("must be between 1 and {MAX_SOLVER_ITERATIONS}, found {solver_iterations}"),
                    );
                }
                Ok(true)
            }
            _ => Ok(false),
        }
    }

    /// A coefficient of restitution, in `[0, 1]`.
    pub(super) fn restitution(&self, field: &str, restitution: Real) -> Result<Real> {
        if (0.0..=1.0).contains(&restitution) {
            return Ok(restitution);
        }
        self.invalid(
            field,
            format!("{} is not a coefficient of restitution: give a number in [0, 1]", shortest(restitution)),
        )
    }

    /// Each body's contact material under `Simulate` (refused elsewhere:
    /// no other response uses it).
    pub(super) fn materials(
        &self,
        on_contact: &OnContact,
        settings: &[BodySettings],
        bodies: &mut [Body],
    ) -> Result<()> {
        for (i, (settings, body)) in settings.iter().zip(bodies.iter_mut()).enumerate() {
            let OnContact::Simulate { restitution, friction, .. } = *on_contact else {
                for (field, given) in [("friction", settings.friction), ("restitution", settings.restitution)]
                {
                    if given.is_some() {
                        return self.invalid(
                            format!("bodies[{i}].{field}"),
                            format!("`{field}` is a material of `on_contact: Simulate` (rapier's contact solver); no other response uses it"),
                        );
                    }
                }
                continue;
            };
            let friction = match settings.friction {
                Some(own) => self.non_negative(&format!("bodies[{i}].friction"), own)?,
                None => friction,
            };
            let restitution = match settings.restitution {
                Some(own) => self.restitution(&format!("bodies[{i}].restitution"), own)?,
                None => restitution,
            };
            let triangle_mesh = settings.collider == ColliderSettings::TriMesh;
            body.material = Some(super::Material { friction, restitution, triangle_mesh });
        }
        Ok(())
    }

    /// The near misses asked for.
    pub(super) fn near_misses(
        &self,
        file: &SceneFile,
        names: &Names<'_>,
    ) -> Result<Option<super::NearMissSpec>> {
        let Some(settings) = &file.near_misses else { return Ok(None) };
        let within = self.positive("near_misses.within", settings.within)?;
        if matches!(file.on_contact, OnContact::Simulate { .. }) {
            return self.invalid(
                "near_misses",
                "not under `on_contact: Simulate` yet (rapier moves the bodies there): use Stop, Record or Bounce",
            );
        }
        let pairs = match &settings.pairs {
            TracePairs::All => None,
            TracePairs::Only(list) => Some(self.named_pairs("near_misses.pairs", list, names)?),
        };
        let tolerance = settings.tolerance.map(|t| self.positive("near_misses.tolerance", t)).transpose()?;
        Ok(Some(super::NearMissSpec { within, pairs, tolerance }))
    }

    /// Pairs given by body names, as indices `(i, j)`, `i < j`.
    pub(super) fn named_pairs(
        &self,
        field: &str,
        list: &[(String, String)],
        names: &Names<'_>,
    ) -> Result<Vec<(usize, usize)>> {
        let mut pairs = Vec::with_capacity(list.len());
        for (k, (a, b)) in list.iter().enumerate() {
            let field = format!("{field}[{k}]");
            let (i, j) = (self.lookup(names, field.clone(), a)?, self.lookup(names, field.clone(), b)?);
            if i == j {
                return self.invalid(field, "a pair needs two different bodies");
            }
            pairs.push((i.min(j), i.max(j)));
        }
        Ok(pairs)
    }

    pub(super) fn trace(
        &self,
        trace: Option<&TraceSettings>,
        names: &Names<'_>,
        bodies: &[Body],
        steps: u64,
    ) -> Result<Option<TraceSpec>> {
        let Some(trace) = trace else { return Ok(None) };
        if trace.every == 0 {
            return self.invalid("trace.every", "must be at least 1");
        }
        let pairs = match &trace.pairs {
            TracePairs::All => {
                let fixed = |i: usize| bodies[i].motion == BodyMotion::Fixed;
                let n = bodies.len();
                // Counted before they are listed: every pair of a large scene
                // would not fit in memory.
                let held = (0..n).filter(|&i| fixed(i)).count();
                let count = (n * n.saturating_sub(1) / 2 - held * held.saturating_sub(1) / 2) as u64;
                self.records_within_limit("trace", "pairs", count, (steps, trace.every))?;
                (0..n)
                    .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                    .filter(|&(i, j)| !(fixed(i) && fixed(j)))
                    .collect()
            }
            TracePairs::Only(list) => {
                let pairs = self.named_pairs("trace.pairs", list, names)?;
                self.records_within_limit("trace", "pairs", pairs.len() as u64, (steps, trace.every))?;
                pairs
            }
        };
        Ok(Some(TraceSpec { pairs, every: trace.every, reference: false }))
    }

    /// Refuses a trace or poses (`field`) of `count` pairs or bodies (`what`)
    /// sampled every `every` of `steps` steps that would keep more than
    /// [`MAX_RECORDS`](super::MAX_RECORDS) records.
    pub(super) fn records_within_limit(
        &self,
        field: &str,
        what: &str,
        count: u64,
        (steps, every): (u64, u64),
    ) -> Result<()> {
        let samples = steps / every + 2;
        let records = super::most_records(count, steps, every);
        if records <= super::MAX_RECORDS {
            return Ok(());
        }
        self.invalid(
            field,
            format!(
                "would keep {records} records ({count} {what} × {samples} samples), more than the limit of {}: {} or sample less often (`every`)",
                super::MAX_RECORDS,
                if field == "trace" { "trace fewer pairs (`pairs: Only([...])`)" } else { "record fewer steps" }
            ),
        )
    }

    /// What `nearmiss test` checks.
    pub(super) fn expect(
        &self,
        expect: Option<&ExpectSettings>,
        names: &Names<'_>,
        near_misses: Option<&super::NearMissSpec>,
    ) -> Result<Option<Expectation>> {
        match expect {
            None => Ok(None),
            Some(ExpectSettings::NoContact) => Ok(Some(Expectation::NoContact)),
            Some(ExpectSettings::Contact { time, tolerance, bodies: (a, b), recorded }) => {
                let field = || "expect.bodies".to_string();
                let (i, j) = (self.lookup(names, field(), a)?, self.lookup(names, field(), b)?);
                if i == j {
                    return self.invalid("expect.bodies", "a contact needs two different bodies");
                }
                Ok(Some(Expectation::Contact {
                    time: self.non_negative("expect.time", *time)?,
                    tolerance: self.non_negative("expect.tolerance", *tolerance)?,
                    bodies: (i.min(j), i.max(j)),
                    recorded: *recorded,
                }))
            }
            Some(ExpectSettings::NearMiss { bodies: (a, b), distance, tolerance }) => {
                let field = || "expect.bodies".to_string();
                let (i, j) = (self.lookup(names, field(), a)?, self.lookup(names, field(), b)?);
                if i == j {
                    return self.invalid("expect.bodies", "a near miss needs two different bodies");
                }
                let distance = self.non_negative("expect.distance", *distance)?;
                let tolerance = self.non_negative("expect.tolerance", *tolerance)?;
                let listed = near_misses.is_some_and(|spec| spec.within >= distance + tolerance);
                if !listed {
                    return self.invalid(
                        "expect",
                        format!(
                            "a near miss is checked from the run's near misses: add `near_misses: (within: {})` or more",
                            shortest(distance + tolerance)
                        ),
                    );
                }
                Ok(Some(Expectation::NearMiss { bodies: (i.min(j), i.max(j)), distance, tolerance }))
            }
        }
    }
}
