//! From the parsed file to a validated [`Scene`]: the scene's own settings
//! here, its bodies (meshes, mass, springs, motion) in `build_body.rs`.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use super::file::{BodySettings, CcdSettings, FormulaSettings, KernelSettings, OnContact, SceneFile, Triple};
use super::{Scene, SceneError};
use crate::ccd::CcdOptions;
use crate::kernels::PointEdgeFormula;
use crate::math::shortest;
use crate::math::{Real, Vector};
use crate::mesh::DistanceKernel;

/// Parses `text` (named `source` in messages; OBJ paths relative to `base`).
pub(super) fn build(text: &str, source: &str, base: &Path) -> Result<Scene> {
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: SceneFile = options.from_str(text).map_err(|e| SceneError::Syntax {
        path: source.to_string(),
        line: e.span.start.line,
        column: e.span.start.col,
        message: syntax_message(text, &e),
    })?;
    Builder { source }.scene(file, base)
}

/// ron's message for a syntax error, with what to write where a
/// response's settings were left out (`on_contact: Simulate` for
/// `Simulate()`).
fn syntax_message(text: &str, error: &ron::error::SpannedError) -> String {
    let message = error.code.to_string();
    if !matches!(error.code, ron::Error::ExpectedStructLike | ron::Error::ExpectedNamedStructLike(_)) {
        return message;
    }
    let line = text.lines().nth(error.span.start.line.saturating_sub(1)).unwrap_or("");
    let before: String = line.chars().take(error.span.start.col.saturating_sub(1)).collect();
    let word = before.trim_end().rsplit(|c: char| !c.is_alphanumeric()).next().unwrap_or("");
    match word {
        "Simulate" => format!("{message}: `Simulate` takes its settings in parentheses, `Simulate()` for the defaults or e.g. `Simulate(friction: 0.3, restitution: 0.2)`"),
        "Bounce" => format!("{message}: `Bounce` takes its restitution, e.g. `Bounce(restitution: 1.0)`"),
        _ => message,
    }
}

pub(super) struct Builder<'a> {
    source: &'a str,
}

/// The usable range of a scene's numbers: every coordinate, velocity,
/// size, time and force parameter is at most this in magnitude, so that
/// the products the kernels and mass properties form (up to fifth powers of
/// a size) stay finite. `1e30`.
pub const MAX_MAGNITUDE: Real = 1e30;

/// The smallest positive size, time step or tolerance a scene may give (a
/// size's square and cube stay normal numbers). `1e-30`.
pub const MIN_MAGNITUDE: Real = 1e-30;

/// The longest scene name, in bytes: it names the output folder, and file
/// systems allow 255 bytes with room left for a temporary suffix.
pub const MAX_NAME_BYTES: usize = 200;

/// The largest contact skin `on_contact: Simulate` accepts, in multiples of
/// rapier's allowed linear error: `100` (half a unit under rapier's
/// defaults: a skin is a thin layer, not a body).
pub const MAX_SKIN: Real = 100.0;

/// The most solver iterations per step `on_contact: Simulate` accepts
/// (rapier's default is 4; more than this is most likely a typo, and each
/// costs a solver pass).
pub const MAX_SOLVER_ITERATIONS: usize = 1000;

/// Body indices by name.
pub(super) type Names<'f> = HashMap<&'f str, usize>;

pub(super) type Result<T> = std::result::Result<T, SceneError>;

impl Builder<'_> {
    pub(super) fn invalid<T>(&self, field: impl Into<String>, message: impl Into<String>) -> Result<T> {
        Err(SceneError::Invalid {
            path: self.source.to_string(),
            field: field.into(),
            message: message.into(),
        })
    }

    /// A finite number within the usable range `|x| ≤ MAX_MAGNITUDE`.
    pub(super) fn finite(&self, field: &str, value: f64) -> Result<Real> {
        if !value.is_finite() {
            return self.invalid(field, format!("expected a finite number, found {}", shortest(value)));
        }
        if value.abs() > MAX_MAGNITUDE {
            return self.invalid(
                field,
                format!(
                    "{} is outside the usable range: |x| ≤ {MAX_MAGNITUDE:e} (products of coordinates must stay finite)",
                    shortest(value)
                ),
            );
        }
        Ok(value)
    }

    /// A positive number within `[MIN_MAGNITUDE, MAX_MAGNITUDE]`.
    pub(super) fn positive(&self, field: &str, value: f64) -> Result<Real> {
        if self.finite(field, value)? <= 0.0 {
            return self.invalid(field, format!("must be positive, found {}", shortest(value)));
        }
        if value < MIN_MAGNITUDE {
            return self.invalid(
                field,
                format!(
                    "{} is below the usable range: at least {MIN_MAGNITUDE:e} (squares of sizes must stay normal numbers)",
                    shortest(value)
                ),
            );
        }
        Ok(value)
    }

    /// A mass or a moment of inertia: positive, and both it and its inverse
    /// normal numbers (not subnormal, not infinite), so that forces and
    /// impulses stay finite.
    pub(super) fn invertible(&self, field: &str, value: f64) -> Result<Real> {
        if !(value.is_finite() && value > 0.0) {
            return self
                .invalid(field, format!("must be a positive finite number, found {}", shortest(value)));
        }
        // Both the value and its inverse normal numbers.
        let (smallest, largest) = (Real::MIN_POSITIVE, 1.0 / Real::MIN_POSITIVE);
        if (smallest..=largest).contains(&value) {
            Ok(value)
        } else {
            self.invalid(
                field,
                format!(
                    "{} is too small or too large for a mass or moment (it and its inverse must be normal numbers): give a value between {smallest:e} and {largest:e}",
                    crate::math::shortest(value)
                ),
            )
        }
    }

    pub(super) fn non_negative(&self, field: &str, value: f64) -> Result<Real> {
        if self.finite(field, value)? >= 0.0 {
            Ok(value)
        } else {
            self.invalid(field, format!("must be zero or positive, found {}", shortest(value)))
        }
    }

    pub(super) fn vector(&self, field: &str, value: &Triple) -> Result<Vector> {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            self.finite(&format!("{field}.{axis}"), value[k])?;
        }
        Ok(Vector::from(*value))
    }

    /// The scene: each part checked in turn (the first error is reported).
    fn scene(&self, file: SceneFile, base: &Path) -> Result<Scene> {
        self.check_name(&file.name)?;
        let dt = self.positive("dt", file.dt)?;
        let steps = self.steps(&file, dt)?;
        let (ccd, kernel) = self.ccd(&file.ccd)?;
        let names = self.body_names(&file.bodies)?;
        let gravity = match &file.gravity {
            Some(g) => self.vector("gravity", g)?,
            None => Vector::zeros(),
        };
        let (mut bodies, centers) = self.bodies(&file.bodies, base)?;
        let springs = self.springs(&file, &names, &bodies, &centers)?;
        let pushed_by_contacts = self.response(&file.on_contact)?;
        self.motions(&file.bodies, &mut bodies, springs, gravity, pushed_by_contacts, dt)?;
        let stops_kinematic = match &file.on_contact {
            OnContact::Bounce { .. } => Some("Bounce"),
            OnContact::Simulate { .. } => Some("Simulate"),
            _ => None,
        };
        self.paths(&file.bodies, &mut bodies, &centers, dt, stops_kinematic)?;
        self.materials(&file.on_contact, &file.bodies, &mut bodies)?;
        let trace = self.trace(file.trace.as_ref(), &names, &bodies, steps)?;
        let poses = match &file.poses {
            None => None,
            Some(poses) => match poses.every {
                Some(0) => return self.invalid("poses.every", "must be at least 1"),
                Some(every) => Some(super::PosesSpec { every }),
                None => Some(super::PosesSpec { every: trace.as_ref().map_or(1, |t| t.every) }),
            },
        };
        if let Some(poses) = &poses {
            self.records_within_limit("poses", "bodies", bodies.len() as u64, (steps, poses.every))?;
        }
        let plot = match &file.plot {
            None => None,
            Some(_) if trace.is_none() => {
                return self.invalid("plot", "the plot draws the distance trace: add `trace: (pairs: All)`")
            }
            Some(_) if bodies.len() < 2 => {
                return self.invalid("plot", "the scene has one body: there is no pair to trace or plot")
            }
            Some(_) if trace.as_ref().is_some_and(|t| t.pairs.is_empty()) => {
                return self.invalid(
                    "plot",
                    "the trace has no pair to draw (every pair of bodies is fixed): remove `plot`, or trace a pair that moves",
                )
            }
            Some(plot) if plot.contacts.contains(&0) => {
                return self.invalid("plot.contacts", "contacts are numbered from 1 (the first reported)")
            }
            Some(plot) => Some(super::PlotSpec { log_y: plot.log_y, contacts: plot.contacts.clone() }),
        };
        if file.initial_overlap == super::InitialOverlapPolicy::Refuse {
            if let Some(overlap) = super::initial_overlaps(&bodies).first() {
                return self.invalid(
                    format!("bodies[{}]", overlap.body_b),
                    format!(
                        "{} at t = 0, and the scene says `initial_overlap: Refuse`: move them apart",
                        overlap.describe(&bodies)
                    ),
                );
            }
        }
        let near_misses = self.near_misses(&file, &names)?;
        let expect = self.expect(file.expect.as_ref(), &names, near_misses.as_ref())?;
        Ok(Scene {
            model: super::Model {
                dt,
                integrator: file.integrator,
                gyroscopic: file.gyroscopic,
                ccd,
                kernel,
                on_contact: file.on_contact,
                gravity,
                bodies: Arc::new(bodies),
                parameters: Default::default(),
            },
            run: super::RunSpec {
                name: file.name,
                source: self.source.to_string(),
                steps,
                duration: file.duration.unwrap_or(steps as Real * dt),
                trace,
                plot,
                expect,
                poses,
                steps_given: file.steps.is_some(),
                near_misses,
                up: file.up.unwrap_or_else(|| super::Axis::against(&gravity)),
            },
        })
    }

    fn check_name(&self, name: &str) -> Result<()> {
        if name.trim().is_empty()
            || name.contains(['/', '\\'])
            || name.starts_with('.')
            || name.chars().any(char::is_control)
        {
            return self.invalid(
                "name",
                "must be a non-empty name usable as a folder name (no `/` or `\\`, no leading `.`, no control characters)",
            );
        }
        if name.len() > MAX_NAME_BYTES {
            return self.invalid(
                "name",
                format!("is {} bytes long; at most {MAX_NAME_BYTES} fit in a folder name", name.len()),
            );
        }
        Ok(())
    }

    /// The number of steps, from `steps` or `duration`.
    fn steps(&self, file: &SceneFile, dt: Real) -> Result<u64> {
        match (file.duration, file.steps) {
            (Some(_), Some(_)) => self.invalid("steps", "give `duration` or `steps`, not both"),
            (None, None) => self.invalid("duration", "give `duration` (time) or `steps` (a count)"),
            (None, Some(0)) => self.invalid("steps", "must be at least 1"),
            (None, Some(steps)) => Ok(steps),
            (Some(duration), None) => {
                let duration = self.positive("duration", duration)?;
                if duration / dt > 1e12 {
                    return self.invalid(
                        "duration",
                        format!(
                            "{} / dt {} is {:.1e} steps: too many (check `dt` and `duration`)",
                            shortest(duration),
                            shortest(dt),
                            duration / dt
                        ),
                    );
                }
                Ok(super::steps_for(duration, dt))
            }
        }
    }

    /// The CCD options and kernel.
    fn ccd(&self, settings: &CcdSettings) -> Result<(CcdOptions, DistanceKernel)> {
        let ccd = CcdOptions {
            distance_tolerance: self.positive("ccd.distance_tolerance", settings.distance_tolerance)?,
            minimum_separation: self.non_negative("ccd.minimum_separation", settings.minimum_separation)?,
            max_iterations: settings.max_iterations,
        };
        if ccd.max_iterations == 0 {
            return self.invalid("ccd.max_iterations", "must be at least 1");
        }
        let kernel = match settings.kernel {
            KernelSettings::Exact => DistanceKernel::Exact,
            KernelSettings::Dyop { formula } => DistanceKernel::Dyop(match formula {
                FormulaSettings::Vector => PointEdgeFormula::Vector,
                FormulaSettings::PlainVector => PointEdgeFormula::PlainVector,
                FormulaSettings::Heron => PointEdgeFormula::Heron,
                FormulaSettings::StableHeron => PointEdgeFormula::StableHeron,
            }),
        };
        Ok((ccd, kernel))
    }

    /// Each body's index by name (at least one body; names non-empty and unique).
    fn body_names<'f>(&self, bodies: &'f [BodySettings]) -> Result<Names<'f>> {
        if bodies.is_empty() {
            return self.invalid("bodies", "a scene needs at least one body");
        }
        let mut names: Names = HashMap::new();
        for (i, body) in bodies.iter().enumerate() {
            if body.name.is_empty() {
                return self.invalid(format!("bodies[{i}].name"), "must not be empty");
            }
            if let Some(first) = names.insert(&body.name, i) {
                return self.invalid(
                    format!("bodies[{i}].name"),
                    format!("`{}` is already the name of bodies[{first}]", body.name),
                );
            }
        }
        Ok(names)
    }

    /// The body named `name`, for `field`.
    pub(super) fn lookup(&self, names: &Names<'_>, field: String, name: &str) -> Result<usize> {
        match names.get(name) {
            Some(&i) => Ok(i),
            None => self.invalid(field, format!("no body is named `{name}`")),
        }
    }
}
