//! From the parsed file to a validated [`Scene`].

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Translation3, UnitQuaternion};

use super::file::{
    BodySettings, ExpectSettings, FormulaSettings, KernelSettings, MeshSettings, OnContact,
    OrientationSettings, SceneFile, TracePairs, Triple,
};
use super::{Body, BodyMotion, Expectation, Scene, SceneError, TraceSpec};
use crate::ccd::CcdOptions;
use crate::kernels::PointEdgeFormula;
use crate::math::{Point, Pose, Real, Vector};
use crate::mesh::{self, DistanceKernel, TriMesh, MAX_ICOSPHERE_SUBDIVISIONS};
use crate::motion::{Dynamics, Spring, MAX_TURN_PER_STEP};

/// Parses `text` (named `source` in messages; OBJ paths relative to `base`).
pub(super) fn build(text: &str, source: &str, base: &Path) -> Result<Scene> {
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: SceneFile = options.from_str(text).map_err(|e| SceneError::Syntax {
        path: source.to_string(),
        line: e.span.start.line,
        column: e.span.start.col,
        message: e.code.to_string(),
    })?;
    Builder { source }.scene(file, base)
}

struct Builder<'a> {
    source: &'a str,
}

type Result<T> = std::result::Result<T, SceneError>;

impl Builder<'_> {
    fn invalid<T>(&self, field: impl Into<String>, message: impl Into<String>) -> Result<T> {
        Err(SceneError::Invalid {
            path: self.source.to_string(),
            field: field.into(),
            message: message.into(),
        })
    }

    fn finite(&self, field: &str, value: f64) -> Result<Real> {
        if value.is_finite() {
            Ok(value)
        } else {
            self.invalid(field, format!("expected a finite number, found {value}"))
        }
    }

    fn positive(&self, field: &str, value: f64) -> Result<Real> {
        if self.finite(field, value)? > 0.0 {
            Ok(value)
        } else {
            self.invalid(field, format!("must be positive, found {value}"))
        }
    }

    fn non_negative(&self, field: &str, value: f64) -> Result<Real> {
        if self.finite(field, value)? >= 0.0 {
            Ok(value)
        } else {
            self.invalid(field, format!("must be zero or positive, found {value}"))
        }
    }

    fn vector(&self, field: &str, value: &Triple) -> Result<Vector> {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            self.finite(&format!("{field}.{axis}"), value[k])?;
        }
        Ok(Vector::from(*value))
    }

    fn scene(&self, file: SceneFile, base: &Path) -> Result<Scene> {
        if file.name.trim().is_empty() || file.name.contains(['/', '\\']) || file.name.starts_with('.') {
            return self.invalid(
                "name",
                "must be a non-empty name usable as a folder name (no `/`, no leading `.`)",
            );
        }
        let dt = self.positive("dt", file.dt)?;
        let steps = match (file.duration, file.steps) {
            (Some(_), Some(_)) => return self.invalid("steps", "give `duration` or `steps`, not both"),
            (None, None) => return self.invalid("duration", "give `duration` (time) or `steps` (a count)"),
            (None, Some(0)) => return self.invalid("steps", "must be at least 1"),
            (None, Some(steps)) => steps,
            (Some(duration), None) => {
                let duration = self.positive("duration", duration)?;
                if duration / dt > 1e12 {
                    return self
                        .invalid("duration", format!("{} steps of dt = {dt}: too many", duration / dt));
                }
                super::steps_for(duration, dt)
            }
        };

        let settings = &file.ccd;
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

        if file.bodies.is_empty() {
            return self.invalid("bodies", "a scene needs at least one body");
        }
        let mut names: HashMap<&str, usize> = HashMap::new();
        for (i, body) in file.bodies.iter().enumerate() {
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
        let lookup = |field: String, name: &str| match names.get(name) {
            Some(&i) => Ok(i),
            None => self.invalid(field, format!("no body is named `{name}`")),
        };

        let gravity = match &file.gravity {
            Some(g) => self.vector("gravity", g)?,
            None => Vector::zeros(),
        };
        let mut assets: HashMap<String, Arc<TriMesh>> = HashMap::new();
        let mut bodies = Vec::with_capacity(file.bodies.len());
        let mut centers = Vec::with_capacity(file.bodies.len());
        for (i, settings) in file.bodies.iter().enumerate() {
            let (body, center) = self.body(i, settings, base, &mut assets)?;
            bodies.push(body);
            centers.push(center);
        }

        // Springs, then each body's motion.
        let mut springs: Vec<Vec<Spring>> = vec![Vec::new(); bodies.len()];
        for (k, spring) in file.springs.iter().enumerate() {
            let field = |name: &str| format!("springs[{k}].{name}");
            let i = lookup(field("body"), &spring.body)?;
            let point = self.vector(&field("point"), &spring.point)? - centers[i];
            let body = &bodies[i];
            let settings = &file.bodies[i];
            if settings.fixed || settings.kinematic {
                return self.invalid(
                    field("body"),
                    format!("`{}` is fixed or kinematic: a spring cannot move it", body.name),
                );
            }
            if body.mass.is_none() {
                return self.invalid(
                    field("body"),
                    format!("`{}` needs a `mass` (or `density`) to hang on a spring", body.name),
                );
            }
            if point.norm() > 0.0 && body.inertia.is_none() {
                return self.invalid(
                    field("point"),
                    format!(
                        "the attachment is off the centre of mass of `{}`, so the spring makes a torque: the body needs `inertia` or `density`",
                        body.name
                    ),
                );
            }
            springs[i].push(Spring {
                point,
                anchor: Point::from(self.vector(&field("anchor"), &spring.anchor)?),
                stiffness: self.non_negative(&field("stiffness"), spring.stiffness)?,
                damping: self.non_negative(&field("damping"), spring.damping)?,
                rest_length: self.non_negative(&field("rest_length"), spring.rest_length)?,
            });
        }
        let bounce = match file.on_contact {
            OnContact::Bounce { restitution } => {
                if !(0.0..=1.0).contains(&restitution) {
                    return self.invalid(
                        "on_contact.restitution",
                        format!("{restitution} is not a coefficient of restitution: give a number in [0, 1]"),
                    );
                }
                true
            }
            _ => false,
        };
        for (i, body) in bodies.iter_mut().enumerate() {
            let settings = &file.bodies[i];
            if bounce
                && !settings.fixed
                && !settings.kinematic
                && (body.mass.is_none() || body.inertia.is_none())
            {
                return self.invalid(
                    format!("bodies[{i}].density"),
                    format!(
                        "`{}` can be pushed by a bounce (`on_contact: Bounce`), so it needs a mass and an inertia: give `density`, or `mass` and `inertia` (or make it `fixed` or `kinematic`)",
                        body.name
                    ),
                );
            }
            body.motion = if settings.fixed {
                if body.velocity.norm() > 0.0 || body.angular_velocity.norm() > 0.0 {
                    return self.invalid(format!("bodies[{i}].fixed"), "a fixed body cannot have a velocity");
                }
                BodyMotion::Fixed
            } else if settings.kinematic {
                BodyMotion::Free
            } else {
                let omega_body = body.pose.rotation.inverse_transform_vector(&body.angular_velocity);
                let precesses = body.inertia.is_some_and(|inertia| {
                    let momentum = inertia * omega_body;
                    momentum.cross(&omega_body).norm()
                        > 64.0 * Real::EPSILON * momentum.norm() * omega_body.norm()
                });
                // A bouncing body's spin changes at every bounce: integrated,
                // so that it precesses.
                if gravity.norm() > 0.0 || !springs[i].is_empty() || precesses || bounce {
                    let turn = body.angular_velocity.norm() * dt;
                    if turn >= MAX_TURN_PER_STEP {
                        return self.invalid(
                            format!("bodies[{i}].angular_velocity"),
                            format!(
                                "the body turns {turn:.3} rad per step (|ω| dt); an integrated body must turn less than π/2 per step: lower `dt`"
                            ),
                        );
                    }
                    BodyMotion::Integrated(Dynamics {
                        inverse_mass: body.mass.map_or(0.0, |m| 1.0 / m),
                        inertia: body.inertia,
                        gravity,
                        springs: std::mem::take(&mut springs[i]),
                    })
                } else {
                    BodyMotion::Free
                }
            };
        }

        let trace = match &file.trace {
            None => None,
            Some(trace) => {
                if trace.every == 0 {
                    return self.invalid("trace.every", "must be at least 1");
                }
                let pairs = match &trace.pairs {
                    TracePairs::All => {
                        let fixed = |i: usize| bodies[i].motion == BodyMotion::Fixed;
                        let n = bodies.len();
                        (0..n)
                            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                            .filter(|&(i, j)| !(fixed(i) && fixed(j)))
                            .collect()
                    }
                    TracePairs::Only(list) => {
                        let mut pairs = Vec::with_capacity(list.len());
                        for (k, (a, b)) in list.iter().enumerate() {
                            let field = format!("trace.pairs[{k}]");
                            let (i, j) = (lookup(field.clone(), a)?, lookup(field.clone(), b)?);
                            if i == j {
                                return self.invalid(field, "a pair needs two different bodies");
                            }
                            pairs.push((i.min(j), i.max(j)));
                        }
                        pairs
                    }
                };
                Some(TraceSpec { pairs, every: trace.every, reference: false })
            }
        };

        let plot = match &file.plot {
            None => None,
            Some(_) if trace.is_none() => {
                return self.invalid("plot", "the plot draws the distance trace: add `trace: (pairs: All)`")
            }
            Some(plot) => Some(super::PlotSpec { log_y: plot.log_y }),
        };

        let expect = match &file.expect {
            None => None,
            Some(ExpectSettings::NoContact) => Some(Expectation::NoContact),
            Some(ExpectSettings::Contact { time, tolerance, bodies: (a, b) }) => {
                let (i, j) = (lookup("expect.bodies".into(), a)?, lookup("expect.bodies".into(), b)?);
                if i == j {
                    return self.invalid("expect.bodies", "a contact needs two different bodies");
                }
                Some(Expectation::Contact {
                    time: self.non_negative("expect.time", *time)?,
                    tolerance: self.non_negative("expect.tolerance", *tolerance)?,
                    bodies: (i.min(j), i.max(j)),
                })
            }
        };

        Ok(Scene {
            name: file.name,
            source: self.source.to_string(),
            dt,
            steps,
            duration: file.duration.unwrap_or(steps as Real * dt),
            integrator: file.integrator,
            gyroscopic: file.gyroscopic,
            ccd,
            kernel,
            on_contact: file.on_contact,
            trace,
            plot,
            bodies,
            expect,
            parameters: Default::default(),
        })
    }

    /// A body and the offset of its centre of mass from its mesh's origin.
    fn body(
        &self,
        i: usize,
        settings: &BodySettings,
        base: &Path,
        assets: &mut HashMap<String, Arc<TriMesh>>,
    ) -> Result<(Body, Vector)> {
        let field = |name: &str| format!("bodies[{i}].{name}");
        let scale = self.positive(&field("scale"), settings.scale)?;
        let position = self.vector(&field("position"), &settings.position)?;
        let velocity = self.vector(&field("velocity"), &settings.velocity)?;
        let angular_velocity = self.vector(&field("angular_velocity"), &settings.angular_velocity)?;
        let rotation = self.orientation(&field("orientation"), &settings.orientation)?;

        let key = format!("{:?}|{scale:e}", settings.mesh);
        let mesh_field = field("mesh");
        let shape = match assets.get(&key) {
            Some(shape) => shape.clone(),
            None => {
                let built = self.mesh(&mesh_field, &settings.mesh, base)?;
                let scaled = if scale == 1.0 {
                    built
                } else {
                    built.scaled(scale).or_else(|e| {
                        self.invalid(field("scale"), format!("the scaled mesh is unusable: {e}"))
                    })?
                };
                let shape = Arc::new(scaled);
                assets.insert(key.clone(), shape.clone());
                shape
            }
        };

        let (mut mass, mut inertia, mut center) = (None, None, Vector::zeros());
        if let Some(m) = settings.mass {
            mass = Some(self.positive(&field("mass"), m)?);
        }
        if let Some(moments) = &settings.inertia {
            let m = self.vector(&field("inertia"), moments)?;
            if m.min() <= 0.0 {
                return self.invalid(field("inertia"), "principal moments must be positive");
            }
            if m.x + m.y < m.z || m.y + m.z < m.x || m.z + m.x < m.y {
                return self.invalid(
                    field("inertia"),
                    "no rigid body has these moments: each must be at most the sum of the other two",
                );
            }
            inertia = Some(Matrix3::from_diagonal(&m));
        }
        let shape = match settings.density {
            None => shape,
            Some(density) => {
                let density = self.positive(&field("density"), density)?;
                if settings.mass.is_some() || settings.inertia.is_some() {
                    return self
                        .invalid(field("density"), "give `density`, or `mass` and `inertia`, not both");
                }
                let Some(props) = shape.mass_properties() else {
                    return self.invalid(
                        field("density"),
                        "the mesh encloses no positive volume (open, or triangles facing inward): mass properties need a closed mesh",
                    );
                };
                mass = Some(density * props.volume);
                inertia = Some(props.inertia * density);
                center = props.center_of_mass.coords;
                // The recentred mesh is an asset of its own, shared likewise.
                let centered = format!("{key}|centred");
                assets
                    .entry(centered)
                    .or_insert_with(|| Arc::new(shape.recentered(&props.center_of_mass)))
                    .clone()
            }
        };

        let pose = Pose::from_parts(Translation3::from(position + rotation * center), rotation);
        let body = Body {
            name: settings.name.clone(),
            mesh: shape,
            pose,
            velocity,
            angular_velocity,
            mass,
            inertia,
            motion: BodyMotion::Free,
        };
        Ok((body, center))
    }

    fn mesh(&self, field: &str, settings: &MeshSettings, base: &Path) -> Result<TriMesh> {
        let sub = |name: &str| format!("{field}.{name}");
        let built = match settings {
            MeshSettings::Box { half_extents } => {
                let h = self.vector(&sub("half_extents"), half_extents)?;
                if h.min() <= 0.0 {
                    return self.invalid(
                        sub("half_extents"),
                        format!("must all be positive, found {half_extents:?}"),
                    );
                }
                mesh::box_mesh(&h)
            }
            MeshSettings::Icosphere { radius, subdivisions } => {
                let radius = self.positive(&sub("radius"), *radius)?;
                if *subdivisions > MAX_ICOSPHERE_SUBDIVISIONS {
                    return self.invalid(
                        sub("subdivisions"),
                        format!("at most {MAX_ICOSPHERE_SUBDIVISIONS}, found {subdivisions}"),
                    );
                }
                mesh::icosphere(radius, *subdivisions)
            }
            MeshSettings::Tetrahedron { circumradius } => {
                mesh::tetrahedron(self.positive(&sub("circumradius"), *circumradius)?)
            }
            MeshSettings::Triangle { a, b, c } => mesh::single_triangle(
                Point::from(self.vector(&sub("a"), a)?),
                Point::from(self.vector(&sub("b"), b)?),
                Point::from(self.vector(&sub("c"), c)?),
            ),
            MeshSettings::Needle { length, width } => {
                mesh::needle(self.positive(&sub("length"), *length)?, self.positive(&sub("width"), *width)?)
            }
            MeshSettings::Obj { path } => {
                return mesh::load_obj(&base.join(path)).or_else(|e| self.invalid(field, e.to_string()));
            }
        };
        built.or_else(|e| self.invalid(field, e.to_string()))
    }

    fn orientation(&self, field: &str, settings: &OrientationSettings) -> Result<UnitQuaternion<Real>> {
        match settings {
            OrientationSettings::Identity => Ok(UnitQuaternion::identity()),
            OrientationSettings::AxisAngle { axis, degrees } => {
                let axis = self.vector(&format!("{field}.axis"), axis)?;
                let degrees = self.finite(&format!("{field}.degrees"), *degrees)?;
                if degrees == 0.0 {
                    return Ok(UnitQuaternion::identity());
                }
                match nalgebra::Unit::try_new(axis, 0.0) {
                    Some(axis) => Ok(UnitQuaternion::from_axis_angle(&axis, degrees.to_radians())),
                    None => self.invalid(format!("{field}.axis"), "the axis must not be zero"),
                }
            }
            OrientationSettings::Quaternion { w, x, y, z } => {
                let q = Quaternion::new(*w, *x, *y, *z);
                let norm = q.norm();
                if !norm.is_finite() || norm == 0.0 {
                    return self
                        .invalid(field, format!("the quaternion ({w}, {x}, {y}, {z}) cannot be normalised"));
                }
                Ok(UnitQuaternion::from_quaternion(q))
            }
        }
    }
}
