//! The bodies of a scene: meshes (shared assets), mass properties, springs
//! and how each body moves.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Translation3, UnitQuaternion};

use super::build::{Builder, Names, Result};
use super::build::{MAX_MAGNITUDE, MIN_MAGNITUDE};
use super::file::{BodySettings, MeshSettings, OrientationSettings, SceneFile};
use super::{Body, BodyMotion};
use crate::math::shortest;
use crate::math::{Point, Pose, Real, Vector};
use crate::mesh::{self, TriMesh, MAX_ICOSPHERE_SUBDIVISIONS};
use crate::motion::classify::{needs_integration, spin_precesses, Influences};
use crate::motion::{Spring, MAX_TURN_PER_STEP};

/// A keyframe's time is on a step when it is within this fraction of
/// itself of a whole number of `dt`: `1e-9` (times written in decimals,
/// `0.3` with `dt: 0.1`); it is then taken as that step's time.
pub const KEYFRAME_TIME_TOLERANCE: Real = 1e-9;

/// Two keyframes' orientations must differ by less than half a turn by at
/// least this angle: `1e-9` rad (a segment turns the short way; half a
/// turn has no short way).
pub const KEYFRAME_TURN_MARGIN: Real = 1e-9;

/// The most segments a `Torus` mesh takes along either direction
/// (4096 × 4096 × 2 triangles, about 33 million, is already too many to
/// run). `4096`.
pub const MAX_TORUS_SEGMENTS: u32 = 4096;

impl Builder<'_> {
    /// `components` (finite, any size) divided by their largest magnitude,
    /// or `None` if all are zero.
    fn direction<const N: usize>(&self, field: &str, components: [f64; N]) -> Result<Option<[Real; N]>> {
        if let Some(bad) = components.iter().find(|c| !c.is_finite()) {
            return self.invalid(field, format!("expected finite numbers, found {}", shortest(*bad)));
        }
        let largest = components.iter().fold(0.0, |m: Real, c| m.max(c.abs()));
        Ok((largest > 0.0).then(|| components.map(|c| c / largest)))
    }

    /// A mesh whose coordinates lie in the usable range (see
    /// [`MAX_MAGNITUDE`]) and whose extent is at least [`MIN_MAGNITUDE`].
    fn check_mesh_range(&self, field: &str, mesh: &TriMesh) -> Result<()> {
        let largest = mesh.vertices().iter().fold(0.0, |m: Real, v| m.max(v.coords.amax()));
        if largest > MAX_MAGNITUDE {
            return self.invalid(
                field,
                format!(
                    "a vertex lies {} from the mesh's origin, outside the usable range {MAX_MAGNITUDE:e} (scale included)",
                    shortest(largest)
                ),
            );
        }
        let (lo, hi) = mesh
            .vertices()
            .iter()
            .fold((Vector::repeat(Real::INFINITY), Vector::repeat(Real::NEG_INFINITY)), |(lo, hi), v| {
                (lo.inf(&v.coords), hi.sup(&v.coords))
            });
        let extent = (hi - lo).amax();
        if extent < MIN_MAGNITUDE {
            return self.invalid(
                field,
                format!(
                    "the mesh is {} across, below the usable size {MIN_MAGNITUDE:e} (scale included)",
                    shortest(extent)
                ),
            );
        }
        Ok(())
    }

    /// Every body, and each one's centre of mass offset from its mesh's origin.
    pub(super) fn bodies(&self, settings: &[BodySettings], base: &Path) -> Result<(Vec<Body>, Vec<Vector>)> {
        let mut assets = Assets::default();
        let mut bodies = Vec::with_capacity(settings.len());
        let mut centers = Vec::with_capacity(settings.len());
        for (i, settings) in settings.iter().enumerate() {
            let (body, center) = self.body(i, settings, base, &mut assets)?;
            bodies.push(body);
            centers.push(center);
        }
        Ok((bodies, centers))
    }

    /// Each body's springs (attachment points relative to its centre of mass).
    pub(super) fn springs(
        &self,
        file: &SceneFile,
        names: &Names<'_>,
        bodies: &[Body],
        centers: &[Vector],
    ) -> Result<Vec<Vec<Spring>>> {
        let mut springs: Vec<Vec<Spring>> = vec![Vec::new(); bodies.len()];
        for (k, spring) in file.springs.iter().enumerate() {
            let field = |name: &str| format!("springs[{k}].{name}");
            let i = self.lookup(names, field("body"), &spring.body)?;
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
        Ok(springs)
    }

    /// How each body moves: fixed, kinematic or free (exactly), or
    /// integrated under what acts on it ([`crate::motion::classify`]).
    pub(super) fn motions(
        &self,
        settings: &[BodySettings],
        bodies: &mut [Body],
        mut springs: Vec<Vec<Spring>>,
        gravity: Vector,
        pushed_by_contacts: bool,
        dt: Real,
    ) -> Result<()> {
        for (i, body) in bodies.iter_mut().enumerate() {
            let settings = &settings[i];
            if pushed_by_contacts
                && !settings.fixed
                && !settings.kinematic
                && (body.mass.is_none() || body.inertia.is_none())
            {
                return self.invalid(
                    format!("bodies[{i}].density"),
                    format!(
                        "`{}` can be pushed by contacts (`on_contact: Bounce` or `Simulate`), so it needs a mass and an inertia: give `density`, or `mass` and `inertia` (or make it `fixed` or `kinematic`)",
                        body.name
                    ),
                );
            }
            if settings.fixed && settings.kinematic {
                return self.invalid(
                    format!("bodies[{i}].kinematic"),
                    "a body is `fixed` (never moves) or `kinematic` (moves at its given velocity), not both",
                );
            }
            if settings.pivot.is_some() && settings.fixed {
                return self
                    .invalid(format!("bodies[{i}].pivot"), "a fixed body never turns: remove `pivot`");
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
                let precesses = body.inertia.is_some_and(|inertia| spin_precesses(&inertia, &omega_body));
                let influences = Influences {
                    gravity: gravity.norm() > 0.0,
                    springs: !springs[i].is_empty(),
                    pushed_by_contacts,
                };
                if needs_integration(influences, precesses) && settings.pivot.is_some() {
                    return self.invalid(
                        format!("bodies[{i}].pivot"),
                        format!(
                            "`{}` is moved by forces (gravity, springs or contacts), and a body under forces turns about its centre of mass: make it `kinematic` to turn it about a pivot",
                            body.name
                        ),
                    );
                }
                if needs_integration(influences, precesses) {
                    let turn = body.angular_velocity.norm() * dt;
                    if turn >= MAX_TURN_PER_STEP {
                        return self.invalid(
                            format!("bodies[{i}].angular_velocity"),
                            format!(
                                "the body turns {turn:.3} rad per step (|ω| dt); an integrated body must turn less than π/2 per step: lower `dt`"
                            ),
                        );
                    }
                    BodyMotion::Integrated { springs: std::mem::take(&mut springs[i]) }
                } else {
                    BodyMotion::Free
                }
            };
        }
        Ok(())
    }

    /// The keyframes of the bodies with a `path` (kinematic, moving only as
    /// the path says; `centers`: each body's centre in its mesh's frame),
    /// and the pivots a response cannot take. `stops_kinematic`: the name
    /// of a response that stops or pushes kinematic bodies.
    pub(super) fn paths(
        &self,
        settings: &[BodySettings],
        bodies: &mut [Body],
        centers: &[Vector],
        dt: Real,
        stops_kinematic: Option<&str>,
    ) -> Result<()> {
        for (i, (settings, body)) in settings.iter().zip(bodies.iter_mut()).enumerate() {
            let field = |name: &str| format!("bodies[{i}].{name}");
            if settings.pivot.is_some() && stops_kinematic == Some("Simulate") {
                return self.invalid(
                    field("pivot"),
                    "rapier turns its bodies about their centres of mass: `pivot` is not taken under `on_contact: Simulate`",
                );
            }
            if settings.path.is_empty() {
                continue;
            }
            if !settings.kinematic {
                return self.invalid(
                    field("path"),
                    "only a kinematic body follows a path (forces and contacts move the others): add `kinematic: true`",
                );
            }
            if body.velocity != Vector::zeros() || body.angular_velocity != Vector::zeros() {
                return self.invalid(
                    field("path"),
                    "a body with a path moves as its keyframes say: remove `velocity` and `angular_velocity`",
                );
            }
            if let Some(response) = stops_kinematic {
                return self.invalid(
                    field("path"),
                    format!("`on_contact: {response}` stops or pushes kinematic bodies, which a path cannot follow: use `Stop` or `Record`"),
                );
            }
            let mut keys = vec![(0u64, body.pose)];
            for (k, key) in settings.path.iter().enumerate() {
                let at = |name: &str| format!("bodies[{i}].path[{k}].{name}");
                let time = self.finite(&at("time"), key.time)?;
                let (previous_step, previous) = keys[keys.len() - 1];
                let step = (time / dt).round();
                if step <= previous_step as Real || time <= 0.0 {
                    return self.invalid(
                        at("time"),
                        format!(
                            "{} is not after the previous keyframe's time (at least one step, dt = {dt:?})",
                            shortest(time)
                        ),
                    );
                }
                if (step * dt - time).abs() > KEYFRAME_TIME_TOLERANCE * time.max(dt) {
                    return self.invalid(
                        at("time"),
                        format!(
                            "{} is not on a step (a whole number of dt = {dt:?}): the nearest are {} and {}",
                            shortest(time),
                            shortest((time / dt).floor() * dt),
                            shortest(((time / dt).floor() + 1.0) * dt)
                        ),
                    );
                }
                let rotation = self.orientation(&at("orientation"), &key.orientation)?;
                let position = self.vector(&at("position"), &key.position)?;
                let pose = Pose::from_parts(Translation3::from(position + rotation * centers[i]), rotation);
                let turn = previous.rotation.angle_to(&pose.rotation);
                if turn > std::f64::consts::PI - KEYFRAME_TURN_MARGIN {
                    return self.invalid(
                        at("orientation"),
                        format!("the turn from the previous keyframe is {turn:.6} rad: a segment turns the short way, less than half a turn, which this is not clearly: add a keyframe between"),
                    );
                }
                keys.push((step as u64, pose));
            }
            let first = super::KeyframePath { keys };
            // At time 0 the body moves as the first segment.
            let start = first.motion(0, dt);
            (body.velocity, body.angular_velocity) = (start.velocity, start.angular_velocity);
            body.path = Some(Arc::new(first));
        }
        Ok(())
    }

    /// A body and the offset of its centre of mass from its mesh's origin.
    pub(super) fn body(
        &self,
        i: usize,
        settings: &BodySettings,
        base: &Path,
        assets: &mut Assets,
    ) -> Result<(Body, Vector)> {
        let field = |name: &str| format!("bodies[{i}].{name}");
        let scale = self.positive(&field("scale"), settings.scale)?;
        let position = self.vector(&field("position"), &settings.position)?;
        let velocity = self.vector(&field("velocity"), &settings.velocity)?;
        let angular_velocity = self.vector(&field("angular_velocity"), &settings.angular_velocity)?;
        let rotation = self.orientation(&field("orientation"), &settings.orientation)?;

        let (original, key) = self.shared_mesh(i, settings, scale, base, assets)?;
        let shape = Arc::clone(&original);

        let (mut mass, mut inertia, mut center) = (None, None, Vector::zeros());
        if let Some(m) = settings.mass {
            mass = Some(self.invertible(&field("mass"), m)?);
        }
        if let Some(moments) = &settings.inertia {
            inertia = Some(self.given_inertia(&field("inertia"), moments)?);
        }
        let shape = match settings.density {
            None => shape,
            Some(density) => {
                let density = self.positive(&field("density"), density)?;
                if settings.mass.is_some() || settings.inertia.is_some() {
                    return self
                        .invalid(field("density"), "give `density`, or `mass` and `inertia`, not both");
                }
                // Checked once per asset: a thousand bodies of one mesh
                // are one check.
                let solid = assets
                    .solids
                    .entry(key.clone())
                    .or_insert_with(|| shape.check_closed().map(|()| shape.mass_properties()));
                let props = match solid {
                    Ok(props) => *props,
                    Err(error) => {
                        return self.invalid(
                            field("density"),
                            format!("mass properties from a density need a closed mesh: {error}"),
                        )
                    }
                };
                let Some(props) = props else {
                    return self.invalid(
                        field("density"),
                        "the mesh encloses no positive volume (open, or triangles facing inward): mass properties need a closed mesh",
                    );
                };
                mass = Some(self.invertible(&field("density"), density * props.volume)?);
                let moments = props.inertia * density;
                for k in 0..3 {
                    self.invertible(&field("density"), moments[(k, k)])?;
                }
                inertia = Some(moments);
                center = props.center_of_mass.coords;
                // The recentred mesh is an asset of its own, shared likewise.
                let centered = format!("{key}|centred");
                assets
                    .meshes
                    .entry(centered)
                    .or_insert_with(|| Arc::new(shape.recentered(&props.center_of_mass)))
                    .clone()
            }
        };

        let (shape, center) = match &settings.pivot {
            None => (shape, center),
            Some(pivot) => {
                // The mesh about its pivot: the file's mesh (scaled), not the
                // recentred one; an asset of its own.
                let pivot = Point::from(self.vector(&field("pivot"), pivot)? * scale);
                let pivoted = format!("{key}|pivot {:?}", pivot.coords.as_slice());
                let shape = match assets.meshes.get(&pivoted) {
                    Some(shape) => shape.clone(),
                    None => {
                        let moved = original.pivoted(&pivot).or_else(|e| {
                            self.invalid(
                                field("pivot"),
                                format!("the mesh about this pivot is unusable: {e}"),
                            )
                        })?;
                        self.check_mesh_range(&field("pivot"), &moved)?;
                        assets.meshes.entry(pivoted).or_insert(Arc::new(moved)).clone()
                    }
                };
                (shape, pivot.coords)
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
            kinematic: settings.kinematic,
            material: None,
            path: None,
        };
        Ok((body, center))
    }

    /// Body `i`'s mesh, built once per mesh and scale and shared by the
    /// bodies that use it, and its key among the assets.
    fn shared_mesh(
        &self,
        i: usize,
        settings: &BodySettings,
        scale: Real,
        base: &Path,
        assets: &mut Assets,
    ) -> Result<(Arc<TriMesh>, String)> {
        let field = |name: &str| format!("bodies[{i}].{name}");
        let key = format!("{:?}|{scale:e}", settings.mesh);
        let mesh_field = field("mesh");
        let shape = match assets.meshes.get(&key) {
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
                self.check_mesh_range(&mesh_field, &scaled)?;
                let shape = Arc::new(scaled);
                assets.meshes.insert(key.clone(), shape.clone());
                shape
            }
        };
        Ok((shape, key))
    }

    /// Principal moments of inertia as given (`field`): positive,
    /// invertible, and those of a rigid body (each at most the sum of the
    /// other two).
    fn given_inertia(&self, field: &str, moments: &super::file::Triple) -> Result<Matrix3<Real>> {
        let m = self.vector(field, moments)?;
        if m.min() <= 0.0 {
            return self.invalid(field, "principal moments must be positive");
        }
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            self.invertible(&format!("{field}.{axis}"), m[k])?;
        }
        if m.x + m.y < m.z || m.y + m.z < m.x || m.z + m.x < m.y {
            return self.invalid(
                field,
                "no rigid body has these moments: each must be at most the sum of the other two",
            );
        }
        Ok(Matrix3::from_diagonal(&m))
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
            MeshSettings::Torus { major, minor, around, across } => {
                let major = self.positive(&sub("major"), *major)?;
                let minor = self.positive(&sub("minor"), *minor)?;
                if minor >= major {
                    return self.invalid(
                        sub("minor"),
                        format!("the tube's radius must be below `major` ({major}), found {minor}"),
                    );
                }
                for (name, segments) in [("around", *around), ("across", *across)] {
                    if !(3..=MAX_TORUS_SEGMENTS).contains(&segments) {
                        return self.invalid(
                            sub(name),
                            format!("3 to {MAX_TORUS_SEGMENTS} segments, found {segments}"),
                        );
                    }
                }
                mesh::torus(major, minor, *around, *across)
            }
            MeshSettings::File { path } | MeshSettings::Obj { path } => {
                return mesh::load_mesh(&base.join(path)).or_else(|e| self.invalid(field, e.to_string()));
            }
        };
        built.or_else(|e| self.invalid(field, e.to_string()))
    }

    fn orientation(&self, field: &str, settings: &OrientationSettings) -> Result<UnitQuaternion<Real>> {
        match settings {
            OrientationSettings::Identity => Ok(UnitQuaternion::identity()),
            OrientationSettings::AxisAngle { axis, degrees, radians } => {
                let radians = match (degrees, radians) {
                    (Some(degrees), None) => self.finite(&format!("{field}.degrees"), *degrees)?.to_radians(),
                    (None, Some(radians)) => self.finite(&format!("{field}.radians"), *radians)?,
                    (None, None) => {
                        return self
                            .invalid(field, "AxisAngle needs its angle: `degrees: 30.0` or `radians: 0.5`")
                    }
                    (Some(_), Some(_)) => {
                        return self.invalid(field, "AxisAngle takes `degrees` or `radians`, not both")
                    }
                };
                // Only the axis's direction matters: any finite size is
                // normalised (scaled by its largest component first, so that
                // its square cannot overflow or underflow).
                let components = [axis[0], axis[1], axis[2]];
                let Some([x, y, z]) = self.direction(&format!("{field}.axis"), components)? else {
                    return self.invalid(format!("{field}.axis"), "the axis must not be zero");
                };
                if radians == 0.0 {
                    return Ok(UnitQuaternion::identity());
                }
                let axis = nalgebra::Unit::new_normalize(Vector::new(x, y, z));
                Ok(UnitQuaternion::from_axis_angle(&axis, radians))
            }
            OrientationSettings::Quaternion { w, x, y, z } => {
                match self.direction(field, [*w, *x, *y, *z])? {
                    Some([w, x, y, z]) => Ok(UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z))),
                    None => self.invalid(
                        field,
                        "the quaternion (0, 0, 0, 0) cannot be normalised: give a non-zero one",
                    ),
                }
            }
        }
    }
}

/// What the bodies of a scene share, by mesh key: the meshes, and whether
/// each is a closed solid with its mass properties at unit density.
#[derive(Default)]
pub(super) struct Assets {
    meshes: HashMap<String, Arc<TriMesh>>,
    solids: HashMap<String, std::result::Result<Option<crate::mesh::MassProperties>, crate::mesh::MeshError>>,
}
