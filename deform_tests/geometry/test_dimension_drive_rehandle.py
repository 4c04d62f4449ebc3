"""Rehandle (issue 17, Date & Onosato's dynamic handle): a hole grown beyond the reach of
one handle goes on with handles rebuilt on the shape reached, the same vertices and
triangles. Oracles written in the tests: the algebraic circle of the hole's vertices, SVD
planes of the top and bottom, flipped triangles counted, the closed-manifold check."""
import numpy as np
import pytest

from freecad_deform.geometry.errors import DeformError
from freecad_deform.geometry.mesh import dimension_drive as dd

from .block_mesh import block_with_hole
from ..oracles.fits import circle, plane
from ..oracles.mesh import assert_closed_manifold, flips

PICK = [(58.0, 30.0, 15.0)]


def rehandled(model, target):
    return dd.rehandled(model, lambda m, r: dd.drive(m, "Radius", r, target), dd.deformed,
                        PICK)


def test_a_hole_beyond_reachable_is_met_with_new_handles():
    V, T = block_with_hole()
    model = dd.DimensionModel(V, T, np.radians(40))
    drive = dd.drive(model, "Radius", PICK, 20.0)
    assert dd.reach_values(drive)[1] < 20.0
    with pytest.raises(DeformError, match="beyond the deformable range") as e:
        dd.deformed(model, drive)
    assert e.value.prop == "Target"
    X, first, last, handles = rehandled(model, 20.0)
    assert handles > 1 and first.current == (8.0,)
    hole = np.abs(np.hypot(V[:, 0] - 50, V[:, 1] - 30) - 8) < 1e-9
    centre, r, dev = circle(X[hole])
    size = np.linalg.norm(np.ptp(V, axis=0))
    assert abs(r - 20.0) < 1e-6 * size and dev < 1e-6 * size
    assert np.allclose(centre, (50, 30), atol=1e-6 * size)
    assert abs(last.measure(X)[0] - 20.0) < 1e-6 * size
    for z in (0, 30):                                      # top and bottom stay planes
        c, n, d = plane(X[V[:, 2] == z])
        assert d < 1e-9 and abs(c[2] - z) < 1e-9
    outer = (V[:, 0] == 0) | (V[:, 0] == 100) | (V[:, 1] == 0) | (V[:, 1] == 60)
    assert np.abs(X[outer] - V[outer]).max() < 1e-9       # the outer walls stay
    assert flips(V, X, T) == 0
    assert X.shape == V.shape
    assert_closed_manifold(X, T)
    assert np.array_equal(model.vertices, V)              # the first model untouched


def test_a_hole_grown_into_the_wall_stops_short_of_it():
    V, T = block_with_hole()
    model = dd.DimensionModel(V, T, np.radians(40))
    with pytest.raises(DeformError, match=r"Target is beyond what rebuilt handles reach: it "
                                          r"went from 8 to [0-9.]+ with [0-9]+ handle") as e:
        rehandled(model, 35.0)
    assert e.value.prop == "Target"
    reached = float(str(e.value).split(" to ")[1].split(" ")[0])
    assert 17.8 < reached < 30.0                          # the wall is 30 from the axis
    assert np.array_equal(model.vertices, V)
