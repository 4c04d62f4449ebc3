"""A simplified mesh holding a doubly covered triangle (the same corners twice, opposite
orientations, as the one DimensionDrive's simplification made of trimesh's bunny.ply,
in a curved region): the handle gave its edges an edge prism along the mean of two
opposite normals, 0/0, so numpy warned of NaN while building it. Oracles: no warning,
every handle weight finite, the mesh reproduced by the weights (eq. 2.3)."""
import warnings

import numpy as np

from freecad_deform.geometry.mesh import dimension_drive as dd
from freecad_deform.geometry.mesh.dimension_handle import build_handle
from freecad_deform.geometry.mesh.simplify import Simplified

from .block_mesh import block_with_hole


def test_doubled_triangle_in_a_curved_region_gives_a_finite_handle():
    V, T = block_with_hole()
    m = dd.DimensionModel(V, T, np.radians(40))
    S, SL = np.asarray(m.simplified.triangles), np.asarray(m.simplified.labels)
    curved = np.flatnonzero(~m.planar[SL])[0]                # a triangle of the hole's wall
    # the copy first, so its edges pair it with the original (a non-manifold edge keeps
    # its first two triangles)
    doubled = Simplified(np.r_[S[curved:curved + 1, ::-1], S], np.r_[SL[curved], SL])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        H = build_handle(V, T, m.labels, m.planar, doubled)
    assert np.isfinite(H.points).all()
    assert np.isfinite(H.weights.data).all()
    assert np.abs(H.weights @ H.points - V).max() < 1e-9
