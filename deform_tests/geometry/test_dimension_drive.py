"""DimensionDrive kernel on an FE-like block-with-hole mesh (numpy-built), each claim
against an oracle written here: exact plane heights, a circle fit of the test's own,
the untouched vertices compared bit for bit, flips counted by brute force."""
import numpy as np
import pytest

from freecad_deform.geometry.mesh import dimension_drive as dd
from freecad_deform.geometry.errors import DeformError
from freecad_deform.geometry.mesh.regions import region_adjacency

from .block_mesh import block_with_hole
from ..oracles.fits import circle
from ..oracles.mesh import flips

TOP, BOTTOM, WALL, HOLE = (50, 5, 30), (50, 5, 0), (50, 0, 15), (58, 30, 15)
FRAME = dict(origin=(0, 0, 30), axis_point=(1, 0, 30))


@pytest.fixture(scope="module")
def block():
    V, T = block_with_hole()
    return V, T, dd.DimensionModel(V, T, np.radians(40))


def hole_vertices(V):
    return np.abs(np.hypot(V[:, 0] - 50, V[:, 1] - 30) - 8) < 1e-9


def test_segmentation_finds_the_faces_of_the_block(block):
    V, T, m = block
    assert m.count == 7
    assert m.planar.sum() == 6
    hole = m.region_at(HOLE)
    assert not m.planar[hole] and abs(m.cylinder(hole).radius - 8) < 1e-9
    touching = {b if a == hole else a for a, b in region_adjacency(T, m.labels) if hole in (a, b)}
    assert touching == {m.region_at(TOP), m.region_at(BOTTOM)}


def test_handle_binds_every_vertex_inside_a_prism(block):
    V, T, m = block
    H = m.handle
    assert H.outside == 0
    assert np.allclose(np.asarray(H.weights.sum(axis=1)).ravel(), 1.0, atol=1e-12)
    assert np.abs(H.weights @ H.points - V).max() < 1e-9      # eq. 2.3 reproduces the mesh
    assert H.weights.min() >= -1e-15


def test_distance_moves_the_top_to_the_target_and_keeps_the_rest(block):
    V, T, m = block
    drive = dd.drive(m, "Distance", [TOP, BOTTOM], 40.0)
    assert drive.current == (30.0,)
    X = dd.deformed(m, drive)
    top, bottom = V[:, 2] == 30, V[:, 2] == 0
    assert np.abs(X[top, 2] - 40).max() < 1e-9
    assert np.abs(X[bottom] - V[bottom]).max() == 0.0
    h = hole_vertices(V)
    centre, r, dev = circle(X[h])
    assert abs(r - 8) < 1e-9 and dev < 1e-9 and np.allclose(centre, [50, 30], atol=1e-9)
    assert flips(V, X, T) == 0
    assert drive.measure(X)[0] == pytest.approx(40.0, abs=1e-9)


def test_radius_scales_the_hole_and_leaves_the_walls(block):
    V, T, m = block
    drive = dd.drive(m, "Radius", [HOLE], 10.0)
    assert drive.current[0] == pytest.approx(8.0, abs=1e-9)
    X = dd.deformed(m, drive)
    h = hole_vertices(V)
    for level in (0.0, 15.0, 30.0):
        ring = h & (np.abs(V[:, 2] - level) < 1e-9)
        centre, r, dev = circle(X[ring])
        assert abs(r - 10) < 1e-9 and dev < 1e-9 and np.allclose(centre, [50, 30], atol=1e-9)
    outer = (V[:, 0] == 0) | (V[:, 0] == 100) | (V[:, 1] == 0) | (V[:, 1] == 60)
    assert np.abs(X[outer] - V[outer]).max() == 0.0
    assert np.abs(X[:, 2] - V[:, 2]).max() < 1e-12
    assert flips(V, X, T) == 0


def test_position_moves_the_hole_in_the_plate_frame(block):
    V, T, m = block
    drive = dd.drive(m, "Position", [TOP, HOLE], (45.0, 30.0), **FRAME)
    assert np.allclose(drive.current, (50, 30), atol=1e-9)
    X = dd.deformed(m, drive)
    centre, r, dev = circle(X[hole_vertices(V)])
    assert np.allclose(centre, [45, 30], atol=1e-9) and abs(r - 8) < 1e-9 and dev < 1e-9
    assert np.abs(X[:, 2] - V[:, 2]).max() < 1e-12
    assert flips(V, X, T) == 0
    assert np.allclose(drive.measure(X), (45, 30), atol=1e-9)


@pytest.mark.parametrize("kind, picks, extra", [
    ("Distance", [TOP, BOTTOM], {}), ("Radius", [HOLE], {}), ("Position", [TOP, HOLE], FRAME)])
def test_reach_is_where_the_first_triangle_turns_over(block, kind, picks, extra):
    V, T, m = block
    target = (45.0, 30.0) if kind == "Position" else 20.0
    drive = dd.drive(m, kind, picks, target, **extra)
    for end in drive.reach:
        if np.isfinite(end):
            assert flips(V, V + 0.999 * end * drive.field, T) == 0
            assert flips(V, V + 1.001 * end * drive.field, T) > 0


def test_errors_name_the_property(block):
    V, T, m = block
    with pytest.raises(DeformError, match="not parallel") as e:
        dd.drive(m, "Distance", [TOP, WALL], 40.0)
    assert e.value.prop == "Regions"
    with pytest.raises(DeformError, match="plane") as e:
        dd.drive(m, "Radius", [TOP], 10.0)
    assert e.value.prop == "Regions"
    with pytest.raises(DeformError, match="same region") as e:
        dd.drive(m, "Distance", [TOP, (20, 20, 30)], 40.0)
    assert e.value.prop == "Regions"
    drive = dd.drive(m, "Radius", [HOLE], 40.0)
    with pytest.raises(DeformError, match=r"reachable [0-9.e+-]+ to [0-9.]+ \(now 8\)") as e:
        dd.deformed(m, drive)
    assert e.value.prop == "Target"


def test_fandisk_every_vertex_in_a_prism_and_a_groove_widened():
    """The paper's model: every vertex bound inside a prism (the handle reproduces the mesh),
    and Radius on the first cylindrical groove keeps its axis: every groove vertex ends at
    the target distance from the axis fitted here, before the drive, by the test itself."""
    import os
    from .test_mesh_simplify import TESTDATA, read_obj
    V, T = read_obj(os.path.join(TESTDATA, "fandisk.obj"))
    m = dd.DimensionModel(V, T, np.radians(40))
    assert m.handle.outside == 0
    assert np.abs(m.handle.weights @ m.handle.points - V).max() < 1e-9
    groove = next(r for r in range(m.count) if m.cylinder(r) is not None)
    ids = m.region_vertices(groove)
    # the test's own axis: normals are perpendicular to it, the circle centre in its plane
    n = m.normals[m.labels == groove]
    axis = np.linalg.svd(n)[2][-1]
    u = np.linalg.svd(np.eye(3) - np.outer(axis, axis))[0][:, :2]
    xy = V[ids] @ u
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    (cx, cy, k), *_ = np.linalg.lstsq(A, (xy * xy).sum(1), rcond=None)
    r0 = np.sqrt(k + cx * cx + cy * cy)
    centre = V[T[m.labels == groove][0]].mean(axis=0)
    drive = dd.drive(m, "Radius", [centre], r0 * 1.05)
    X = dd.deformed(m, drive)
    radial = np.hypot(*(X[ids] @ u - [cx, cy]).T)
    assert np.abs(radial - r0 * 1.05).max() < 1e-4 * r0      # the fandisk is float32 data
    assert flips(V, X, T) == 0
    assert drive.measure(X)[0] == pytest.approx(r0 * 1.05, rel=1e-5)
    # regions that do not touch the groove share no handle vertex with it: not one bit moves
    near = {groove} | {b if a == groove else a
                       for a, b in region_adjacency(T, m.labels) if groove in (a, b)}
    far = np.setdiff1d(np.arange(len(V)), np.unique(T[np.isin(m.labels, list(near))]))
    assert len(far) > 1000 and np.all(X[far] == V[far])


def test_position_without_a_frame_uses_the_global_axes(block):
    V, T, m = block
    drive = dd.drive(m, "Position", [TOP, HOLE], (45.0, 30.0), (0, 0, 0), (0, 0, 0))
    assert np.allclose(drive.current, (50, 30), atol=1e-9)
    with pytest.raises(DeformError, match="perpendicular") as e:
        dd.drive(m, "Position", [TOP, HOLE], (45.0, 30.0), (0, 0, 0), (0, 0, 5))
    assert e.value.prop == "AxisPoint"
