"""Triangle and point-segment distances against analytic answers."""

import math

import numpy as np
import pytest

import nearmiss

UNIT = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def test_parallel_triangles_one_apart():
    above = UNIT + [0.0, 0.0, 1.0]
    d = nearmiss.triangle_distance(UNIT, above)
    assert d.distance == 1.0
    assert d.point_b[2] - d.point_a[2] == 1.0
    assert d.within_range


def test_crossing_triangles_are_exactly_zero_apart_with_a_common_point():
    # A vertical triangle through the unit triangle's interior.
    crossing = np.array([[0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [0.5, 0.0, 0.0]])
    d = nearmiss.triangle_distance(UNIT, crossing)
    assert d.distance == 0.0
    assert np.array_equal(d.point_a, d.point_b)


def test_vertex_over_face_and_edge_to_edge():
    # The apex 0.5 above the face's interior point (0.25, 0.25).
    apex_down = np.array([[0.25, 0.25, 0.5], [0.25, 3.0, 2.0], [3.0, 0.25, 2.0]])
    d = nearmiss.triangle_distance(UNIT, apex_down)
    assert d.distance == pytest.approx(0.5, rel=1e-15)
    assert (d.feature_a, d.feature_b) == ("face", "vertex 0")
    # An edge lying 2 straight above the hypotenuse (x + y = 1), the
    # triangle's third vertex farther up.
    skew = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 2.0], [0.5, 0.5, 9.0]])
    d = nearmiss.triangle_distance(UNIT, skew)
    assert d.distance == pytest.approx(2.0, rel=1e-15)


def test_the_batch_gives_each_pairs_distance():
    rng = np.random.default_rng(7)
    a = rng.random((500, 3, 3))
    b = rng.random((500, 3, 3)) + rng.random((500, 1, 3)) * 2.0
    batched = nearmiss.triangle_distances(a, b)
    single = np.array([nearmiss.triangle_distance(x, y).distance for x, y in zip(a, b)])
    assert batched.shape == (500,)
    assert np.array_equal(batched, single)
    closest = nearmiss.triangle_closest_points(a, b)
    assert np.array_equal(closest.distance, single)
    gaps = np.linalg.norm(closest.point_b - closest.point_a, axis=1)
    assert np.allclose(gaps, single, rtol=1e-14, atol=0)
    names = [nearmiss.FEATURES[c] for c in closest.feature_a[:5]]
    assert names == [nearmiss.triangle_distance(x, y).feature_a for x, y in zip(a[:5], b[:5])]


def test_empty_batches():
    empty = np.zeros((0, 3, 3))
    assert nearmiss.triangle_distances(empty, empty).shape == (0,)
    assert nearmiss.point_segment_distances(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)


@pytest.mark.parametrize("formula", nearmiss.FORMULAS)
def test_point_segment_distance_of_every_formula(formula):
    # (0, 3, 4) is 5 from the x axis; from the segment's end past it, the
    # distance to the end point.
    assert nearmiss.point_segment_distance([0.5, 3.0, 4.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], formula) == pytest.approx(5.0, rel=1e-15)
    assert nearmiss.point_segment_distance([4.0, 0.0, 4.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], formula) == pytest.approx(5.0, rel=1e-15)


def test_herons_formula_loses_a_far_points_digits_where_the_vector_formula_does_not():
    # A point 1e-7 off a unit segment, the segment 1e4 from the origin: the
    # seed paper's Heron on side lengths cancels; the default keeps it.
    p, a, b = [1e4 + 0.5, 1e-7, 0.0], [1e4, 0.0, 0.0], [1e4 + 1.0, 0.0, 0.0]
    exact = 1e-7
    vector = nearmiss.point_segment_distance(p, a, b, "vector")
    heron = nearmiss.point_segment_distance(p, a, b, "heron")
    assert abs(vector - exact) <= 1e-15 * 1e4
    assert abs(heron - exact) > 100 * abs(vector - exact)
    batch = nearmiss.point_segment_distances([p, p], [a, a], [b, b], "heron")
    assert np.array_equal(batch, [heron, heron])


def test_dyop_is_exact_vertex_to_vertex_and_never_below_the_distance():
    # Vertex to vertex (1 apart along x): the seed's kernel is exact.
    beside = np.array([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]])
    for formula in nearmiss.FORMULAS:
        assert nearmiss.dyop_distance(UNIT, beside, formula) == 1.0
    # A vertex over the face's interior: it over-estimates (it never looks
    # at vertex-face pairs), never under.
    above = UNIT + [0.2, 0.1, 0.75]
    assert nearmiss.dyop_distance(UNIT, above) > nearmiss.triangle_distance(UNIT, above).distance == 0.75


def test_a_batch_lets_other_python_threads_run():
    # The batch runs without the GIL: the main thread keeps ticking while
    # the worker's call is under way. Held, the GIL would stop it for the
    # whole of the Rust call: one gap between ticks nearly as long as the
    # call (the Python around the call may still share the GIL in turns).
    import threading
    import time

    rng = np.random.default_rng(3)
    a = rng.random((1_500_000, 3, 3))
    b = a + 5.0
    span = {}

    def work():
        span["start"] = time.perf_counter()
        nearmiss.triangle_distances(a, b)
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    during = [t for t in ticks if span["start"] <= t <= span["end"]]
    call = span["end"] - span["start"]
    longest = max(np.diff([span["start"], *during, span["end"]]))
    assert call > 0.02, call
    assert longest < 0.5 * call, (longest, call)
