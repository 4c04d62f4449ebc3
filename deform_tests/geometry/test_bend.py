"""Bend validity: the section must turn away from the near part, about an axis outside it."""
import numpy as np
import pytest
from hypothesis import given, strategies as st

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep.bend import check_bend, twist_tangents

SQUARE = np.array([[0, y, z] for y in (0.0, 10.0) for z in (0.0, 10.0)])  # section in x = 0
N = np.array([1.0, 0, 0])


@given(st.floats(10.001, 1e3), st.floats(1e-3, 6.28))
def test_axis_beyond_the_section_bends_one_way(height, angle):
    # axis along +y above the square: a negative angle swings the top... check by velocity sign
    axis = np.array([0, 0, height]), np.array([0, 1.0, 0])
    check_bend(SQUARE, N, *axis, -angle)
    with pytest.raises(DeformError) as err:
        check_bend(SQUARE, N, *axis, angle)
    assert err.value.prop == "Angle"


def test_axis_through_the_section():
    with pytest.raises(DeformError) as err:
        check_bend(SQUARE, N, np.array([0, 0, 5.0]), np.array([0, 1.0, 0]), 0.5)
    assert err.value.prop == "Axis" and "radius" in str(err.value)


@pytest.mark.parametrize("angle, prop", [(0.0, "Angle"), (2 * np.pi, "Angle")])
def test_angle_range(angle, prop):
    with pytest.raises(DeformError) as err:
        check_bend(SQUARE, N, np.array([0, 0, 20.0]), np.array([0, 1.0, 0]), angle)
    assert err.value.prop == prop


def test_axis_along_the_normal_is_not_a_bend():
    with pytest.raises(DeformError) as err:
        check_bend(SQUARE, N, np.array([0, 5.0, 5.0]), N, 0.5)
    assert err.value.prop == "Axis"


def test_twist_tangent_matches_finite_difference():
    gap, angle, c, w = 40.0, 1.2, np.array([0, 5.0, 5.0]), N
    p = np.array([[0, 10.0, 2.0]])

    def trajectory(s):
        a = angle * s / gap
        q = p[0] + s * N - c
        rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
        return c + rot @ q

    h = 1e-6
    fd = (trajectory(h) - trajectory(-h)) / (2 * h)
    np.testing.assert_allclose(twist_tangents(N, gap, angle, c, w)(p)[0], fd, atol=1e-8)
