"""Case 3 folded separating surface: the graph s = h(u) of a polyline, validated."""
import numpy as np
import pytest
from hypothesis import given, strategies as st

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep.polyline import PolylineSurface

N = np.array([1.0, 0, 0])
V_SHAPE = [[90, -10, 0], [90, 30, 0], [140, 50, 0], [140, 70, 0]]  # in the xy plane


@given(st.floats(-10, 70), st.floats(-100, 100), st.floats(-50, 50))
def test_offset_is_distance_along_normal_to_the_polyline(y, dx, z):
    surface = PolylineSurface(V_SHAPE, N)
    # the polyline's x at lateral y, by hand: 90 up to y=30, then linear to 140 at y=50
    x_at = 90.0 if y <= 30 else (140.0 if y >= 50 else 90 + (y - 30) * 50 / 20)
    p = np.array([[x_at + dx, y, z]])
    assert surface.offset(p)[0] == pytest.approx(dx, abs=1e-9)


def test_order_reversed_and_segment_normals():
    surface = PolylineSurface(V_SHAPE[::-1], N)
    planes = surface.segment_planes()
    assert len(planes) == 3
    for origin, normal in planes:
        assert normal @ N > 0 and abs(normal[2]) < 1e-12
    np.testing.assert_allclose(planes[1][1], np.array([20, -50, 0]) / np.hypot(20, 50))


@pytest.mark.parametrize("points", [
    [[0, 0, 0]],                                   # too few
    [[0, 0, 0], [5, 0, 0]],                        # along the normal
    [[0, 0, 0], [0, 5, 0], [0, 10, 3]],            # not planar with the normal... (bent)
    [[0, 0, 0], [0, 5, 0], [3, 2, 0]],             # folds back
])
def test_bad_polylines_name_the_property(points):
    with pytest.raises(DeformError) as err:
        PolylineSurface(points, N)
    assert err.value.prop == "Polyline"
