"""Mesh volume in float64 against the closed form of a box."""
import numpy as np
import pytest

from freecad_deform.geometry.mesh.measure import mesh_volume

CUBE_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
CUBE_T = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                   [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


@pytest.mark.parametrize("scale, shift", [(1.0, 0.0), (300.0, 1e4), (1e-3, -5.0)])
def test_box_volume(scale, shift):
    v = CUBE_V * [scale, 2 * scale, 3 * scale] + shift
    assert mesh_volume(v, CUBE_T) == pytest.approx(6 * scale ** 3, rel=1e-9)
    assert mesh_volume(v, CUBE_T[:, ::-1]) == pytest.approx(-6 * scale ** 3, rel=1e-9)
