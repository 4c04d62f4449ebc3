"""Space maps between two planes: closed-form oracles written here (rotations, scalings)."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from freecad_deform.geometry.sweep import space_map as sm
from freecad_deform.geometry.errors import DeformError

ORIGIN = np.array([1.0, -2.0, 3.0])
NORMAL = np.array([0.0, 0.0, 1.0])
GAP = 10.0


def rot_z(phi, p, c):
    """p turned by phi about the z line through c (written out, not from the package)."""
    d = p - c
    return c + np.stack([np.cos(phi) * d[:, 0] - np.sin(phi) * d[:, 1],
                         np.sin(phi) * d[:, 0] + np.cos(phi) * d[:, 1], d[:, 2]], axis=1)


coords = st.floats(-20, 20, allow_nan=False)
points = st.lists(st.tuples(coords, coords, coords), min_size=1, max_size=20).map(np.array)


@settings(max_examples=40)
@given(points, st.floats(-3, 3), st.sampled_from(sm.PROFILES))
def test_twist_turns_each_section_by_its_angle(pts, angle, profile):
    c = np.array([0.5, 0.25, 0.0])
    m = sm.twist_map(ORIGIN, NORMAL, GAP, angle, c, NORMAL, profile)
    s = np.clip((pts[:, 2] - ORIGIN[2]) / GAP, 0, 1)
    t = s if profile == "Linear" else 3 * s ** 2 - 2 * s ** 3
    expect = np.vstack([rot_z(a, p[None], c) for a, p in zip(angle * t, pts)])
    assert np.allclose(m(pts), expect, atol=1e-12 * 20)
    assert np.allclose(m.jacobian_det(pts + [0, 0, 1e-3]), 1.0, atol=1e-5)  # keeps volume


@settings(max_examples=40)
@given(points, st.floats(0.2, 3), st.floats(0.2, 3), st.sampled_from(sm.PROFILES))
def test_taper_scales_across_the_axis(pts, sx, sy, profile):
    c = np.array([2.0, 1.0, 0.0])
    m = sm.taper_map(ORIGIN, NORMAL, GAP, (sx, sy), c, np.eye(3), profile)
    s = np.clip((pts[:, 2] - ORIGIN[2]) / GAP, 0, 1)
    t = s if profile == "Linear" else 3 * s ** 2 - 2 * s ** 3
    expect = pts.copy()
    expect[:, 0] = c[0] + (1 + (sx - 1) * t) * (pts[:, 0] - c[0])
    expect[:, 1] = c[1] + (1 + (sy - 1) * t) * (pts[:, 1] - c[1])
    assert np.allclose(m(pts), expect, atol=1e-11)


def test_bend_linear_wraps_the_region_around_the_axis():
    axis_point, w = ORIGIN + [30.0, 0, 0], np.array([0.0, 1.0, 0.0])
    m = sm.bend_map(ORIGIN, NORMAL, GAP, 0.5, axis_point, w)
    p = np.array([ORIGIN + [0, 0, 4.0]])                  # s = 0.4 on the section's centre
    r = np.linalg.norm((p - axis_point)[0] - [0, 0, 4.0])  # its distance at Plane: 30
    q = m(p)[0]
    assert np.isclose(np.linalg.norm((q - axis_point)[[0, 2]]), r)
    assert np.isclose(np.arctan2(-(q - axis_point)[2], -(q - axis_point)[0]), -0.2)


def test_stretch_is_affine_and_the_far_part_translates():
    m = sm.stretch_map(ORIGIN, NORMAL, GAP, 5.0)
    pts = np.array([[0, 0, ORIGIN[2] + 2.0], [3, 1, ORIGIN[2] + 20.0], [3, 1, ORIGIN[2] - 1]])
    assert np.allclose(m(pts)[:, 2] - pts[:, 2], [1.0, 5.0, 0.0])
    with pytest.raises(DeformError) as err:
        sm.stretch_map(ORIGIN, NORMAL, GAP, -10.0)
    assert err.value.prop == "Distance"


@pytest.mark.parametrize("side", [0, 1])
def test_smooth_profile_leaves_no_jump_at_the_joints(side):
    c = np.zeros(3)
    pts = np.array([[5.0, 2.0, ORIGIN[2] + side * GAP], [-3.0, 4.0, ORIGIN[2] + side * GAP]])
    smooth = sm.twist_map(ORIGIN, NORMAL, GAP, 1.0, c, NORMAL, "Smooth")
    linear = sm.twist_map(ORIGIN, NORMAL, GAP, 1.0, c, NORMAL, "Linear")
    assert np.abs(smooth.normal_derivative(pts, side)).max() < 1e-6
    # the linear twist's jump is the tangential speed angle/gap * (w x (p - c))
    expect = np.cross(NORMAL, pts - c) / GAP
    expect[:, 2] = 0
    got = linear.normal_derivative(pts, side)  # at Plane2 pulled back by the far turn
    assert np.allclose(np.linalg.norm(got, axis=1), np.linalg.norm(expect, axis=1), rtol=1e-6)


def test_fold_and_bad_scale_name_their_property():
    with pytest.raises(DeformError) as err:
        sm.taper_map(ORIGIN, NORMAL, GAP, 0.0, np.zeros(3))
    assert err.value.prop == "Scale"
    m = sm.bend_map(ORIGIN, NORMAL, GAP, 1.0, ORIGIN + [2.0, 0, 0], [0, 1.0, 0], "Smooth")
    with pytest.raises(DeformError) as err:
        m.check_fold(np.array([[ORIGIN[0] + 1.0, 0, ORIGIN[2] + 5.0]]), "Profile")
    assert err.value.prop == "Profile"
