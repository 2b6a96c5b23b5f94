"""Type stubs of the extension module `nearmiss._nearmiss` (Rust, pyo3).

Call the package `nearmiss` instead: it converts arguments, names the
results and documents them. Every array argument here must already be a
float64 numpy array; shapes and finiteness are checked (ValueError).
"""

from os import PathLike
from typing import List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
PoseArrays = Tuple[FloatArray, FloatArray]
MotionArrays = Tuple[FloatArray, FloatArray]
MeshDistanceTuple = Tuple[float, FloatArray, FloatArray, int, int, str, str]

__version__: str

class SceneError(ValueError):
    """A scene file that cannot be read or is not valid."""

class Mesh:
    """A triangle mesh (validated, with its bounding-volume tree)."""

    def __init__(self, vertices: npt.ArrayLike, faces: npt.ArrayLike) -> None: ...
    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Mesh: ...
    @staticmethod
    def from_obj(path: Union[str, PathLike[str]]) -> Mesh: ...
    @property
    def vertices(self) -> FloatArray: ...
    @property
    def faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def radius(self) -> float: ...
    @property
    def zero_area_triangles(self) -> int: ...
    @property
    def dropped_faces(self) -> int: ...
    def pivoted(self, about: FloatArray) -> Mesh: ...
    def __len__(self) -> int: ...

def triangle_distance(a: FloatArray, b: FloatArray) -> Tuple[float, FloatArray, FloatArray, str, str, bool]: ...
def triangle_distances(a: FloatArray, b: FloatArray) -> FloatArray: ...
def triangle_closest_points(
    a: FloatArray, b: FloatArray
) -> Tuple[FloatArray, FloatArray, FloatArray, npt.NDArray[np.int8], npt.NDArray[np.int8]]: ...
def point_segment_distance(p: FloatArray, a: FloatArray, b: FloatArray, formula: str) -> float: ...
def point_segment_distances(p: FloatArray, a: FloatArray, b: FloatArray, formula: str) -> FloatArray: ...
def dyop_distance(a: FloatArray, b: FloatArray, formula: str) -> float: ...
def mesh_distance_between(mesh_a: Mesh, pose_a: PoseArrays, mesh_b: Mesh, pose_b: PoseArrays) -> MeshDistanceTuple: ...
def triangle_intersection(a: FloatArray, b: FloatArray) -> Tuple[str, FloatArray]: ...
def triangle_penetration(a: FloatArray, b: FloatArray) -> Optional[Tuple[float, FloatArray]]: ...
def mesh_intersection_between(
    mesh_a: Mesh, pose_a: PoseArrays, mesh_b: Mesh, pose_b: PoseArrays
) -> Tuple[npt.NDArray[np.uint64], FloatArray, float]: ...
def signed_distance_between(
    mesh_a: Mesh, pose_a: PoseArrays, mesh_b: Mesh, pose_b: PoseArrays
) -> Tuple[float, str, Optional[float], Optional[float], Optional[FloatArray]]: ...
def mesh_time_of_impact(
    a: Tuple[Mesh, PoseArrays, MotionArrays],
    b: Tuple[Mesh, PoseArrays, MotionArrays],
    duration: float,
    options: Tuple[Optional[float], float, Optional[int], str],
) -> Tuple[Optional[float], str, float, float, Optional[MeshDistanceTuple], int]: ...
def closest_approach_between(
    a: Tuple[Mesh, PoseArrays, MotionArrays],
    b: Tuple[Mesh, PoseArrays, MotionArrays],
    duration: float,
    options: Tuple[float, Optional[float], Optional[int]],
) -> Tuple[str, float, float, float, Optional[MeshDistanceTuple], int]: ...
def motion_between(
    pose0: PoseArrays, pose1: PoseArrays, duration: float, about: FloatArray
) -> Tuple[FloatArray, FloatArray, FloatArray, FloatArray]: ...
def load_scene(path: Union[str, PathLike[str]]) -> Tuple[str, List[str], int, float]: ...
def run_scene_json(
    path: Union[str, PathLike[str]],
) -> Tuple[
    str,
    Tuple[
        npt.NDArray[np.uint64],
        FloatArray,
        npt.NDArray[np.uint64],
        npt.NDArray[np.uint64],
        FloatArray,
    ],
]: ...
