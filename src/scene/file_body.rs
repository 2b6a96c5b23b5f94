//! The file format's bodies: their meshes, colliders, orientations and
//! springs, as RON gives them (validated in `build_body.rs`).

use serde::Deserialize;

/// Three numbers `(x, y, z)`.
pub type Triple = [f64; 3];

fn default_torus_around() -> u32 {
    48
}

fn default_torus_across() -> u32 {
    24
}

/// A spring from a body point to a world anchor.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSettings {
    /// The body's name.
    pub body: String,
    /// The attachment point in the body's mesh frame. Default: the origin.
    #[serde(default)]
    pub point: Triple,
    /// The world anchor.
    pub anchor: Triple,
    /// Stiffness (force per length).
    pub stiffness: f64,
    /// Damping (force per speed). Default: 0.
    #[serde(default)]
    pub damping: f64,
    /// Rest length. Default: 0.
    #[serde(default)]
    pub rest_length: f64,
}

/// A body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySettings {
    /// A unique name.
    pub name: String,
    /// The mesh.
    pub mesh: MeshSettings,
    /// A uniform scale applied to the mesh. Default: 1.
    #[serde(default = "unit_scale")]
    pub scale: f64,
    /// Where the mesh's origin is placed. Default: the world origin.
    #[serde(default)]
    pub position: Triple,
    /// The mesh's orientation. Default: none.
    #[serde(default)]
    pub orientation: OrientationSettings,
    /// Velocity of the centre of mass. Default: 0.
    #[serde(default)]
    pub velocity: Triple,
    /// Angular velocity, world frame, radians per time unit. Default: 0.
    #[serde(default)]
    pub angular_velocity: Triple,
    /// Mass (needed by bodies with springs).
    #[serde(default)]
    pub mass: Option<f64>,
    /// Principal moments of inertia about the centre of mass, along the
    /// mesh's axes.
    #[serde(default)]
    pub inertia: Option<Triple>,
    /// Density: mass, centre of mass and inertia from the (closed) mesh;
    /// excludes `mass` and `inertia`.
    #[serde(default)]
    pub density: Option<f64>,
    /// Never moves. Default: false.
    #[serde(default)]
    pub fixed: bool,
    /// Keeps its velocities whatever acts on it. Default: false.
    #[serde(default)]
    pub kinematic: bool,
    /// Its friction coefficient under `on_contact: Simulate` (overrides the
    /// scene's). Default: the scene's.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Its coefficient of restitution under `on_contact: Simulate`
    /// (overrides the scene's). Default: the scene's.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// The collider rapier is given under `on_contact: Simulate`. Default:
    /// `Auto` (the convex hull of a convex mesh, the same solid; the
    /// triangle mesh otherwise).
    #[serde(default)]
    pub collider: ColliderSettings,
    /// The point the body turns about, in the mesh's coordinates (scaled
    /// with it): a link's joint. Its `velocity` is then that point's.
    /// Default: the centre of mass (with `density`), else the mesh's
    /// origin. Only for bodies that move at constant velocities (kinematic,
    /// or nothing acts on them): a body under forces turns about its centre
    /// of mass.
    #[serde(default)]
    pub pivot: Option<Triple>,
    /// Keyframes of a kinematic body after its start pose (`position`,
    /// `orientation` at time 0): between two keyframes it turns about its
    /// `pivot` at a constant angular velocity (the short way) while the
    /// pivot moves at a constant velocity, so it is at each keyframe's pose
    /// at its time; after the last it stays. Default: none.
    #[serde(default)]
    pub path: Vec<KeyframeSettings>,
}

/// A keyframe of a kinematic body's `path`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeSettings {
    /// Its time: after the previous keyframe's, on a step (a whole number
    /// of `dt`).
    pub time: f64,
    /// Where the mesh's origin is then.
    pub position: Triple,
    /// The mesh's orientation then. Default: none.
    #[serde(default)]
    pub orientation: OrientationSettings,
}

/// The collider shape rapier is given for a body (`on_contact: Simulate`).
#[derive(Copy, Clone, Debug, Default, Deserialize, PartialEq, Eq)]
pub enum ColliderSettings {
    /// The convex hull where the mesh is convex, else the triangle mesh.
    #[default]
    Auto,
    /// The triangle mesh, convex or not (what rapier applications do with
    /// meshes; rapier never sweeps it: the guard does).
    TriMesh,
}

fn unit_scale() -> f64 {
    1.0
}

/// A mesh: a primitive (centred on its origin) or an OBJ file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum MeshSettings {
    /// A box.
    Box {
        /// Half extents along x, y, z.
        half_extents: Triple,
    },
    /// A subdivided icosahedron.
    Icosphere {
        /// The radius of its vertices.
        radius: f64,
        /// Subdivisions (0 to 7); 20 × 4^subdivisions triangles.
        #[serde(default)]
        subdivisions: u32,
    },
    /// A regular tetrahedron.
    Tetrahedron {
        /// The distance of its vertices from the centre.
        circumradius: f64,
    },
    /// One triangle, vertices in the body's frame.
    Triangle {
        /// First vertex.
        a: Triple,
        /// Second vertex.
        b: Triple,
        /// Third vertex.
        c: Triple,
    },
    /// A needle (sliver) triangle.
    Needle {
        /// Base length.
        length: f64,
        /// Height of the apex over the base.
        width: f64,
    },
    /// A torus about the body's z axis (not convex: its hole is outside it).
    Torus {
        /// The radius of the tube's centre circle.
        major: f64,
        /// The tube's radius (below `major`).
        minor: f64,
        /// Segments along the centre circle (3 to 4096). Default: 48.
        #[serde(default = "default_torus_around")]
        around: u32,
        /// Segments around the tube (3 to 4096). Default: 24.
        #[serde(default = "default_torus_across")]
        across: u32,
    },
    /// A mesh file, its path relative to the scene file: OBJ, STL (binary
    /// or ASCII), PLY or glTF/GLB, the format told by the contents;
    /// coincident vertices welded (see [`crate::mesh::load_mesh`]).
    File {
        /// The path.
        path: String,
    },
    /// A mesh file as `File` reads it (the name of the OBJ-only days, kept).
    Obj {
        /// The path.
        path: String,
    },
}

/// An orientation.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum OrientationSettings {
    /// No rotation.
    #[default]
    Identity,
    /// A rotation about an axis (need not be unit), by an angle in
    /// `degrees` or in `radians` (exactly one of the two).
    AxisAngle {
        /// The axis.
        axis: Triple,
        /// The angle in degrees.
        #[serde(default)]
        degrees: Option<f64>,
        /// The angle in radians.
        #[serde(default)]
        radians: Option<f64>,
    },
    /// A quaternion; normalised on reading.
    Quaternion {
        /// Scalar part.
        w: f64,
        /// i.
        x: f64,
        /// j.
        y: f64,
        /// k.
        z: f64,
    },
}
