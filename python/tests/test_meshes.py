"""Meshes, mesh distance, time of impact and closest approach against
analytic answers: the contact is never late, the bracket holds the
closest approach."""

import math

import numpy as np
import pytest

import nearmiss
from conftest import ROOT, box


def test_a_mesh_keeps_its_arrays(cube):
    assert len(cube) == 12
    assert cube.vertices.shape == (8, 3) and cube.faces.shape == (12, 3)
    assert cube.faces.dtype == np.int64
    assert cube.radius == pytest.approx(math.sqrt(3) / 2, rel=1e-15)
    assert "12 triangles" in repr(cube)


def test_an_obj_file(cube):
    handle = nearmiss.Mesh.from_obj(ROOT / "scenes" / "meshes" / "t_handle.obj")
    assert len(handle) == 24
    # The bar's end face is at x = 1: a cube 2 to its right is 0.5 away.
    d = nearmiss.mesh_distance(handle, None, cube, ([2.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]))
    assert d.distance == pytest.approx(0.5, rel=1e-15)


def test_mesh_distance_with_a_rotation_matrix_and_a_quaternion(cube):
    # Turned 45 degrees about z, the cube's edge reaches sqrt(2)/2 along x.
    c, s = math.cos(math.pi / 4), math.sin(math.pi / 4)
    matrix = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    quaternion = [math.cos(math.pi / 8), 0.0, 0.0, math.sin(math.pi / 8)]
    for rotation in (matrix, quaternion):
        d = nearmiss.mesh_distance(cube, ([0.0, 0.0, 0.0], rotation), cube, ([2.0, 0.0, 0.0], [1, 0, 0, 0]))
        assert d.distance == pytest.approx(1.5 - math.sqrt(2) / 2, rel=1e-14)


def test_head_on_cubes_touch_at_the_analytic_time_never_late(cube):
    # Faces 2 apart, closing at 1: contact at t = 2.
    toi = nearmiss.mesh_time_of_impact(
        cube, None, None, cube, ([3.0, 0.0, 0.0], [1, 0, 0, 0]), ([-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), 3.0
    )
    assert toi.status == "converged"
    assert toi.time <= 2.0
    assert 2.0 - toi.time <= toi.contact_distance  # early by at most the contact distance over the speed 1
    assert toi.closest.distance <= toi.contact_distance


def test_a_spinning_bar_reaches_a_wall_at_the_analytic_angle():
    # A bar (2 x 0.2 x 0.2) spins about z at 10 rad/s; the wall's face is the
    # plane x = 0.9. Its corner (radius sqrt(1.01), angle atan(0.1) off the
    # bar's axis) first reaches x = 0.9 when cos(theta + atan 0.1) =
    # 0.9 / sqrt(1.01), turning the bar's +x end towards the wall from -90
    # degrees: theta measured from the start.
    bar = box((1.0, 0.1, 0.1))
    wall = box((0.5, 3.0, 3.0))
    start = [math.cos(-math.pi / 4), 0.0, 0.0, math.sin(-math.pi / 4)]  # -90 degrees about z
    omega = 10.0
    toi = nearmiss.mesh_time_of_impact(
        bar, ([0.0, 0.0, 0.0], start), ([0, 0, 0], [0.0, 0.0, omega]), wall, ([1.4, 0.0, 0.0], [1, 0, 0, 0]), None, 0.5
    )
    r, lead = math.sqrt(1.01), math.atan(0.1)
    # The corner at angle phi = -90 deg + theta + atan(0.1) reaches x = 0.9
    # first where cos(phi) = 0.9 / r, phi < 0.
    phi = -math.acos(0.9 / r)
    analytic = (phi + math.pi / 2 - lead) / omega
    assert toi.status == "converged"
    assert toi.time <= analytic
    # Early by at most the contact distance over the corner's speed there.
    assert analytic - toi.time <= toi.contact_distance / (omega * r * abs(math.sin(phi))) * 1.01


@pytest.mark.parametrize("scale", [1e-5, 1.0, 1e6])
def test_the_closest_approach_of_a_pass_is_bracketed(scale):
    # A cube passes another 0.25 from its face (scaled).
    big = box((0.5 * scale, 0.5 * scale, 0.5 * scale))
    approach = nearmiss.closest_approach(
        big,
        None,
        None,
        big,
        ([-3.0 * scale, 1.25 * scale, 0.0], [1, 0, 0, 0]),
        ([3.0 * scale, 0.0, 0.0], [0, 0, 0]),
        2.0,
    )
    analytic = 0.25 * scale
    assert approach.status == "bracketed"
    assert approach.lower <= analytic <= approach.upper * (1 + 1e-12)
    assert approach.upper - approach.lower <= 1e-6 * big.radius
    assert approach.closest.distance == approach.upper


def test_a_pair_that_stays_beyond_within_costs_one_run(cube):
    far = nearmiss.closest_approach(
        cube, None, None, cube, ([5.0, 0.0, 0.0], [1, 0, 0, 0]), None, 1.0, within=1.0
    )
    assert far.status == "beyond" and far.runs == 1
    assert far.lower >= 1.0 and far.closest is None


def test_poses_as_users_have_them(cube):
    """One pose written five ways gives one distance: (position,
    quaternion), (position, matrix), a 4 x 4 transform, an object with
    ``as_matrix()`` (scipy's ``Rotation``), and an ``[x, y, z, w]``
    quaternion through ``quaternion_from_xyzw``."""
    half = math.sqrt(0.5)
    # A quarter turn about z, and a shift of 3 along x.
    wxyz = np.array([half, 0.0, 0.0, half])
    matrix = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    transform = np.eye(4)
    transform[:3, :3], transform[:3, 3] = matrix, [3.0, 0.0, 0.0]

    class Turn:
        def as_matrix(self):
            return matrix

    poses = [
        ([3.0, 0.0, 0.0], wxyz),
        ([3.0, 0.0, 0.0], matrix),
        transform,
        transform.tolist(),
        ([3.0, 0.0, 0.0], Turn()),
        ([3.0, 0.0, 0.0], nearmiss.quaternion_from_xyzw([0.0, 0.0, half, half])),
    ]
    # Unit cubes 3 apart along x, one turned about z: faces 2 apart.
    for pose in poses:
        assert nearmiss.mesh_distance(cube, None, cube, pose).distance == pytest.approx(2.0, rel=1e-15)
    bad = np.eye(4)
    bad[3, 0] = 1.0
    with pytest.raises(ValueError, match=r"pose_b: a 4 x 4 transform's last row must be \[0, 0, 0, 1\]"):
        nearmiss.mesh_distance(cube, None, cube, bad)
    with pytest.raises(ValueError, match=r"pose_b: expected \(position, rotation\), a 4 x 4 transform"):
        nearmiss.mesh_distance(cube, None, cube, np.eye(3))
    rotation = pytest.importorskip("scipy.spatial.transform").Rotation
    turn = rotation.from_quat([0.0, 0.0, half, half])  # scipy's [x, y, z, w]
    assert nearmiss.mesh_distance(cube, None, cube, ([3.0, 0.0, 0.0], turn)).distance == pytest.approx(2.0, rel=1e-15)


def test_meshes_as_other_libraries_hold_them(cube):
    """Any object with ``vertices`` and ``faces`` (a ``trimesh.Trimesh``)
    is a mesh wherever one is taken, converted once while unchanged."""

    class Held:
        def __init__(self, vertices, faces):
            self.vertices, self.faces = vertices, faces

    held = Held(cube.vertices.copy(), cube.faces.copy())
    d = nearmiss.mesh_distance(held, None, cube, ([2.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]))
    assert d.distance == pytest.approx(1.0, rel=1e-15)
    # A cube 3 along x closing at 1: faces 2 apart, contact at t = 2 (never late).
    toi = nearmiss.mesh_time_of_impact(
        held, None, None, cube, ([3.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]), ([-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), 3.0
    )
    assert toi.time is not None and 2.0 - 1e-6 <= toi.time <= 2.0
    # Changed in place: converted again, not the old mesh.
    held.vertices[:, 0] -= 1.0
    d = nearmiss.mesh_distance(held, None, cube, ([2.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]))
    assert d.distance == pytest.approx(2.0, rel=1e-15)
    with pytest.raises(TypeError, match="mesh_a: expected a nearmiss.Mesh or an object with vertices and faces"):
        nearmiss.mesh_distance(object(), None, cube, None)
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    assert nearmiss.mesh_distance(box, None, cube, ([3.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])).distance == pytest.approx(2.0, rel=1e-15)


def test_a_binary_stl_file_is_welded_into_the_closed_cube(cube, tmp_path):
    """STL stores each triangle's corners apart: read back, they are welded
    to the cube's 8 corners, and it answers as the cube does."""
    corners = cube.vertices[cube.faces].astype("<f4")  # (12, 3, 3)
    records = np.zeros(12, dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    records["corners"] = corners
    path = tmp_path / "cube.stl"
    path.write_bytes(b"solid cube".ljust(80) + np.uint32(12).tobytes() + records.tobytes())
    read = nearmiss.Mesh.from_file(path)
    assert read.vertices.shape == (8, 3) and len(read) == 12
    assert sorted(map(tuple, read.vertices)) == sorted(map(tuple, cube.vertices))
    d = nearmiss.mesh_distance(read, None, cube, ([2.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]))
    assert d.distance == pytest.approx(1.0, rel=1e-15)
    path.write_bytes(path.read_bytes()[:-10])
    with pytest.raises(ValueError, match=r"cube\.stl: binary STL, the header: it states 12 triangles"):
        nearmiss.Mesh.from_file(path)


@pytest.mark.parametrize(
    "file_type, options",
    [("stl", {}), ("stl_ascii", {}), ("ply", {"encoding": "binary"}), ("ply", {"encoding": "ascii"}),
     ("glb", {}), ("obj", {})],
)
def test_files_trimesh_writes_read_as_trimesh_reads_them(tmp_path, file_type, options):
    """trimesh, the peer: the files it writes read to the vertices and
    faces its own loader (which merges vertices) finds in them."""
    trimesh = pytest.importorskip("trimesh")
    shape = trimesh.creation.annulus(r_min=0.5, r_max=1.0, height=0.3, sections=24)
    shape.apply_translation([0.25, -0.5, 2.0])
    path = tmp_path / f"annulus.{file_type.split('_')[0]}"
    exported = shape.export(file_type=file_type, **options)
    path.write_bytes(exported.encode() if isinstance(exported, str) else exported)
    peer = trimesh.load(str(path), force="mesh", process=True)
    read = nearmiss.Mesh.from_file(path)
    assert len(read) == len(peer.faces)
    assert read.vertices.shape == peer.vertices.shape
    np.testing.assert_allclose(
        np.sort(read.vertices, axis=0), np.sort(peer.vertices, axis=0), rtol=0, atol=1e-6
    )
    # The same surface: each face's corners, as sets, match the peer's.
    ours = sorted(tuple(sorted(map(tuple, np.round(read.vertices[f], 5)))) for f in read.faces)
    theirs = sorted(tuple(sorted(map(tuple, np.round(peer.vertices[f], 5)))) for f in peer.faces)
    assert ours == theirs


def test_a_rod_hinged_at_its_end_swings_about_its_joint(tmp_path):
    """motion_between about a joint: a rod (2 x 0.1 x 0.1 about its centre)
    hinged at its end swings a quarter turn about z, the joint fixed at the
    origin. Its far top edge (radius r = sqrt(4.0025), phi = atan(0.025)
    ahead of its axis) reaches the bottom face y = 0.5 of the block
    [1.5, 2] x [0.5, 1.5] when r sin(theta + phi) = 0.5: never late."""
    rod = box((1.0, 0.05, 0.05))
    joint = [-1.0, 0.0, 0.0]
    turned = [math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)]  # a quarter about z
    start = np.eye(4)
    start[0, 3] = 1.0  # the joint at the origin
    motion = nearmiss.motion_between(start, ([0.0, 1.0, 0.0], turned), 1.0, about=joint)
    np.testing.assert_allclose(motion.velocity, [0.0, 0.0, 0.0], atol=1e-15)  # the joint stays put
    np.testing.assert_allclose(motion.angular_velocity, [0.0, 0.0, math.pi / 2], rtol=1e-15)
    block = box((0.25, 0.5, 1.0))
    at_block = ([1.75, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0])
    r = math.sqrt(4.0025)
    expected = (math.asin(0.5 / r) - math.atan(0.025)) / (math.pi / 2)
    toi = nearmiss.mesh_time_of_impact(rod, None, motion, block, at_block, None, 1.0, distance_tolerance=1e-9)
    assert toi.status == "converged"
    closing = r * math.pi / 2 * math.cos(math.asin(0.5 / r))
    assert 0.0 <= expected - toi.time <= 1.01 * toi.contact_distance / closing
    # The witness triangle indexes the rod as the caller holds it.
    assert 0 <= toi.closest.triangle_a < len(rod)
    # Beyond the reach: [-0.5, 0.5] x [2.01, 3]; the far corners peak at
    # sqrt(4.0025) along y (at theta = atan 40), 2.01 - sqrt(4.0025) short.
    far = ([0.0, 2.505, 0.0], [1.0, 0.0, 0.0, 0.0])
    approach = nearmiss.closest_approach(rod, None, motion, box((0.5, 0.495, 1.0)), far, None, 1.0)
    gap = 2.01 - r
    assert approach.status == "bracketed"
    assert approach.lower <= gap <= approach.upper * (1 + 1e-12)
    with pytest.raises(TypeError, match="pass None as the pose"):
        nearmiss.mesh_time_of_impact(rod, start, motion, block, at_block, None, 1.0)
