"""Scene runs from Python: the summary as summary.json holds it, checked
against the shipped scenes' analytic answers."""

import math

import numpy as np

import nearmiss
from conftest import ROOT

SCENES = ROOT / "scenes"


def test_the_spinning_blade_touches_at_its_analytic_time_never_late():
    summary = nearmiss.run_scene(SCENES / "spinning_blade.ron")
    analytic = (math.pi / 3 - math.asin(0.025)) / 10  # derived in the scene's header
    first = summary["first_contact"]
    assert first["time"] <= analytic and analytic - first["time"] < 1e-9
    assert (first["body_a"], first["body_b"]) == ("blade", "probe")
    for key in ("scene", "steps", "wall_time_s", "contacts", "termination"):
        assert key in summary


def test_a_clearance_run_lists_its_certified_near_miss_and_its_trace():
    summary, trace = nearmiss.run_scene(SCENES / "bar_clearance.ron", trace=True)
    clearance = 1.1 - math.sqrt(1.01)
    (miss,) = summary["near_misses"]
    assert miss["lower"] <= clearance <= miss["distance"] * (1 + 1e-12)
    assert miss["distance"] - miss["lower"] <= 1e-6 * 1.01
    info = nearmiss.load_scene(SCENES / "bar_clearance.ron")
    assert info.bodies == ("block", "bar") and info.steps == 15
    assert set(trace) == {"step", "time", "body_a", "body_b", "distance"}
    assert trace["time"].shape == (16,) and trace["distance"].dtype == np.float64
    # The samples at the step ends never go below the certified bound.
    assert trace["distance"].min() >= miss["lower"]
