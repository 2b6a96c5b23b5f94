"""One mesh against many: a collection of named, posed meshes with a broad
phase inside, under the names and return shapes of trimesh's
``trimesh.collision.CollisionManager``, so that it drops in where trimesh
users have one.

Each object keeps its mesh's box in its own frame; a pose gives the
world box of that box's eight corners, which holds the mesh. Candidate
pairs are those whose world boxes touch (for collisions) or whose boxes'
gap is below the nearest distance found so far (for distances, taken in
the order of that gap): the answers are the exact ones of
:func:`nearmiss.mesh_distance` over every pair, with the pairs that cannot
matter never measured.

Surfaces, as in FCL and trimesh: two meshes are in collision when their
surfaces touch or cross (a mesh wholly inside another is not), and the
distance of meshes in collision is 0.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Set, Tuple

import numpy as np

from . import _mesh, _pose, mesh_distance

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


def _matrix(name: str, transform: Any) -> np.ndarray:
    """A pose as a 4 x 4 transform (checked as every query checks poses)."""
    position, rotation = _pose(name, transform)
    rotation = np.asarray(rotation, dtype=float)
    matrix = np.eye(4)
    if rotation.shape == (3, 3):
        matrix[:3, :3] = rotation
    else:  # a quaternion [w, x, y, z]
        w, x, y, z = rotation / np.linalg.norm(rotation)
        matrix[:3, :3] = [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    matrix[:3, 3] = position
    return matrix


def _local_box(mesh: Any) -> np.ndarray:
    vertices = mesh.vertices
    return np.array([vertices.min(axis=0), vertices.max(axis=0)])


def _world_box(local: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """The world box of a local box's eight corners under ``matrix``,
    widened by a few ulps of its reach for the rounding of the transform."""
    corners = np.array([[local[i][0], local[j][1], local[k][2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    world = corners @ matrix[:3, :3].T + matrix[:3, 3]
    low, high = world.min(axis=0), world.max(axis=0)
    slack = 8 * np.finfo(float).eps * (np.abs(world).max() + 1e-300)
    return np.array([low - slack, high + slack])


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    """The distance between two boxes (0 where they touch): a lower bound
    on the distance of anything inside them."""
    separation = np.maximum(0.0, np.maximum(a[0] - b[1], b[0] - a[1]))
    return float(np.sqrt(separation @ separation))


class CollisionManager:
    """Named meshes with poses; collisions and distances of one mesh
    against them all (``*_single``) or among them (``*_internal``).

    Meshes are ``nearmiss.Mesh`` objects or anything with ``vertices`` and
    ``faces`` (a ``trimesh.Trimesh``); transforms are 4 x 4 homogeneous
    matrices (or any pose the queries take), ``None`` for the identity.
    """

    def __init__(self) -> None:
        self._objects: Dict[str, Tuple[Any, np.ndarray, np.ndarray, np.ndarray]] = {}

    def add_object(self, name: str, mesh: Any, transform: Any = None) -> None:
        """Adds (or replaces) the object ``name``."""
        converted = _mesh(f"mesh of {name!r}", mesh)
        matrix = _matrix(f"transform of {name!r}", transform)
        local = _local_box(converted)
        self._objects[name] = (converted, matrix, local, _world_box(local, matrix))

    def remove_object(self, name: str) -> None:
        if name not in self._objects:
            raise ValueError(f"{name} not in collision manager!")
        del self._objects[name]

    def set_transform(self, name: str, transform: Any) -> None:
        if name not in self._objects:
            raise ValueError(f"{name} not in collision manager!")
        mesh, _, local, _ = self._objects[name]
        matrix = _matrix(f"transform of {name!r}", transform)
        self._objects[name] = (mesh, matrix, local, _world_box(local, matrix))

    def _query(self, mesh: Any, transform: Any) -> Tuple[Any, np.ndarray, np.ndarray]:
        converted = _mesh("mesh", mesh)
        matrix = _matrix("transform", transform)
        return converted, matrix, _world_box(_local_box(converted), matrix)

    def in_collision_single(self, mesh: Any, transform: Any = None, return_names: bool = False, return_data: bool = False):
        """Whether ``mesh`` at ``transform`` touches any object: a bool, then
        (as asked) the set of names it touches and a list of
        :class:`ContactData`."""
        query, matrix, box = self._query(mesh, transform)
        names: Set[str] = set()
        data: List[ContactData] = []
        for name, (other, other_matrix, _, other_box) in self._objects.items():
            if _gap(box, other_box) > 0.0:
                continue
            found = mesh_distance(other, other_matrix, query, matrix)
            if found.distance == 0.0:
                names.add(name)
                data.append(ContactData((name, EXTERNAL), found.point_a))
        return _shaped(bool(names), names, data, return_names, return_data)

    def in_collision_internal(self, return_names: bool = False, return_data: bool = False):
        """Whether any two objects touch: a bool, then (as asked) the set of
        touching pairs as sorted name tuples and a list of
        :class:`ContactData`."""
        pairs: Set[Tuple[str, str]] = set()
        data: List[ContactData] = []
        for a, b in self._touching_boxes():
            mesh_a, matrix_a, _, _ = self._objects[a]
            mesh_b, matrix_b, _, _ = self._objects[b]
            found = mesh_distance(mesh_a, matrix_a, mesh_b, matrix_b)
            if found.distance == 0.0:
                pairs.add(tuple(sorted((a, b))))
                data.append(ContactData((a, b), found.point_a))
        return _shaped(bool(pairs), pairs, data, return_names, return_data)

    def _touching_boxes(self) -> List[Tuple[str, str]]:
        """The pairs of objects whose world boxes touch (a sweep along x)."""
        names = list(self._objects)
        if len(names) < 2:
            return []
        boxes = np.array([self._objects[n][3] for n in names])
        order = np.argsort(boxes[:, 0, 0], kind="stable")
        pairs = []
        for k, i in enumerate(order):
            for j in order[k + 1 :]:
                if boxes[j, 0, 0] > boxes[i, 1, 0]:
                    break
                if np.all(boxes[i, 0] <= boxes[j, 1]) and np.all(boxes[j, 0] <= boxes[i, 1]):
                    pairs.append((names[i], names[j]))
        return pairs

    def min_distance_single(self, mesh: Any, transform: Any = None, return_name: bool = False, return_data: bool = False):
        """The least distance from ``mesh`` at ``transform`` to any object
        (0 where it touches one; ``inf`` with no objects), then (as asked) the
        nearest object's name and a :class:`DistanceData`."""
        query, matrix, box = self._query(mesh, transform)
        candidates = sorted((_gap(box, entry[3]), name) for name, entry in self._objects.items())
        best, best_name, best_points = float("inf"), None, None
        for gap, name in candidates:
            if gap >= best:
                break
            other, other_matrix, _, _ = self._objects[name]
            found = mesh_distance(other, other_matrix, query, matrix)
            if found.distance < best:
                best, best_name, best_points = found.distance, name, (found.point_a, found.point_b)
        data = None if best_name is None else DistanceData((best_name, EXTERNAL), best, best_points)
        return _shaped(best, best_name, data, return_name, return_data)

    def min_distance_internal(self, name: Optional[str] = None, return_names: bool = False, return_data: bool = False):
        """The least distance between two objects (of ``name`` to the others
        where given; ``inf`` with fewer than two), then (as asked) their
        names as a sorted tuple and a :class:`DistanceData`."""
        if name is not None and name not in self._objects:
            raise ValueError(f"{name} not in collision manager!")
        names = list(self._objects)
        pairs = [
            (_gap(self._objects[a][3], self._objects[b][3]), a, b)
            for i, a in enumerate(names)
            for b in names[i + 1 :]
            if name is None or name in (a, b)
        ]
        pairs.sort(key=lambda p: p[0])
        best, best_pair, best_points = float("inf"), None, None
        for gap, a, b in pairs:
            if gap >= best:
                break
            mesh_a, matrix_a, _, _ = self._objects[a]
            mesh_b, matrix_b, _, _ = self._objects[b]
            found = mesh_distance(mesh_a, matrix_a, mesh_b, matrix_b)
            if found.distance < best:
                best, best_pair, best_points = found.distance, (a, b), (found.point_a, found.point_b)
        data = None if best_pair is None else DistanceData(best_pair, best, best_points)
        sorted_names = None if best_pair is None else tuple(sorted(best_pair))
        return _shaped(best, sorted_names, data, return_names, return_data)


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
