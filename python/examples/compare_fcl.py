"""nearmiss beside python-fcl's continuousCollide on tumbling meshes.

Ten cases: an icosphere of 320 triangles and one of 1,280, each turning at
up to 3 rad/s while they close at 2 per unit time; over [0, 1] each pair
touches. Both libraries get the same motion: each mesh's frame moves
linearly and turns at a constant angular velocity about its origin (FCL's
linear interpolation motion, ``CCDM_LINEAR``, between the start and end
poses is that motion while the turn is under half a revolution). The truth is sampled with the exact mesh distance at 4,000 times:
the first sample where the meshes overlap and the last before it where
they do not bracket the true time of first contact.

Prints each case's answers, who is right, and each library's time per
query; python-fcl with both solvers it offers for meshes (conservative
advancement, and the naive one that samples the motion). python-fcl is
optional: ``pip install python-fcl`` (without it, only
nearmiss's answers are printed).

Usage: ``python python/examples/compare_fcl.py``
"""

from __future__ import annotations

import math
import time

import numpy as np

import nearmiss

try:
    import fcl
except ImportError:  # python-fcl is optional
    fcl = None


def icosphere(radius: float, subdivisions: int):
    """A sphere of 20 * 4**subdivisions triangles, faces outward."""
    t = (1.0 + 5.0**0.5) / 2.0
    vertices = [
        [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
        [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
        [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
    ]
    faces = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ]
    vertices = [list(np.array(v) / np.linalg.norm(v)) for v in vertices]
    for _ in range(subdivisions):
        middle = {}

        def halfway(i, j):
            key = (min(i, j), max(i, j))
            if key not in middle:
                m = (np.array(vertices[i]) + np.array(vertices[j])) / 2.0
                vertices.append(list(m / np.linalg.norm(m)))
                middle[key] = len(vertices) - 1
            return middle[key]

        faces = [
            f
            for a, b, c in faces
            for ab, bc, ca in [(halfway(a, b), halfway(b, c), halfway(c, a))]
            for f in ([a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca])
        ]
    return np.array(vertices) * radius, np.array(faces)


def rotation(axis_angle: np.ndarray) -> np.ndarray:
    """The rotation matrix of a rotation vector (Rodrigues)."""
    angle = float(np.linalg.norm(axis_angle))
    if angle == 0.0:
        return np.eye(3)
    k = axis_angle / angle
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * cross + (1 - math.cos(angle)) * cross @ cross


def quaternion(matrix: np.ndarray) -> list:
    """[w, x, y, z] of a rotation matrix."""
    w = math.sqrt(max(0.0, 1.0 + np.trace(matrix))) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1 + matrix[0, 0] - matrix[1, 1] - matrix[2, 2])) / 2, matrix[2, 1] - matrix[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - matrix[0, 0] + matrix[1, 1] - matrix[2, 2])) / 2, matrix[0, 2] - matrix[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - matrix[0, 0] - matrix[1, 1] + matrix[2, 2])) / 2, matrix[1, 0] - matrix[0, 1])
    q = np.array([w, x, y, z])
    return list(q / np.linalg.norm(q))


def spin(rng) -> np.ndarray:
    """An angular velocity of at most 3 rad/s: under half a turn over the
    interval, which FCL's interpolation between two poses can express."""
    w = rng.normal(size=3) * 2.0
    return w * min(1.0, 3.0 / np.linalg.norm(w))


def cases(count: int = 10):
    rng = np.random.default_rng(2013)
    for _ in range(count):
        start_a = rotation(rng.normal(size=3))
        start_b = rotation(rng.normal(size=3))
        offset = rng.normal(size=3) * [0.0, 0.35, 0.35]
        yield dict(
            position_a=np.zeros(3),
            rotation_a=start_a,
            velocity_a=np.array([1.0, 0.0, 0.0]),
            spin_a=spin(rng),
            position_b=np.array([2.4, 0.0, 0.0]) + offset,
            rotation_b=start_b,
            velocity_b=np.array([-1.0, 0.0, 0.0]),
            spin_b=spin(rng),
        )


def pose_at(case: dict, body: str, t: float):
    position = case[f"position_{body}"] + case[f"velocity_{body}"] * t
    matrix = rotation(case[f"spin_{body}"] * t) @ case[f"rotation_{body}"]
    return position, matrix


def sampled_truth(mesh_a, mesh_b, case, samples: int = 4000):
    """(last time apart, first time overlapping) of the samples, or None."""
    last_apart = 0.0
    for k in range(samples + 1):
        t = k / samples
        pa, ra = pose_at(case, "a", t)
        pb, rb = pose_at(case, "b", t)
        if nearmiss.mesh_distance(mesh_a, (pa, ra), mesh_b, (pb, rb)).distance == 0.0:
            return last_apart, t
        last_apart = t
    return None


def fcl_time(fcl_a, fcl_b, case, solver):
    """python-fcl's time of contact by `solver` (None: no contact) and the
    seconds it took."""
    def obj(model, body, t):
        position, matrix = pose_at(case, body, t)
        return fcl.CollisionObject(model, fcl.Transform(matrix, position))

    request = fcl.ContinuousCollisionRequest()
    request.ccd_motion_type = fcl.CCDMotionType.CCDM_LINEAR
    request.ccd_solver_type = solver
    request.num_max_iterations = 1000
    request.toc_err = 1e-6
    result = fcl.ContinuousCollisionResult()
    o1, o2 = obj(fcl_a, "a", 0.0), obj(fcl_b, "b", 0.0)
    end_a, end_b = obj(fcl_a, "a", 1.0), obj(fcl_b, "b", 1.0)
    clock = time.perf_counter()
    fcl.continuousCollide(o1, end_a.getTransform(), o2, end_b.getTransform(), request, result)
    seconds = time.perf_counter() - clock
    return (result.time_of_contact if result.is_collide else None), seconds


def fcl_model(vertices, faces):
    model = fcl.BVHModel()
    model.beginModel(len(vertices), len(faces))
    model.addSubModel(vertices, faces)
    model.endModel()
    return model


def verdict(answer, truth):
    """right / late / early (false contact) / missed."""
    if truth is None:
        return "right (no contact)" if answer is None else "false contact"
    apart, touching = truth
    if answer is None:
        return "missed"
    if answer > touching:
        return "late"
    if answer < apart - 1e-3:
        return "early by more than 1e-3"
    return "right"


def main():
    va, fa = icosphere(0.5, 2)  # 320 triangles
    vb, fb = icosphere(0.6, 3)  # 1,280 triangles
    mesh_a, mesh_b = nearmiss.Mesh(va, fa), nearmiss.Mesh(vb, fb)
    models = (fcl_model(va, fa), fcl_model(vb, fb)) if fcl else None
    print(f"meshes: {len(mesh_a)} and {len(mesh_b)} triangles; python-fcl: {'yes' if fcl else 'not installed'}")
    # python-fcl's solvers that take meshes: conservative advancement, and
    # the naive one (samples the motion).
    solvers = {}
    if fcl:
        solvers = {
            "fcl conservative advancement": fcl.CCDSolverType.CCDC_CONSERVATIVE_ADVANCEMENT,
            "fcl naive": fcl.CCDSolverType.CCDC_NAIVE,
        }
    print("| case | truth (sampled bracket) | nearmiss | verdict |" + "".join(f" {name} | verdict |" for name in solvers))
    print("|---|---|---|---|" + "---|---|" * len(solvers))
    seconds = {name: 0.0 for name in ["nearmiss", *solvers]}
    wrong = {name: 0 for name in seconds}
    for n, case in enumerate(cases(), start=1):
        clock = time.perf_counter()
        answer = nearmiss.mesh_time_of_impact(
            mesh_a,
            (case["position_a"], case["rotation_a"]),
            (case["velocity_a"], case["spin_a"]),
            mesh_b,
            (case["position_b"], case["rotation_b"]),
            (case["velocity_b"], case["spin_b"]),
            1.0,
        )
        seconds["nearmiss"] += time.perf_counter() - clock
        truth = sampled_truth(mesh_a, mesh_b, case)
        ours = verdict(answer.time, truth)
        wrong["nearmiss"] += not ours.startswith("right")
        truth_text = "no contact" if truth is None else f"[{truth[0]:.5f}, {truth[1]:.5f}]"
        ours_text = "none" if answer.time is None else f"{answer.time:.6f}"
        row = f"| {n} | {truth_text} | {ours_text} | {ours} |"
        for name, solver in solvers.items():
            theirs, spent = fcl_time(models[0], models[1], case, solver)
            seconds[name] += spent
            their_verdict = verdict(theirs, truth)
            wrong[name] += not their_verdict.startswith("right")
            row += f" {'none' if theirs is None else f'{theirs:.6f}'} | {their_verdict} |"
        print(row)
    print()
    for name in seconds:
        print(f"{name}: {wrong[name]} of 10 wrong, {seconds[name] / 10 * 1e3:.3f} ms a query")


if __name__ == "__main__":
    main()
