"""Key motions for the general Stretch/Bend: the piecewise screw and the factory."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep.motion import (KeyMotion, PiecewiseScrew, apply, key_motion,
                                            rotation, translation)


def rigid(rotvec, shift):
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    T[:3, 3] = shift
    return T


KEYS = [np.eye(4), rigid([0, 0, 0.4], [10, 2, 0]), rigid([0.2, -0.1, 0.9], [25, -4, 6]),
        rigid([0.1, 0.3, 1.5], [40, 0, 3])]


def test_piecewise_screw_passes_through_keys_and_is_rigid():
    m = PiecewiseScrew(KEYS)
    for k, t in zip(KEYS, np.linspace(0, 1, len(KEYS))):
        np.testing.assert_allclose(m.matrix(t), k, atol=1e-12)
    for t in np.linspace(0, 1, 37):
        R = m.matrix(t)[:3, :3]
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)


def test_translation_keys_give_straight_segments():
    keys = [np.eye(4), translation([10, 0, 0]), translation([10, 10, 0])]
    m = PiecewiseScrew(keys)
    p = np.array([[1.0, 2.0, 3.0]])
    np.testing.assert_allclose(apply(m.matrix(0.25), p), p + [5, 0, 0], atol=1e-12)
    np.testing.assert_allclose(apply(m.matrix(0.75), p), p + [10, 5, 0], atol=1e-12)


def test_piecewise_velocity_is_the_tangent():
    m = PiecewiseScrew(KEYS)
    p = np.array([[1.0, -2.0, 0.5], [3.0, 1.0, -1.0]])
    h = 1e-6
    for t in (0.1, 0.4, 0.9):  # inside pieces: central differences
        fd = (apply(m.matrix(t + h), p) - apply(m.matrix(t - h), p)) / (2 * h)
        np.testing.assert_allclose(m.velocity(p, t), fd, atol=1e-5 * (1 + np.abs(fd).max()))


def test_rotation_piece_is_a_circle():
    m = PiecewiseScrew([np.eye(4), rotation([0, 0, 0], [0, 0, 1], np.pi / 2)])
    p = np.array([[2.0, 0, 1.0]])
    for t in np.linspace(0, 1, 9):
        q = apply(m.matrix(t), p)[0]
        assert np.hypot(q[0], q[1]) == pytest.approx(2.0, abs=1e-12)
        assert np.arctan2(q[1], q[0]) == pytest.approx(t * np.pi / 2, abs=1e-12)


def test_factory_and_errors():
    assert isinstance(key_motion(KEYS, "Rational"), KeyMotion)
    assert isinstance(key_motion(KEYS, "Screw"), PiecewiseScrew)
    with pytest.raises(DeformError) as err:
        key_motion(KEYS, "Spline")
    assert err.value.prop == "Interpolation"
    with pytest.raises(DeformError) as err:
        PiecewiseScrew(KEYS[1:])
    assert err.value.prop == "Keys"
