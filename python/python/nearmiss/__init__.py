"""nearmiss: continuous collision detection for triangle meshes.

Exact triangle distances (and the seed paper's DyOP), continuous collision
detection of rotating meshes that never reports contact late, certified
closest approaches of moving meshes, and scene runs, on numpy arrays.

Arrays are float64 (anything numpy converts to float64 is accepted);
every number must be finite. Shapes: a point (3,), a triangle (3, 3) (its
vertices as rows), batches (N, 3) and (N, 3, 3). Bad input raises
``ValueError`` (wrong shape, a non-finite number, an index out of range)
or ``TypeError`` (not numbers), naming the argument. Faces of zero area
(repeated or collinear vertices, as real meshes hold them) are kept and
take part as the segments or points they span (``Mesh.zero_area_triangles``).

A mesh is a :class:`Mesh` or any object with ``vertices`` and ``faces``
(a ``trimesh.Trimesh``: converted once and kept while it is unchanged).
A pose is ``(position, rotation)``: position (3,), rotation a unit
quaternion ``[w, x, y, z]`` (4,), a rotation matrix (3, 3) or a scipy
``Rotation``; or a 4 x 4 homogeneous transform; ``None`` is the identity.
Quaternions are always ``[w, x, y, z]``: one in scipy's, ROS's or Eigen's
``[x, y, z, w]`` order is a unit quaternion too and cannot be told apart,
so convert it with :func:`quaternion_from_xyzw`.

A motion is ``(velocity, angular_velocity)``, both (3,) in the world
frame, constant over the query (the mesh turns about its own frame's
origin, placed by the pose); ``None`` is at rest.
"""

from __future__ import annotations

import hashlib
import json
import os
import weakref
from typing import Any, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _nearmiss
from ._nearmiss import Mesh, SceneError

#: The version of the package (and of the Rust crates it is built from).
__version__: str = _nearmiss.__version__

__all__ = [
    "FEATURES",
    "FORMULAS",
    "Clearance",
    "ClosestApproach",
    "CollisionManager",
    "FirstContact",
    "Mesh",
    "MeshDistance",
    "MotionBetween",
    "MeshIntersection",
    "SignedDistance",
    "SceneError",
    "SceneInfo",
    "TimeOfImpact",
    "TriangleDistance",
    "TriangleClosestPoints",
    "TriangleIntersection",
    "TrianglePenetration",
    "closest_approach",
    "dyop_distance",
    "load_scene",
    "mesh_distance",
    "mesh_intersection",
    "mesh_time_of_impact",
    "motion_between",
    "point_segment_distance",
    "point_segment_distances",
    "quaternion_from_xyzw",
    "run_scene",
    "signed_distance",
    "triangle_closest_points",
    "triangle_distance",
    "triangle_distances",
    "triangle_intersection",
    "triangle_penetration",
]

#: The names of the feature codes of :func:`triangle_closest_points`:
#: ``FEATURES[code]``; vertex ``i`` is code ``i``, edge ``i`` (from vertex
#: ``i`` to vertex ``i + 1``) is ``3 + i``, the face is 6.
FEATURES: Tuple[str, ...] = ("vertex 0", "vertex 1", "vertex 2", "edge 0", "edge 1", "edge 2", "face")

#: The point–edge formulas: ``"vector"`` (the default, compensated),
#: ``"plain_vector"`` and ``"heron"`` (the seed paper's), ``"stable_heron"``
#: (Kahan's ordering of Heron's formula).
FORMULAS: Tuple[str, ...] = ("vector", "plain_vector", "heron", "stable_heron")

ArrayLike = Union[np.ndarray, Sequence[Any]]
Pose = Optional[Union[Tuple[ArrayLike, Any], ArrayLike]]
#: ``(velocity, angular_velocity)``, a :class:`MotionBetween`, or None (at rest).
Motion = Optional[Union[Tuple[ArrayLike, ArrayLike], "MotionBetween"]]


class TriangleDistance(NamedTuple):
    """The distance of two triangles and where it is reached."""

    #: The distance; exactly 0 when the triangles touch or overlap.
    distance: float
    #: The closest point on the first triangle (a common point if they meet).
    point_a: np.ndarray
    #: The closest point on the second triangle.
    point_b: np.ndarray
    #: The feature ``point_a`` lies on: ``"vertex 0"``, ``"edge 2"``, ``"face"``.
    feature_a: str
    #: The feature ``point_b`` lies on.
    feature_b: str
    #: Whether the stated accuracy holds (sizes within about 1e60 of each other).
    within_range: bool


class TriangleClosestPoints(NamedTuple):
    """Distances, closest points and features of triangle pairs, as arrays."""

    distance: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    #: Feature codes (int8): ``FEATURES[code]`` names them.
    feature_a: np.ndarray
    feature_b: np.ndarray


class MeshDistance(NamedTuple):
    """The distance of two meshes and where it is reached (world frame)."""

    distance: float
    point_a: np.ndarray
    point_b: np.ndarray
    #: The triangles (indices into the meshes' faces).
    triangle_a: int
    triangle_b: int
    feature_a: str
    feature_b: str


class TriangleIntersection(NamedTuple):
    """What two triangles share (:func:`triangle_intersection`)."""

    #: ``"disjoint"``, ``"point"``, ``"segment"`` or ``"polygon"`` (coplanar
    #: triangles overlapping with area), decided with exact predicates.
    kind: str
    #: The points spanning it, (k, 3): none, the point, the segment's two
    #: ends, or the polygon's vertices in order.
    points: np.ndarray


class TrianglePenetration(NamedTuple):
    """The shortest translation that separates two triangles."""

    #: Its length (0 when they only touch, or are coplanar).
    depth: float
    #: Its unit direction: the second triangle moved by ``depth`` along it
    #: touches the first.
    direction: np.ndarray


class MeshIntersection(NamedTuple):
    """Where two posed meshes' surfaces meet (:func:`mesh_intersection`)."""

    #: The triangle pairs that meet, (k, 2) face indices (first mesh, second).
    pairs: np.ndarray
    #: The intersection curve's segments, (m, 2, 3), world frame.
    segments: np.ndarray
    #: The curve's length.
    length: float


class SignedDistance(NamedTuple):
    """How two posed meshes stand (:func:`signed_distance`)."""

    #: The distance apart (0 touching); minus the depth where they overlap.
    value: float
    #: ``"apart"``; ``"convex"`` (two convex solids: the exact shortest
    #: separating move); ``"local"`` (closed meshes crossing: the deepest
    #: local depth at a component of their intersection curve); ``"inside"``
    #: (a closed mesh wholly inside another); ``"open_crossing"`` (an open
    #: mesh crosses: no inside, no depth, ``value`` 0).
    kind: str
    #: The depth is at least this (None apart or open).
    lower: Optional[float]
    #: The depth is at most this (None apart or open).
    upper: Optional[float]
    #: ``"convex"``: the direction to move the second mesh by the depth.
    direction: Optional[np.ndarray]


class TimeOfImpact(NamedTuple):
    """The answer of :func:`mesh_time_of_impact`."""

    #: The time of first contact (never later than the true one), or None.
    time: Optional[float]
    #: How the iteration ended: ``"separated"``, ``"filtered"`` (no contact,
    #: proved before any iteration), ``"converged"``, ``"initially_touching"``,
    #: ``"out_of_iterations"`` (contact reported, conservatively, where the
    #: iterations ran out: could not decide).
    status: str
    #: No contact is reported farther apart than this.
    contact_distance: float
    #: Every approach closer than this is reported.
    guaranteed_distance: float
    #: At contact: a triangle pair within the contact distance there.
    closest: Optional[MeshDistance]
    #: Advancement steps taken.
    iterations: int


class ClosestApproach(NamedTuple):
    """The answer of :func:`closest_approach`: ``lower <= d* <= upper``."""

    #: ``"bracketed"``, ``"contact"`` (they touch; ``time`` is the time of
    #: first contact), ``"beyond"`` (never within ``within``),
    #: ``"out_of_iterations"`` or ``"undecided"``.
    status: str
    #: Certified: the meshes are never closer than this over the interval.
    lower: float
    #: Reached: the meshes are this far apart at ``time`` (inf when beyond).
    upper: float
    time: float
    closest: Optional[MeshDistance]
    #: CCD runs taken.
    runs: int


class MotionBetween(NamedTuple):
    """A motion from :func:`motion_between`: pass it as a body's motion,
    with ``None`` as its pose (the motion holds where it starts)."""

    #: The start pose of the frame at ``about``: ``(position, [w, x, y, z])``.
    pose: Tuple[np.ndarray, np.ndarray]
    #: The constant velocity of the point ``about`` (world frame).
    velocity: np.ndarray
    #: The constant angular velocity (world frame, radians per unit time).
    angular_velocity: np.ndarray
    #: The point turned about, in the mesh's own frame.
    about: np.ndarray


def _floats(name: str, value: Any) -> np.ndarray:
    array = np.asarray(value)
    if array.dtype.kind not in "biuf":
        raise TypeError(f"{name}: expected numbers (float64), got an array of dtype {array.dtype}")
    return np.ascontiguousarray(array, dtype=np.float64)


def quaternion_from_xyzw(q: ArrayLike) -> np.ndarray:
    """A quaternion in scipy's, ROS's and Eigen's ``[x, y, z, w]`` order as
    nearmiss takes it, ``[w, x, y, z]``. (Both orders hold unit
    quaternions, so nearmiss cannot tell them apart: it never guesses.)"""
    q = _floats("q", q)
    if q.shape != (4,):
        raise ValueError(f"q: expected a quaternion of shape (4,), got shape {q.shape}")
    return np.array([q[3], q[0], q[1], q[2]])


def _rotation(name: str, rotation: Any) -> np.ndarray:
    # A scipy ``Rotation`` (or anything with ``as_matrix()``): its matrix.
    as_matrix = getattr(rotation, "as_matrix", None)
    if callable(as_matrix):
        rotation = as_matrix()
    return _floats(name, rotation)


def _pose(name: str, pose: Pose) -> Tuple[np.ndarray, np.ndarray]:
    if pose is None:
        return np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])
    if isinstance(pose, np.ndarray) or (isinstance(pose, (list, tuple)) and len(pose) == 4):
        # A 4 x 4 homogeneous transform: rotation and position, last row 0 0 0 1.
        matrix = _floats(name, pose)
        if matrix.shape != (4, 4):
            raise ValueError(
                f"{name}: expected (position, rotation), a 4 x 4 transform or None, got an array of shape {matrix.shape}"
            )
        if not np.array_equal(matrix[3], [0.0, 0.0, 0.0, 1.0]):
            raise ValueError(f"{name}: a 4 x 4 transform's last row must be [0, 0, 0, 1], got {matrix[3].tolist()}")
        return np.ascontiguousarray(matrix[:3, 3]), np.ascontiguousarray(matrix[:3, :3])
    try:
        position, rotation = pose
    except (TypeError, ValueError):
        raise TypeError(
            f"{name}: expected (position, rotation), a 4 x 4 transform or None, got {type(pose).__name__}"
        ) from None
    return _floats(f"{name} position", position), _rotation(f"{name} rotation", rotation)


def _motion(name: str, motion: Motion) -> Tuple[np.ndarray, np.ndarray]:
    if motion is None:
        return np.zeros(3), np.zeros(3)
    try:
        velocity, angular_velocity = motion
    except (TypeError, ValueError):
        raise TypeError(
            f"{name}: expected (velocity, angular_velocity) or None, got {type(motion).__name__}"
        ) from None
    return _floats(f"{name} velocity", velocity), _floats(f"{name} angular velocity", angular_velocity)


#: Meshes built from other libraries' objects (a ``trimesh.Trimesh``),
#: each kept while its object lives and its arrays are unchanged, so a
#: query in a loop does not rebuild the tree.
_converted: "weakref.WeakKeyDictionary[Any, Tuple[bytes, Mesh]]" = weakref.WeakKeyDictionary()


def _mesh(name: str, mesh: Any) -> Mesh:
    if isinstance(mesh, Mesh):
        return mesh
    vertices, faces = getattr(mesh, "vertices", None), getattr(mesh, "faces", None)
    if vertices is None or faces is None:
        raise TypeError(
            f"{name}: expected a nearmiss.Mesh or an object with vertices and faces (a trimesh.Trimesh), "
            f"got {type(mesh).__name__}"
        )
    vertices = _floats(f"{name}.vertices", vertices)
    faces = np.ascontiguousarray(np.asarray(faces))
    digest = hashlib.blake2b(vertices.data, digest_size=16)
    digest.update(faces.data)
    digest.update(str(faces.dtype).encode())
    key = digest.digest()
    try:
        kept = _converted.get(mesh)
    except TypeError:  # not weakly referenceable: converted each time
        kept = None
    if kept is not None and kept[0] == key:
        return kept[1]
    converted = Mesh(vertices, faces)
    try:
        _converted[mesh] = (key, converted)
    except TypeError:
        pass
    return converted


#: Meshes moved to a pivot (:meth:`Mesh.pivoted`) for motions from
#: :func:`motion_between`, by mesh and point, so that a query in a loop
#: does not rebuild them; the oldest go first past a few dozen.
_pivoted: "dict[Tuple[int, bytes], Tuple[Mesh, Mesh]]" = {}


def _body(suffix: str, mesh: Any, pose: Pose, motion: Any) -> tuple:
    """One moving body's arguments (named ``mesh{suffix}``, ``pose{suffix}``,
    ``motion{suffix}`` in errors): ``(mesh, pose arrays, motion arrays)``; a
    :class:`MotionBetween` brings its pivot frame's pose and the mesh in
    that frame."""
    mesh = _mesh(f"mesh{suffix}", mesh)
    if not isinstance(motion, MotionBetween):
        return mesh, _pose(f"pose{suffix}", pose), _motion(f"motion{suffix}", motion)
    if pose is not None:
        raise TypeError(
            f"pose{suffix}: a motion from motion_between holds its start pose: pass None as the pose"
        )
    key = (id(mesh), motion.about.tobytes())
    kept = _pivoted.get(key)
    if kept is None or kept[0] is not mesh:
        if len(_pivoted) >= 64:
            del _pivoted[next(iter(_pivoted))]
        kept = _pivoted[key] = (mesh, mesh.pivoted(motion.about))
    return kept[1], _pose(f"pose{suffix}", motion.pose), (motion.velocity, motion.angular_velocity)


def _moving(mesh_a, pose_a, motion_a, mesh_b, pose_b, motion_b, duration) -> tuple:
    """A moving pair's arguments, converted and checked: each body as
    ``(mesh, pose arrays, motion arrays)``, then the duration."""
    return _body("_a", mesh_a, pose_a, motion_a), _body("_b", mesh_b, pose_b, motion_b), float(duration)


def motion_between(pose0: Pose, pose1: Pose, duration: float = 1.0, about: ArrayLike = (0.0, 0.0, 0.0)) -> MotionBetween:
    """The motion that takes a body from ``pose0`` to ``pose1`` in
    ``duration``, turning about its point ``about`` (in the mesh's own
    frame: a link's joint) with constant angular velocity, and moving that
    point with constant velocity (zero for a joint that stays put).

    Pass it as the body's motion, with ``None`` as its pose, to
    :func:`mesh_time_of_impact` or :func:`closest_approach`: every vertex is
    where ``pose0`` puts it at 0 and ``pose1`` at ``duration`` (to
    rounding), turning about ``about`` between. The turn is taken the short
    way (less than half a turn); split a longer one into several motions.
    Poses as everywhere: ``(position, rotation)``, a 4 x 4 transform, a
    quaternion ``[w, x, y, z]``, a matrix or a scipy ``Rotation``.
    """
    position0, rotation0 = _pose("pose0", pose0)
    position1, rotation1 = _pose("pose1", pose1)
    about = _floats("about", about)
    position, quaternion, velocity, angular = _nearmiss.motion_between(
        (position0, rotation0), (position1, rotation1), float(duration), about
    )
    return MotionBetween((position, quaternion), velocity, angular, about)


def _mesh_distance(raw: Optional[tuple]) -> Optional[MeshDistance]:
    return None if raw is None else MeshDistance(*raw)


def triangle_distance(a: ArrayLike, b: ArrayLike) -> TriangleDistance:
    """The exact distance between triangles ``a`` and ``b`` (each (3, 3)).

    Exactly 0 when they touch or intersect (decided with exact
    predicates), with a common point as both closest points.
    """
    return TriangleDistance(*_nearmiss.triangle_distance(_floats("a", a), _floats("b", b)))


def triangle_distances(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """The distances of ``a[i]`` and ``b[i]`` for (N, 3, 3) batches.

    The vectorised kernel (AVX2 or AVX-512 where the machine has them), on
    all cores, without the GIL; the same numbers as the Rust library's
    ``kernels::batch::triangle_distances``.
    """
    return _nearmiss.triangle_distances(_floats("a", a), _floats("b", b))


def triangle_closest_points(a: ArrayLike, b: ArrayLike) -> TriangleClosestPoints:
    """Distances, closest points (N, 3) and feature codes of (N, 3, 3) batches.

    Each pair as :func:`triangle_distance` answers it, on all cores.
    """
    return TriangleClosestPoints(*_nearmiss.triangle_closest_points(_floats("a", a), _floats("b", b)))


def point_segment_distance(p: ArrayLike, a: ArrayLike, b: ArrayLike, formula: str = "vector") -> float:
    """The distance from point ``p`` to the segment ``a``–``b`` by ``formula``.

    See :data:`FORMULAS`; ``"heron"`` and ``"plain_vector"`` are the seed
    paper's formulas, kept to show their error.
    """
    return _nearmiss.point_segment_distance(_floats("p", p), _floats("a", a), _floats("b", b), formula)


def point_segment_distances(p: ArrayLike, a: ArrayLike, b: ArrayLike, formula: str = "vector") -> np.ndarray:
    """:func:`point_segment_distance` for (N, 3) batches, on all cores."""
    return _nearmiss.point_segment_distances(_floats("p", p), _floats("a", a), _floats("b", b), formula)


def dyop_distance(a: ArrayLike, b: ArrayLike, formula: str = "vector") -> float:
    """The seed paper's DyOP distance between triangles ``a`` and ``b``.

    An approximation (it does not detect intersecting triangles); use
    :func:`triangle_distance` for the exact distance.
    """
    return _nearmiss.dyop_distance(_floats("a", a), _floats("b", b), formula)


def mesh_distance(mesh_a: Mesh, pose_a: Pose, mesh_b: Mesh, pose_b: Pose) -> MeshDistance:
    """The exact distance between two posed meshes (0 if they touch).

    Within an ulp of the largest posed coordinate of the exact distance of
    the poses as given: a rotation matrix (or a 4 x 4 transform's) that is
    one to rounding is applied as it is, not through a quaternion, and the
    closest triangle pair is posed in double-double before it is measured.
    """
    raw = _nearmiss.mesh_distance_between(
        _mesh("mesh_a", mesh_a), _pose("pose_a", pose_a), _mesh("mesh_b", mesh_b), _pose("pose_b", pose_b)
    )
    return MeshDistance(*raw)


def triangle_intersection(a: ArrayLike, b: ArrayLike) -> TriangleIntersection:
    """What triangles ``a`` and ``b`` (each (3, 3)) share.

    A segment of the line where their planes cross, a point, or (coplanar)
    the polygon they overlap in; every configuration decided with exact
    predicates, only the points rounded.
    """
    kind, points = _nearmiss.triangle_intersection(_floats("a", a), _floats("b", b))
    return TriangleIntersection(kind, points)


def triangle_penetration(a: ArrayLike, b: ArrayLike) -> Optional[TrianglePenetration]:
    """The shortest translation that separates triangles ``a`` and ``b``.

    None when they do not meet. Exact to the rounding of dot products: the
    least reach of their Minkowski difference over its candidate facets.
    """
    found = _nearmiss.triangle_penetration(_floats("a", a), _floats("b", b))
    return None if found is None else TrianglePenetration(*found)


def mesh_intersection(mesh_a: Mesh, pose_a: Pose, mesh_b: Mesh, pose_b: Pose) -> MeshIntersection:
    """Every triangle pair of two posed meshes that meets, and the curve.

    Runs without the GIL.
    """
    pairs, segments, length = _nearmiss.mesh_intersection_between(
        _mesh("mesh_a", mesh_a), _pose("pose_a", pose_a), _mesh("mesh_b", mesh_b), _pose("pose_b", pose_b)
    )
    return MeshIntersection(pairs, segments.reshape(-1, 2, 3), length)


def signed_distance(mesh_a: Mesh, pose_a: Pose, mesh_b: Mesh, pose_b: Pose) -> SignedDistance:
    """The distance between two posed meshes, or minus how deep they overlap.

    Convex meshes get the exact penetration depth (the shortest move that
    separates the solids); closed meshes that are not both convex the local
    depth of the deepest place where their surfaces cross, as a certified
    bracket ``[lower, upper]`` (``value`` is minus ``lower``). Runs without
    the GIL.
    """
    raw = _nearmiss.signed_distance_between(
        _mesh("mesh_a", mesh_a), _pose("pose_a", pose_a), _mesh("mesh_b", mesh_b), _pose("pose_b", pose_b)
    )
    return SignedDistance(*raw)


def mesh_time_of_impact(
    mesh_a: Mesh,
    pose_a: Pose,
    motion_a: Motion,
    mesh_b: Mesh,
    pose_b: Pose,
    motion_b: Motion,
    duration: float = 1.0,
    *,
    distance_tolerance: Optional[float] = None,
    minimum_separation: float = 0.0,
    max_iterations: Optional[int] = None,
    kernel: str = "exact",
) -> TimeOfImpact:
    """The time of first contact of two moving meshes over ``[0, duration]``.

    Each mesh starts at its pose and moves with constant linear and angular
    velocity (the rotation exact, not linearised). Contact is reported
    within ``minimum_separation + distance_tolerance * r`` (``r`` the
    smaller mesh radius; tolerance default 1e-6), never later than the
    true time and never missed; a query that runs out of iterations says
    so (``status == "out_of_iterations"``). ``kernel``: ``"exact"`` or a
    DyOP kernel (``"dyop_vector"``, ``"dyop_heron"``, ...). Runs without
    the GIL.
    """
    raw = _nearmiss.mesh_time_of_impact(
        *_moving(mesh_a, pose_a, motion_a, mesh_b, pose_b, motion_b, duration),
        (
            None if distance_tolerance is None else float(distance_tolerance),
            float(minimum_separation),
            max_iterations,
            kernel,
        ),
    )
    time, status, contact_distance, guaranteed_distance, closest, iterations = raw
    return TimeOfImpact(time, status, contact_distance, guaranteed_distance, _mesh_distance(closest), iterations)


def closest_approach(
    mesh_a: Mesh,
    pose_a: Pose,
    motion_a: Motion,
    mesh_b: Mesh,
    pose_b: Pose,
    motion_b: Motion,
    duration: float = 1.0,
    *,
    within: float = float("inf"),
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
) -> ClosestApproach:
    """The smallest distance of two moving meshes over ``[0, duration]``.

    A certified bracket ``lower <= d* <= upper`` (``upper - lower`` at most
    ``tolerance``, default 1e-6 of the smaller radius), ``upper`` reached at
    ``time`` between ``closest``'s points. Only approaches within
    ``within`` are bracketed (a pair that stays farther costs one CCD run:
    ``status == "beyond"``). Motions as in :func:`mesh_time_of_impact`.
    """
    raw = _nearmiss.closest_approach_between(
        *_moving(mesh_a, pose_a, motion_a, mesh_b, pose_b, motion_b, duration),
        (float(within), None if tolerance is None else float(tolerance), max_iterations),
    )
    status, lower, upper, time, closest, runs = raw
    return ClosestApproach(status, lower, upper, time, _mesh_distance(closest), runs)


class SceneInfo(NamedTuple):
    """What :func:`load_scene` reads of a valid scene."""

    name: str
    bodies: Tuple[str, ...]
    steps: int
    dt: float


def load_scene(path: Union[str, os.PathLike]) -> SceneInfo:
    """Reads and validates a scene file, as ``nearmiss check`` does.

    Raises :class:`SceneError` (a ``ValueError``) with the file, line and
    column or field when it is not valid.
    """
    name, bodies, steps, dt = _nearmiss.load_scene(os.fspath(path))
    return SceneInfo(name, tuple(bodies), steps, dt)


def run_scene(path: Union[str, os.PathLike], *, trace: bool = False) -> Any:
    """Runs a scene file; returns its summary as a dict (``summary.json``).

    With ``trace=True``, returns ``(summary, trace)``, the trace a dict of
    arrays ``step``, ``time``, ``body_a``, ``body_b`` (body indices into
    ``load_scene(path).bodies``) and ``distance``. Raises
    :class:`SceneError` for a scene that is not valid. Runs without the
    GIL.
    """
    text, columns = _nearmiss.run_scene_json(os.fspath(path))
    summary = json.loads(text)
    if not trace:
        return summary
    keys = ("step", "time", "body_a", "body_b", "distance")
    return summary, dict(zip(keys, columns))


# One mesh against many (imports the queries above).
from .collision import Clearance, CollisionManager, FirstContact  # noqa: E402
