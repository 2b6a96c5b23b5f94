"""Shared helpers of the nearmiss package's tests."""

import pathlib

import numpy as np
import pytest

import nearmiss

#: The repository's root (the tests read its shipped scenes and meshes).
ROOT = pathlib.Path(__file__).resolve().parents[2]


def box(half_extents):
    """A closed box mesh centred on its frame's origin, faces outward."""
    hx, hy, hz = half_extents
    vertices = np.array(
        [[sx * hx, sy * hy, sz * hz] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)], dtype=float
    )
    # Corners: index = x + 2 y + 4 z (each 0 for -, 1 for +).
    faces = [
        [0, 2, 3], [0, 3, 1],  # -z
        [4, 5, 7], [4, 7, 6],  # +z
        [0, 1, 5], [0, 5, 4],  # -y
        [2, 6, 7], [2, 7, 3],  # +y
        [0, 4, 6], [0, 6, 2],  # -x
        [1, 3, 7], [1, 7, 5],  # +x
    ]
    return nearmiss.Mesh(vertices, faces)


@pytest.fixture
def cube():
    return box((0.5, 0.5, 0.5))
