"""The wheel's answers are the Rust library's, bit for bit: the same
queries through `cargo run --example rust_answers` (cli/examples/) and
through the package. Needs cargo and the repository (skipped without)."""

import json
import math
import shutil
import subprocess

import numpy as np
import pytest

import nearmiss
from conftest import ROOT, box

pytestmark = pytest.mark.skipif(shutil.which("cargo") is None, reason="needs cargo to run the Rust library")


def rust_answers(queries):
    run = subprocess.run(
        ["cargo", "run", "--quiet", "--release", "-p", "nearmiss-cli", "--example", "rust_answers"],
        input=json.dumps(queries),
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=True,
    )
    return json.loads(run.stdout)


def tumbling_pairs():
    """Boxes and bars passing and hitting each other while turning."""
    rng = np.random.default_rng(11)
    pairs = []
    for k in range(6):
        a = box(tuple(rng.uniform(0.2, 0.8, 3)))
        b = box(tuple(rng.uniform(0.2, 0.8, 3)))
        axis = rng.normal(size=3)
        half = rng.uniform(0, math.pi) / 2
        q = [math.cos(half), *(math.sin(half) * axis / np.linalg.norm(axis))]
        pairs.append(
            dict(
                mesh_a=a,
                mesh_b=b,
                pose_a=([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
                motion_a=(list(rng.normal(size=3) * 0.2), list(rng.normal(size=3) * 3)),
                # Every other one passes 4 to the side (a miss).
                pose_b=(list(rng.uniform(1.5, 2.5, 3) * [1, 0.3, 0.3] + [0, 4.0 * (k % 2), 0]), q),
                motion_b=([-2.0, 0.0, 0.0], list(rng.normal(size=3) * 3)),
                duration=1.0,
            )
        )
    return pairs


def test_the_wheel_answers_as_the_rust_library_does():
    rng = np.random.default_rng(5)
    a = rng.normal(size=(64, 3, 3))
    b = rng.normal(size=(64, 3, 3)) + rng.normal(size=(64, 1, 3)) * 3
    # Segments far from the origin, points near them (where the formulas differ).
    s0 = rng.normal(size=(32, 3)) * 1e3
    s1 = s0 + rng.normal(size=(32, 3))
    p = s0 + rng.normal(size=(32, 3))
    moving = tumbling_pairs()
    queries = {
        "triangle_pairs": [[x.tolist(), y.tolist()] for x, y in zip(a, b)],
        "point_segments": [[x.tolist(), y.tolist(), z.tolist()] for x, y, z in zip(p, s0, s1)],
        "moving_pairs": [
            {
                "vertices_a": m["mesh_a"].vertices.tolist(),
                "faces_a": m["mesh_a"].faces.tolist(),
                "vertices_b": m["mesh_b"].vertices.tolist(),
                "faces_b": m["mesh_b"].faces.tolist(),
                **{k: m[k] for k in ("pose_a", "motion_a", "pose_b", "motion_b", "duration")},
            }
            for m in moving
        ],
    }
    rust = rust_answers(queries)

    for x, y, expected in zip(a, b, rust["triangle_distance"]):
        got = nearmiss.triangle_distance(x, y)
        assert got.distance == expected["distance"]
        assert got.point_a.tolist() == expected["point_a"] and got.point_b.tolist() == expected["point_b"]
        assert (got.feature_a, got.feature_b) == (expected["feature_a"], expected["feature_b"])
        assert nearmiss.dyop_distance(x, y, "vector") == expected["dyop_vector"]
        assert nearmiss.dyop_distance(x, y, "heron") == expected["dyop_heron"]
    assert nearmiss.triangle_distances(a, b).tolist() == rust["triangle_distances"]

    for formula in nearmiss.FORMULAS:
        got = nearmiss.point_segment_distances(p, s0, s1, formula).tolist()
        assert got == [answer[formula] for answer in rust["point_segment_distance"]]

    for m, expected in zip(moving, rust["moving_pairs"]):
        args = (m["mesh_a"], m["pose_a"], m["motion_a"], m["mesh_b"], m["pose_b"], m["motion_b"], m["duration"])
        toi = nearmiss.mesh_time_of_impact(*args)
        assert toi.time == expected["time_of_impact"]
        assert toi.iterations == expected["iterations"]
        approach = nearmiss.closest_approach(*args)
        assert (approach.lower, approach.upper, approach.time) == (
            expected["lower"],
            expected["upper"],
            expected["time"],
        )
        if expected["closest"] is not None:
            assert approach.closest.point_a.tolist() == expected["closest"]["point_a"]
    # The cases include contacts and misses.
    times = [answer["time_of_impact"] for answer in rust["moving_pairs"]]
    assert any(t is None for t in times) and any(t is not None for t in times), times
