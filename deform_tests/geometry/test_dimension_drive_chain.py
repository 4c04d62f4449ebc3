"""A chain of DimensionDrives (issue 17): each on the result of the one before, as a
DimensionDrive whose Base is another does. Thickness, then hole radius, then hole position
on the block-with-hole mesh: all three dimensions hold at the end, measured by planes and a
cylinder fitted here (SVD plane, algebraic circle of the hole's vertices, refined in 3D)."""
import numpy as np

from freecad_deform.geometry.mesh import dimension_drive as dd

from .block_mesh import block_with_hole
from ..oracles.fits import circle, plane
from ..oracles.mesh import flips


def test_thickness_then_radius_then_position_all_hold():
    V, T = block_with_hole()
    top, bottom = V[:, 2] == 30, V[:, 2] == 0
    hole = np.abs(np.hypot(V[:, 0] - 50, V[:, 1] - 30) - 8) < 1e-9
    frame = dict(origin=(0, 0, 40), axis_point=(1, 0, 40))
    steps = [("Distance", [(20, 5, 30), (20, 5, 0)], 40.0, {}),
             ("Radius", [(58, 30, 15)], 10.0, {}),
             ("Position", [(20, 5, 40), (60, 30, 15)], (42.0, 25.0), frame)]
    X = V
    for kind, picks, target, extra in steps:
        model = dd.DimensionModel(X, T, np.radians(40))
        drive = dd.drive(model, kind, picks, target, **extra)
        X = dd.deformed(model, drive)
    assert flips(V, X, T) == 0
    ct, nt, dt = plane(X[top])
    cb, nb, db = plane(X[bottom])
    assert max(dt, db) < 1e-9 and np.linalg.norm(np.cross(nt, nb)) < 1e-12
    assert abs(abs((ct - cb) @ nb) - 40.0) < 1e-6
    centre, r, dev = circle(X[hole])
    assert abs(r - 10.0) < 1e-6 and dev < 1e-6
    assert np.allclose(centre, (42.0, 25.0), atol=1e-6)
