"""Plane helpers: frames are orthonormal and right-handed, gaps need parallel ordered planes."""
import numpy as np
import pytest
from hypothesis import given, strategies as st

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep.planes import frame, parallel_gap, signed_distance


@given(st.tuples(*[st.floats(-1e3, 1e3)] * 3).filter(lambda v: np.linalg.norm(v) > 1e-6))
def test_frame_is_right_handed_orthonormal(direction):
    f = frame(direction)
    np.testing.assert_allclose(f @ f.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(f) == pytest.approx(1.0)
    np.testing.assert_allclose(f[2], np.asarray(direction) / np.linalg.norm(direction), atol=1e-12)


def test_signed_distance_and_gap():
    assert signed_distance([[0, 0, 5.0]], [0, 0, 2.0], [0, 0, 2.0])[0] == pytest.approx(3.0)
    assert parallel_gap([0, 0, 0], [0, 0, 1], [7, 3, 4.0], [0, 0, 5]) == pytest.approx(4.0)
    with pytest.raises(DeformError) as err:
        parallel_gap([0, 0, 0], [0, 0, 1], [0, 0, 4.0], [0, 1, 1])
    assert err.value.prop == "Plane2"
