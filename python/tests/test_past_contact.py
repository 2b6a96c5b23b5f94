"""Past contact from Python: what two triangles share and how deep they
are, where two meshes' surfaces cross, and their signed distance, against
analytic answers."""

import math

import numpy as np
import pytest

import nearmiss
from conftest import box


def torus(major, minor, around, across):
    """A torus about z as a nearmiss.Mesh (faces outward)."""
    u = np.arange(around) * 2 * math.pi / around
    w = np.arange(across) * 2 * math.pi / across
    ring = major + minor * np.cos(w)[None, :]
    x, y = ring * np.cos(u)[:, None], ring * np.sin(u)[:, None]
    z = np.broadcast_to(minor * np.sin(w)[None, :], x.shape)
    vertices = np.stack([x, y, z], -1).reshape(-1, 3)
    index = lambda i, j: (i % around) * across + (j % across)
    faces = []
    for i in range(around):
        for j in range(across):
            faces.append([index(i, j), index(i + 1, j), index(i + 1, j + 1)])
            faces.append([index(i, j), index(i + 1, j + 1), index(i, j + 1)])
    return nearmiss.Mesh(vertices, np.array(faces))


def test_a_blade_through_a_plate():
    plate = np.array([[-1.0, -1.0, 0.0], [3.0, -1.0, 0.0], [-1.0, 3.0, 0.0]])
    # In x = 0, apex 0.25 below the plate, top edge 0.5 above it.
    blade = np.array([[0.0, 0.0, -0.25], [0.0, -0.5, 0.5], [0.0, 0.5, 0.5]])
    shared = nearmiss.triangle_intersection(plate, blade)
    assert shared.kind == "segment" and shared.points.shape == (2, 3)
    ys = sorted(shared.points[:, 1])
    assert ys == pytest.approx([-1 / 6, 1 / 6], abs=1e-15)
    assert np.all(shared.points[:, 2] == 0.0)
    depth = nearmiss.triangle_penetration(plate, blade)
    assert depth.depth == pytest.approx(0.25, abs=1e-15)
    assert depth.direction == pytest.approx([0.0, 0.0, 1.0], abs=1e-15)
    # Apart: disjoint, no depth.
    lifted = blade + [0.0, 0.0, 1.0]
    assert nearmiss.triangle_intersection(plate, lifted).kind == "disjoint"
    assert nearmiss.triangle_penetration(plate, lifted) is None


def test_coplanar_triangles_share_a_polygon():
    a = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    b = np.array([[1.0, -1.0, 0.0], [1.0, 3.0, 0.0], [-1.0, 1.0, 0.0]])
    shared = nearmiss.triangle_intersection(a, b)
    assert shared.kind == "polygon" and len(shared.points) >= 3
    # Every corner of the shared polygon lies on both triangles' closed sets.
    for p in shared.points:
        assert p[0] >= -1e-15 and p[1] >= -1e-15 and p[0] + p[1] <= 2 + 1e-15


def test_a_cube_through_a_plate_crosses_along_two_squares():
    cube, plate = box((1.0, 1.0, 1.0)), box((2.0, 2.0, 0.1))
    found = nearmiss.mesh_intersection(cube, None, plate, ([0.1, 0.2, 0.0], [1.0, 0.0, 0.0, 0.0]))
    assert found.length == pytest.approx(16.0, rel=1e-12)
    assert found.segments.shape[1:] == (2, 3) and found.pairs.shape[1] == 2
    assert np.allclose(np.abs(found.segments[:, :, 2]), 0.1, atol=1e-15)


def test_signed_distance_of_boxes_and_a_ring():
    big, small = box((1.0, 1.0, 1.0)), box((0.5, 0.5, 0.5))
    at = lambda x, y, z: ([x, y, z], [1.0, 0.0, 0.0, 0.0])
    apart = nearmiss.signed_distance(big, None, small, at(1.75, 0.0, 0.0))
    assert apart.kind == "apart" and apart.value == pytest.approx(0.25, rel=1e-15)
    overlapping = nearmiss.signed_distance(big, None, small, at(1.3, 0.2, 0.0))
    assert overlapping.kind == "convex" and overlapping.value == pytest.approx(-0.2, abs=1e-15)
    assert overlapping.direction == pytest.approx([1.0, 0.0, 0.0], abs=1e-15)
    inside = nearmiss.signed_distance(big, None, small, at(0.1, 0.0, 0.0))
    assert inside.value == pytest.approx(-1.4, abs=1e-15)
    # A ring (not convex) dipped 0.1 into a slab: its local depth.
    ring, slab = torus(1.0, 0.25, 128, 64), box((3.0, 3.0, 0.5))
    dipped = nearmiss.signed_distance(ring, None, slab, at(0.0, 0.0, -0.25 + 0.1 - 0.5))
    assert dipped.kind == "local"
    assert dipped.value == pytest.approx(-0.1, abs=1e-3)
    assert dipped.lower <= 0.1 + 1e-3 and dipped.upper >= 0.1 - 1e-3


def test_past_contact_arguments_are_checked():
    with pytest.raises(ValueError, match="a"):
        nearmiss.triangle_intersection(np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="b"):
        nearmiss.triangle_penetration(np.zeros((3, 3)), [[0, 0, 0], [1, 0, float("nan")], [0, 1, 0]])
