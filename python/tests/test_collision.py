"""nearmiss.CollisionManager: one mesh against many, under trimesh's
names and return shapes. Analytic answers on cubes in a row, then the
same calls as trimesh's own manager (python-fcl underneath) on random
scenes, where both are installed."""

import numpy as np
import pytest

import nearmiss
from conftest import box


def at(x, y=0.0, z=0.0):
    transform = np.eye(4)
    transform[:3, 3] = [x, y, z]
    return transform


@pytest.fixture
def row():
    """Unit cubes centred at x = 0, 3 and 7."""
    manager = nearmiss.CollisionManager()
    for name, x in (("a", 0.0), ("b", 3.0), ("c", 7.0)):
        manager.add_object(name, box((0.5, 0.5, 0.5)), at(x))
    return manager


def test_a_cube_against_a_row_of_cubes(row):
    cube = box((0.5, 0.5, 0.5))
    # Centred at 1.4: 0.4 from a's face, 0.6 from b's.
    assert row.min_distance_single(cube, at(1.4)) == pytest.approx(0.4, rel=1e-15)
    distance, name, data = row.min_distance_single(cube, at(1.4), return_name=True, return_data=True)
    assert name == "a" and data.names == {"a", "__external"}
    assert data.point("a")[0] == pytest.approx(0.5) and data.point("__external")[0] == pytest.approx(0.9)
    assert row.in_collision_single(cube, at(1.4)) is False
    # Centred at 0.9: it crosses a's face.
    hit, names, contacts = row.in_collision_single(cube, at(0.9), return_names=True, return_data=True)
    assert hit is True and names == {"a"} and contacts[0].names == {"a", "__external"}
    assert 0.4 - 1e-12 <= contacts[0].point[0] <= 0.5 + 1e-12
    with pytest.raises(NotImplementedError, match="signed_distance"):
        contacts[0].depth


def test_the_row_among_itself(row):
    assert row.in_collision_internal() is False
    assert row.min_distance_internal(return_names=True) == (pytest.approx(2.0, rel=1e-15), ("a", "b"))
    assert row.min_distance_internal(name="c", return_names=True) == (pytest.approx(3.0, rel=1e-15), ("b", "c"))
    row.set_transform("c", at(0.9, 0.2))
    assert row.in_collision_internal(return_names=True) == (True, {("a", "c")})
    assert row.min_distance_internal() == 0.0
    row.remove_object("a")
    assert row.in_collision_internal() is False
    with pytest.raises(ValueError, match="a not in collision manager"):
        row.remove_object("a")
    assert nearmiss.CollisionManager().min_distance_single(box((0.5, 0.5, 0.5))) == float("inf")


def test_the_same_answers_as_trimesh_and_python_fcl():
    trimesh = pytest.importorskip("trimesh")
    pytest.importorskip("fcl")
    pytest.importorskip("scipy")  # trimesh's manager needs it
    for seed in range(4):
        rng = np.random.default_rng(seed)
        ours, peer = nearmiss.CollisionManager(), trimesh.collision.CollisionManager()
        for k in range(24):
            if k % 2:
                mesh = trimesh.creation.icosphere(subdivisions=2, radius=rng.uniform(0.2, 0.6))
            else:
                mesh = trimesh.creation.box(extents=rng.uniform(0.2, 1.0, 3))
            transform = trimesh.transformations.random_rotation_matrix(rng.random(3))
            transform[:3, 3] = rng.uniform(-3.0, 3.0, 3)
            ours.add_object(f"o{k}", mesh, transform)
            peer.add_object(f"o{k}", mesh, transform)
        assert ours.in_collision_internal(return_names=True) == peer.in_collision_internal(return_names=True)
        for _ in range(8):
            query = trimesh.creation.box(extents=rng.uniform(0.1, 0.6, 3))
            transform = trimesh.transformations.random_rotation_matrix(rng.random(3))
            transform[:3, 3] = rng.uniform(-3.0, 3.0, 3)
            assert ours.in_collision_single(query, transform, return_names=True) == peer.in_collision_single(
                query, transform, return_names=True
            )
            distance, name = ours.min_distance_single(query, transform, return_name=True)
            peer_distance, peer_name = peer.min_distance_single(query, transform, return_name=True)
            if peer_distance > 0.0:
                # FCL's own distance is good to about 1e-8 here; nearmiss's is exact.
                assert (distance, name) == (pytest.approx(peer_distance, rel=1e-6, abs=1e-9), peer_name)
            else:
                assert distance == 0.0


def test_the_first_contact_of_a_sliding_cube_is_the_earliest(row):
    # A unit cube from x = -3 at speed 1 along +x meets a (face at -0.5) at
    # t = 2; over 1.5 it meets nothing; a wall beside its path never.
    row.add_object("beside", box((0.5, 0.5, 0.5)), at(-1.0, 3.0))
    cube = box((0.5, 0.5, 0.5))
    found = row.time_of_impact_single(cube, at(-3.0), ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), 10.0)
    assert found.status == "contact" and found.name == "a"
    assert 2.0 - found.contact_distance <= found.time <= 2.0
    assert found.closest.point_a[0] == pytest.approx(-0.5)
    clear = row.time_of_impact_single(cube, at(-3.0), ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), 1.5)
    assert (clear.status, clear.time, clear.name) == ("clear", 1.5, None)


def test_the_clearance_of_a_pass_is_bracketed(row):
    # A unit cube along y = 1.25 passes every cube of the row 0.25 apart;
    # within 0.1 nothing is near (certified).
    cube = box((0.5, 0.5, 0.5))
    motion = ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    found = row.closest_approach_single(cube, at(-3.0, 1.25), motion, 12.0, tolerance=1e-9)
    assert found.status == "bracketed" and found.name in ("a", "b", "c")
    assert found.lower <= 0.25 <= found.upper and found.upper - found.lower <= 1e-9
    beyond = row.closest_approach_single(cube, at(-3.0, 1.25), motion, 12.0, within=0.1)
    assert (beyond.status, beyond.lower, beyond.name) == ("beyond", 0.1, None)


def test_a_link_swinging_about_its_joint_against_the_manager():
    # A rod 2 x 0.1 x 0.1 hinged at its end (the origin) swings a quarter
    # turn about z over 1. A slab whose face is the plane y = 1 stops it
    # where its far corner (2, 0.05) turned by theta reaches y = 1; a cube
    # behind the joint, at (-3, 0), is never reached.
    manager = nearmiss.CollisionManager()
    manager.add_object("slab", box((2.0, 0.5, 1.0)), at(1.5, 1.5))
    manager.add_object("behind", box((0.5, 0.5, 0.5)), at(-3.0))
    rod = box((1.0, 0.05, 0.05))
    turned = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    pose0 = ([1.0, 0.0, 0.0], np.eye(3))
    pose1 = ([0.0, 1.0, 0.0], turned)
    motion = nearmiss.motion_between(pose0, pose1, 1.0, about=[-1.0, 0.0, 0.0])
    found = manager.time_of_impact_single(rod, None, motion, 1.0)
    # 2 sin(theta) + 0.05 cos(theta) = 1, by bisection.
    low, high = 0.0, np.pi / 2
    for _ in range(200):
        mid = (low + high) / 2
        low, high = (mid, high) if 2 * np.sin(mid) + 0.05 * np.cos(mid) < 1 else (low, mid)
    exact = low / (np.pi / 2)
    assert found.status == "contact" and found.name == "slab"
    # The corner moves at 2 * (pi / 2) per unit time at least.
    assert exact - found.contact_distance / np.pi <= found.time <= exact


def test_transforms_are_kept_as_given():
    """A 4 x 4 transform's rotation matrix is applied as it is (not through
    a quaternion): the manager's nearest distance is ``mesh_distance``'s on
    the same transforms, to the bit (that one is within an ulp of the exact
    distance of the poses as given)."""
    rng = np.random.default_rng(46)
    manager, placed = nearmiss.CollisionManager(), []
    for k in range(10):
        q = rng.normal(size=4)
        w, x, y, z = q / np.linalg.norm(q)
        transform = np.eye(4)
        transform[:3, :3] = [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
        transform[:3, 3] = rng.uniform(-3.0, 3.0, 3)
        mesh = box((0.6, 0.4, 0.5)) if k % 2 else box((0.5, 0.3, 0.2))
        manager.add_object(f"o{k}", mesh, transform)
        placed.append((mesh, transform))
    query = box((0.2, 0.3, 0.4))
    for _ in range(6):
        transform = placed[0][1].copy()
        transform[:3, 3] = rng.uniform(-3.0, 3.0, 3)
        expected = min(nearmiss.mesh_distance(mesh, t, query, transform).distance for mesh, t in placed)
        assert manager.min_distance_single(query, transform) == expected
