"""Bad input: a clear ValueError or TypeError naming the argument, never a
crash, never a silent wrong answer."""

import numpy as np
import pytest

import nearmiss
from conftest import ROOT

UNIT = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
CUBE_VERTICES = [[x, y, z] for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)]


@pytest.mark.parametrize(
    "call, kind, message",
    [
        (lambda: nearmiss.triangle_distance(np.zeros((2, 3)), UNIT), ValueError, "a: expected an array of shape (3, 3), got shape (2, 3)"),
        (lambda: nearmiss.triangle_distance(UNIT, [[0, 0, np.nan], [1, 0, 0], [0, 1, 0]]), ValueError, "b: element [0, 2] is NaN, not a finite number"),
        (lambda: nearmiss.triangle_distance(UNIT, UNIT + [[np.inf, 0, 0], [0, 0, 0], [0, 0, 0]]), ValueError, "not a finite number"),
        (lambda: nearmiss.triangle_distance("abc", UNIT), TypeError, "a: expected numbers"),
        (lambda: nearmiss.triangle_distances(np.zeros((4, 3, 3)), np.zeros((5, 3, 3))), ValueError, "a and b must hold as many items: 4 and 5"),
        (lambda: nearmiss.triangle_distances(np.zeros((4, 3)), np.zeros((4, 3))), ValueError, "expected an array of shape (N, 3, 3)"),
        (lambda: nearmiss.point_segment_distance([0, 0, 0], [1, 0, 0], [2, 0, 0], "herons"), ValueError, "formula: \"herons\" is not one of"),
        (lambda: nearmiss.Mesh(CUBE_VERTICES, [[0, 1, 9]]), ValueError, "triangle 0 refers to vertex 9, but there are only 8 vertices"),
        (lambda: nearmiss.Mesh(CUBE_VERTICES, [[0, -1, 2]]), ValueError, "faces: element [0, 1] is -1, not a vertex index"),
        (lambda: nearmiss.Mesh(CUBE_VERTICES, [[0.0, 1.0, 2.0]]), TypeError, "faces: expected numbers of dtype int64, got dtype float64"),
        (lambda: nearmiss.Mesh(CUBE_VERTICES, np.zeros((0, 3), dtype=int)), ValueError, "the mesh has no triangles"),
        (lambda: nearmiss.Mesh([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], [[0, 1, 2]]), ValueError, "vertices: element [2, 1] is NaN"),
        (lambda: nearmiss.Mesh.from_obj(ROOT / "no such.obj"), ValueError, "no such.obj"),
    ],
)
def test_bad_arrays(call, kind, message):
    with pytest.raises(kind) as raised:
        call()
    assert message in str(raised.value)


def test_zero_area_faces_are_kept_and_short_obj_faces_dropped_with_counts(tmp_path):
    # A segment (a face with a repeated vertex) is a mesh: its distance to
    # a point-like triangle far along x is the segment's.
    segment = nearmiss.Mesh([[0, 0, 0], [1, 0, 0]], [[0, 1, 1]])
    assert segment.zero_area_triangles == 1 and segment.dropped_faces == 0
    assert "1 of zero area" in repr(segment)
    tiny = nearmiss.Mesh([[3, 0, 0], [3, 1e-9, 0], [3, 0, 1e-9]], [[0, 1, 2]])
    assert nearmiss.mesh_distance(segment, None, tiny, None).distance == 2.0
    obj = tmp_path / "lines.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 3\nf 2\n")
    mesh = nearmiss.Mesh.from_obj(obj)
    assert (len(mesh), mesh.zero_area_triangles, mesh.dropped_faces) == (2, 1, 2)


def test_bad_poses_and_motions():
    cube = nearmiss.Mesh(CUBE_VERTICES, [[0, 1, 3]])
    at = [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match=r"pose_a rotation: a quaternion \[w, x, y, z\] must have norm 1"):
        nearmiss.mesh_distance(cube, (at, [1.0, 1.0, 0.0, 0.0]), cube, None)
    with pytest.raises(ValueError, match="pose_b rotation: not a rotation matrix"):
        nearmiss.mesh_distance(cube, None, cube, (at, -np.eye(3)))
    with pytest.raises(ValueError, match=r"expected a quaternion \(4,\) or a rotation matrix \(3, 3\), got shape \(2,\)"):
        nearmiss.mesh_distance(cube, (at, [1.0, 0.0]), cube, None)
    with pytest.raises(TypeError, match="pose_a: expected \\(position, rotation\\)"):
        nearmiss.mesh_distance(cube, 3.0, cube, None)
    with pytest.raises(ValueError, match="a velocity: element \\[1\\] is inf"):
        nearmiss.mesh_time_of_impact(cube, None, ([0, np.inf, 0], [0, 0, 0]), cube, (at, [1, 0, 0, 0]), None)
    with pytest.raises(ValueError, match="duration: -1 is not a positive number"):
        nearmiss.mesh_time_of_impact(cube, None, None, cube, None, None, -1.0)
    with pytest.raises(ValueError, match="kernel:"):
        nearmiss.mesh_time_of_impact(cube, None, None, cube, None, None, 1.0, kernel="approximate")
    with pytest.raises(TypeError, match="mesh_b: expected a nearmiss.Mesh"):
        nearmiss.mesh_distance(cube, None, "cube", None)


def test_bad_scenes_name_the_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.ron"
    bad.write_text(
        'Scene(name: "x", dt: 0.01, steps: 10, bodies: [\n'
        '    (name: "a", mesh: Box(half_extents: (1.0, 1.0)), fixed: true),\n'
        "])\n"
    )
    with pytest.raises(nearmiss.SceneError) as raised:
        nearmiss.load_scene(bad)
    assert f"{bad}:2:" in str(raised.value)
    assert isinstance(raised.value, ValueError)
    with pytest.raises(nearmiss.SceneError, match="cannot read the scene file"):
        nearmiss.run_scene(tmp_path / "missing.ron")
    typo = tmp_path / "typo.ron"
    typo.write_text('Scene(name: "x", dt: 0.01, stepz: 10, bodies: [])\n')
    with pytest.raises(nearmiss.SceneError, match="stepz"):
        nearmiss.run_scene(typo)


def test_the_package_says_its_version():
    """``nearmiss.__version__`` is the version the package was built as:
    pyproject.toml's, and the installed distribution's."""
    import importlib.metadata
    import re

    text = (ROOT / "python" / "pyproject.toml").read_text()
    declared = re.search(r'^version\s*=\s*"([^"]+)"', text, re.MULTILINE).group(1)
    assert nearmiss.__version__ == declared
    assert importlib.metadata.version("nearmiss") == declared


def test_float32_and_noisy_rotations_are_made_rotations_again():
    """A rotation stored in float32 or carrying 1e-7 of noise is
    re-orthonormalised (issue 46: the old 1e-9 tolerance refused 100 of 100
    float32 matrices); one 1e-4 off is refused, saying how to fix it."""
    cube = nearmiss.Mesh(CUBE_VERTICES, [[0, 1, 3]])
    rng = np.random.default_rng(46)
    for _ in range(100):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w, x, y, z = q
        matrix = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
            ]
        )
        exact = nearmiss.mesh_distance(cube, None, cube, ([2.0, 0.5, 0.3], matrix)).distance
        for rotation in (matrix.astype(np.float32), q.astype(np.float32), matrix + rng.normal(size=(3, 3)) * 1e-7):
            d = nearmiss.mesh_distance(cube, None, cube, ([2.0, 0.5, 0.3], rotation)).distance
            # The rotation moved by ~1e-7: the distance by that times the reach.
            assert abs(d - exact) <= 1e-6
    with pytest.raises(ValueError, match=r"pose_b rotation: not a rotation matrix .* take its nearest rotation first"):
        nearmiss.mesh_distance(cube, None, cube, ([0, 0, 0], np.eye(3) + 1e-4))
    with pytest.raises(ValueError, match=r"divide it by its norm"):
        nearmiss.mesh_distance(cube, None, cube, ([0, 0, 0], [1.0, 1e-2, 0.0, 0.0]))
