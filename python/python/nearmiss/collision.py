"""One mesh against many: a collection of named, posed meshes with a broad
phase inside (the library's ``nearmiss::collection``), under the names and
return shapes of trimesh's ``trimesh.collision.CollisionManager``, so that
it drops in where trimesh users have one, and with what no peer manager
has: the first contact (never late) and the certified clearance of a mesh
*moving* against every object (:meth:`CollisionManager.time_of_impact_single`,
:meth:`CollisionManager.closest_approach_single`).

Each object keeps its world box; only the objects whose boxes can matter
are measured (those touching the query's box for collisions, the rest in
the order of their box's gap until it passes the best distance found).
Distances are the exact ones of :func:`nearmiss.mesh_distance`.

Surfaces, as in FCL and trimesh: two meshes are in collision when their
surfaces touch or cross (a mesh wholly inside another is not), and the
distance of meshes in collision is 0.
"""

from __future__ import annotations

from typing import Any, List, NamedTuple, Optional, Set, Tuple

import numpy as np

from . import MeshDistance, Motion, Pose, _body, _mesh, _mesh_distance, _nearmiss, _pose

#: The name trimesh gives the query mesh of the ``*_single`` calls in the
#: names of their data.
EXTERNAL = "__external"


class ContactData:
    """Where two objects touch: ``names`` (a set of the two names) and
    ``point``, a point common to both surfaces (world frame)."""

    def __init__(self, names: Tuple[str, str], point: np.ndarray) -> None:
        self.names = set(names)
        self._point = point

    @property
    def point(self) -> np.ndarray:
        return self._point

    @property
    def normal(self) -> np.ndarray:
        raise NotImplementedError(_NO_NORMAL_OR_DEPTH)

    @property
    def depth(self) -> float:
        raise NotImplementedError(_NO_NORMAL_OR_DEPTH)


_NO_NORMAL_OR_DEPTH = (
    "nearmiss's manager reports where surfaces touch (point), not a contact normal or depth: "
    "nearmiss.signed_distance gives the depth of closed meshes"
)


class DistanceData:
    """The nearest pair: ``names`` (a set), ``distance`` and ``point(name)``,
    each object's nearest point (world frame)."""

    def __init__(self, names: Tuple[str, str], distance: float, points: Tuple[np.ndarray, np.ndarray]) -> None:
        self.names = set(names)
        self._distance = distance
        self._points = {names[0]: points[0], names[1]: points[1]}

    @property
    def distance(self) -> float:
        return self._distance

    def point(self, name: str) -> np.ndarray:
        return self._points[name]


class FirstContact(NamedTuple):
    """The answer of :meth:`CollisionManager.time_of_impact_single`."""

    #: ``"clear"`` (no object is touched over the interval, certified),
    #: ``"contact"`` or ``"undecided"`` (a pair's CCD ran out of iterations
    #: at ``time``: nothing is touched before it, nothing known after).
    status: str
    #: The time of first contact (never later than the true one), where the
    #: query could not decide, or the duration when clear.
    time: float
    #: The object touched (or whose pair was undecided).
    name: Optional[str]
    #: At contact: a triangle pair within the contact distance there
    #: (``point_a`` on the object, ``point_b`` on the moving mesh).
    closest: Optional[MeshDistance]
    #: The pair's contact distance: no contact is reported farther apart.
    contact_distance: Optional[float]
    #: Objects whose boxes let them near the mesh's swept box.
    candidates: int


class Clearance(NamedTuple):
    """The answer of :meth:`CollisionManager.closest_approach_single`:
    the smallest distance ``d*`` to any object over the interval satisfies
    ``lower <= d* <= upper``."""

    #: ``"bracketed"``, ``"contact"`` (it touches an object; ``time`` is a
    #: time of first contact), ``"beyond"`` (nothing within ``within``),
    #: ``"out_of_iterations"`` or ``"undecided"``.
    status: str
    #: Certified: the mesh is never closer than this to any object.
    lower: float
    #: Reached: at ``time`` the mesh is this far from ``name`` (inf when beyond).
    upper: float
    time: float
    #: The nearest object at ``time``.
    name: Optional[str]
    #: The closest points there (``point_a`` on the object).
    closest: Optional[MeshDistance]
    #: CCD runs taken.
    runs: int
    #: Objects bracketed (those whose boxes let them within reach).
    candidates: int


class CollisionManager:
    """Named meshes with poses; collisions and distances of one mesh
    against them all (``*_single``) or among them (``*_internal``), and the
    first contact and clearance of a moving mesh against them all.

    Meshes are ``nearmiss.Mesh`` objects or anything with ``vertices`` and
    ``faces`` (a ``trimesh.Trimesh``); transforms are 4 x 4 homogeneous
    matrices (or any pose the queries take), ``None`` for the identity.
    """

    def __init__(self) -> None:
        self._collection = _nearmiss.Collection()

    def add_object(self, name: str, mesh: Any, transform: Any = None) -> None:
        """Adds (or replaces) the object ``name``."""
        self._collection.insert(name, _mesh(f"mesh of {name!r}", mesh), _pose(f"transform of {name!r}", transform))

    def remove_object(self, name: str) -> None:
        if name not in self._collection:
            raise ValueError(f"{name} not in collision manager!")
        self._collection.remove(name)

    def set_transform(self, name: str, transform: Any) -> None:
        if name not in self._collection:
            raise ValueError(f"{name} not in collision manager!")
        self._collection.set_pose(name, _pose(f"transform of {name!r}", transform))

    def in_collision_single(self, mesh: Any, transform: Any = None, return_names: bool = False, return_data: bool = False):
        """Whether ``mesh`` at ``transform`` touches any object: a bool, then
        (as asked) the set of names it touches and a list of
        :class:`ContactData`."""
        found = self._collection.in_collision(_mesh("mesh", mesh), _pose("transform", transform))
        names: Set[str] = {name for name, _, _ in found}
        data = [ContactData((name, EXTERNAL), distance[1]) for name, _, distance in found]
        return _shaped(bool(names), names, data, return_names, return_data)

    def in_collision_internal(self, return_names: bool = False, return_data: bool = False):
        """Whether any two objects touch: a bool, then (as asked) the set of
        touching pairs as sorted name tuples and a list of
        :class:`ContactData`."""
        found = self._collection.in_collision_internal()
        pairs: Set[Tuple[str, str]] = {tuple(sorted((a, b))) for a, b, _ in found}
        data = [ContactData((a, b), distance[1]) for a, b, distance in found]
        return _shaped(bool(pairs), pairs, data, return_names, return_data)

    def min_distance_single(self, mesh: Any, transform: Any = None, return_name: bool = False, return_data: bool = False):
        """The least distance from ``mesh`` at ``transform`` to any object
        (0 where it touches one; ``inf`` with no objects), then (as asked) the
        nearest object's name and a :class:`DistanceData`."""
        found = self._collection.min_distance(_mesh("mesh", mesh), _pose("transform", transform))
        if found is None:
            return _shaped(float("inf"), None, None, return_name, return_data)
        name, _, distance = found
        data = DistanceData((name, EXTERNAL), distance[0], (distance[1], distance[2]))
        return _shaped(distance[0], name, data, return_name, return_data)

    def min_distance_internal(self, name: Optional[str] = None, return_names: bool = False, return_data: bool = False):
        """The least distance between two objects (of ``name`` to the others
        where given; ``inf`` with fewer than two), then (as asked) their
        names as a sorted tuple and a :class:`DistanceData`."""
        if name is not None and name not in self._collection:
            raise ValueError(f"{name} not in collision manager!")
        found = self._collection.min_distance_internal(name)
        if found is None:
            return _shaped(float("inf"), None, None, return_names, return_data)
        a, b, distance = found
        data = DistanceData((a, b), distance[0], (distance[1], distance[2]))
        return _shaped(distance[0], tuple(sorted((a, b))), data, return_names, return_data)

    def time_of_impact_single(
        self,
        mesh: Any,
        transform: Pose = None,
        motion: Motion = None,
        duration: float = 1.0,
        *,
        distance_tolerance: Optional[float] = None,
        minimum_separation: float = 0.0,
        max_iterations: Optional[int] = None,
    ) -> FirstContact:
        """The first contact of ``mesh``, starting at ``transform`` and moving
        by ``motion`` over ``[0, duration]``, with any object (which stay
        put): never later than the true time, never missed, each pair's
        contact distance as in :func:`nearmiss.mesh_time_of_impact`.
        ``motion``: ``(velocity, angular_velocity)`` or a
        :func:`nearmiss.motion_between` (with ``None`` as the transform)."""
        raw = self._collection.first_contact(
            _body("", mesh, transform, motion),
            float(duration),
            (None if distance_tolerance is None else float(distance_tolerance), float(minimum_separation), max_iterations),
        )
        status, time, name, closest, contact_distance, candidates = raw
        return FirstContact(status, time, name, _mesh_distance(closest), contact_distance, candidates)

    def closest_approach_single(
        self,
        mesh: Any,
        transform: Pose = None,
        motion: Motion = None,
        duration: float = 1.0,
        *,
        within: float = float("inf"),
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
    ) -> Clearance:
        """The certified clearance of ``mesh`` moving as in
        :meth:`time_of_impact_single` from every object: a bracket
        ``lower <= d* <= upper`` on its smallest distance to any of them over
        the interval (``upper - lower`` at most ``tolerance``, default 1e-6
        of a pair's smaller radius), only approaches within ``within``
        bracketed."""
        raw = self._collection.clearance(
            _body("", mesh, transform, motion),
            float(duration),
            (float(within), None if tolerance is None else float(tolerance), max_iterations),
        )
        status, lower, upper, time, name, closest, runs, candidates = raw
        return Clearance(status, lower, upper, time, name, _mesh_distance(closest), runs, candidates)


def _shaped(result: Any, names: Any, data: Any, return_names: bool, return_data: bool):
    """trimesh's return shapes: the result, then the names and the data
    where asked for."""
    if return_names and return_data:
        return result, names, data
    if return_names:
        return result, names
    if return_data:
        return result, data
    return result
