"""Rigid motions: screw (Chasles) and rational key motions, profile placements, checked against
scipy's rotations, closed-form trajectories and finite differences."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep.motion import (KeyMotion, ScrewMotion, apply, profile_frames,
                                            rotation, translation)

vec = st.tuples(*[st.floats(-5, 5)] * 3).map(np.array)
direction = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 0.2)
seed = st.integers(0, 2 ** 32 - 1)
T_GRID = np.linspace(0.0, 1.0, 23)


def rigid(R, d):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, d
    return T


def random_rigid(seed, scale=3.0):
    rng = np.random.default_rng(seed)
    return rigid(Rotation.random(random_state=seed).as_matrix(), scale * rng.normal(size=3))


def assert_rigid_stack(M, tol=1e-12):
    M = np.asarray(M).reshape(-1, 4, 4)
    R = M[:, :3, :3]
    np.testing.assert_allclose(R @ np.swapaxes(R, 1, 2), np.broadcast_to(np.eye(3), R.shape),
                               atol=tol)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=tol)
    np.testing.assert_array_equal(M[:, 3], np.broadcast_to([0, 0, 0, 1.0], (len(M), 4)))


def distance_to_line(P, c, k):
    k = k / np.linalg.norm(k)
    rel = P - c
    return np.linalg.norm(rel - (rel @ k)[..., None] * k, axis=-1)


def central_difference(motion, points, t, h=1e-6):
    return (apply(motion.matrix(t + h), points) - apply(motion.matrix(t - h), points)) / (2 * h)


# ---------------------------------------------------------------- transforms

@settings(max_examples=50, deadline=None)
@given(c=vec, k=direction, angle=st.floats(-7, 7), pts=st.lists(vec, min_size=1, max_size=5))
def test_rotation_matches_scipy(c, k, angle, pts):
    P = np.array(pts)
    u = k / np.linalg.norm(k)
    expected = Rotation.from_rotvec(angle * u).apply(P - c) + c
    np.testing.assert_allclose(apply(rotation(c, k, angle), P), expected, atol=1e-12)


def test_rotation_right_hand_rule_and_stacks():
    M = rotation([1.0, 0, 0], [0, 0, 2.0], np.pi / 2)
    np.testing.assert_allclose(apply(M, [[2.0, 0, 5]]), [[1.0, 1.0, 5]], atol=1e-15)
    stack = rotation([1.0, 0, 0], [0, 0, 1.0], np.array([0.0, np.pi / 2, np.pi]))
    assert stack.shape == (3, 4, 4)
    P = np.array([[2.0, 0, 0], [1.0, 0, 3], [0.0, 0, 0]])
    out = apply(stack, P)
    assert out.shape == (3, 3, 3)
    np.testing.assert_allclose(out[1], apply(M, P), atol=1e-15)
    np.testing.assert_allclose(out[2], [[0, 0, 0], [1, 0, 3], [2, 0, 0]], atol=1e-15)
    np.testing.assert_array_equal(apply(translation([1.0, 2, 3]), P), P + [1, 2, 3])
    np.testing.assert_allclose(apply(translation([[1.0, 0, 0], [0, 2, 0]]), P)[1], P + [0, 2, 0])
    with pytest.raises(DeformError) as err:
        rotation([0, 0, 0], [0, 0, 0], 1.0)
    assert err.value.prop == "Axis"


# ---------------------------------------------------------------- screw motion

@settings(max_examples=80, deadline=None)
@given(seed=seed, scale=st.floats(0.0, 10.0))
def test_screw_ends_are_identity_and_T_and_every_step_rigid(seed, scale):
    T = random_rigid(seed, scale)
    m = ScrewMotion(T)
    np.testing.assert_allclose(m.matrix(1.0), T, atol=1e-12)
    np.testing.assert_allclose(m.matrix(0.0), np.eye(4), atol=1e-15)
    assert_rigid_stack(m.matrices(T_GRID))
    # Chasles: T turns about the axis and slides along it
    k, c = m.axis_direction, m.axis_point
    np.testing.assert_allclose(T[:3, :3] @ k, k, atol=1e-12)
    np.testing.assert_allclose(apply(T, c[None])[0], c + m.slide * k, atol=1e-11)
    assert 0 <= m.angle <= np.pi + 1e-15
    # constant speed: M(t) M(u) = M(t + u) (one-parameter group)
    np.testing.assert_allclose(m.matrix(0.3) @ m.matrix(0.45), m.matrix(0.75), atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(c=vec, k=direction, angle=st.one_of(st.floats(0.05, np.pi), st.just(np.pi)),
       sign=st.sampled_from([-1.0, 1.0]), pts=st.lists(vec, min_size=1, max_size=6))
def test_pure_rotation_revolves_on_circles(c, k, angle, sign, pts):
    P = np.array(pts)
    m = ScrewMotion(rotation(c, k, sign * angle))
    assert m.angle == pytest.approx(angle, abs=1e-12)
    assert m.slide == pytest.approx(0.0, abs=1e-12)
    traj = apply(m.matrices(T_GRID), P)                            # (K, N, 3)
    np.testing.assert_allclose(distance_to_line(traj, c, k), np.broadcast_to(
        distance_to_line(P, c, k), traj.shape[:2]), atol=1e-12)
    u = k / np.linalg.norm(k)
    np.testing.assert_allclose((traj - c) @ u, np.broadcast_to((P - c) @ u, traj.shape[:2]),
                               atol=1e-12)
    # and at constant angular speed: M(t) is the rotation by t*angle (same turning sense,
    # which a half turn leaves open)
    senses = [sign, -sign] if angle == np.pi else [sign]
    for t in (0.25, 0.5, 0.9):
        assert min(np.abs(m.matrix(t) - rotation(c, k, t * e * angle)).max()
                   for e in senses) < 1e-12


@given(d=vec, pts=st.lists(vec, min_size=1, max_size=6))
def test_pure_translation_extrudes_along_lines(d, pts):
    P = np.array(pts)
    m = ScrewMotion(translation(d))
    assert m.angle == 0.0
    traj = apply(m.matrices(T_GRID), P)
    np.testing.assert_allclose(traj, P + T_GRID[:, None, None] * d, atol=1e-12)
    np.testing.assert_allclose(m.velocity(P, 0.4), np.broadcast_to(d, P.shape), atol=1e-15)


@pytest.mark.parametrize("angle", [np.pi, np.pi - 1e-9, 1e-6, 1e-10, 1e-14, 0.0])
def test_screw_angles_near_zero_and_pi(angle):
    T = rotation([1.0, -2, 0.5], [0.3, 1, -0.2], angle) @ translation([0.3, 1, -0.2])
    m = ScrewMotion(T)
    np.testing.assert_allclose(m.matrix(1.0), T, atol=1e-12)
    assert_rigid_stack(m.matrices(T_GRID))
    P = np.array([[2.0, 1, 0], [-1, 0, 3]])
    np.testing.assert_allclose(m.velocity(P, 0.7), central_difference(m, P, 0.7), atol=1e-7)


@settings(max_examples=50, deadline=None)
@given(seed=seed, t=st.floats(0.0, 1.0), pts=st.lists(vec, min_size=1, max_size=5))
def test_screw_velocity_is_the_trajectory_tangent(seed, t, pts):
    P = np.array(pts)
    m = ScrewMotion(random_rigid(seed))
    np.testing.assert_allclose(m.velocity(P, t), central_difference(m, P, t), atol=1e-6)


@pytest.mark.parametrize("T", [np.diag([1.0, 1, -1, 1]), np.diag([2.0, 2, 2, 1]),
                               np.eye(3), np.full((4, 4), np.nan)])
def test_screw_rejects_non_rigid(T):
    with pytest.raises(DeformError) as err:
        ScrewMotion(T)
    assert err.value.prop == "Placement"


# ---------------------------------------------------------------- rational key motion

def random_keys(seed, count, turn=1.2, step=2.0):
    """Identity then keys a bounded turn and step from the previous one."""
    rng = np.random.default_rng(seed)
    keys = [np.eye(4)]
    for _ in range(count - 1):
        rv = rng.normal(size=3)
        rv *= rng.uniform(0.1, turn) / np.linalg.norm(rv)
        keys.append(rigid(Rotation.from_rotvec(rv).as_matrix(), step * rng.normal(size=3))
                    @ keys[-1])
    return keys


def random_params(seed, count):
    if count == 2:
        return [0.0, 1.0]
    inner = np.sort(np.random.default_rng(seed + 1).uniform(0.1, 0.9, count - 2))
    params = np.r_[0.0, inner, 1.0]
    return params if np.diff(params).min() > 0.03 else None


@settings(max_examples=60, deadline=None)
@given(seed=seed, count=st.integers(2, 7), given_params=st.booleans())
def test_key_motion_passes_keys_and_is_rigid(seed, count, given_params):
    keys = random_keys(seed, count)
    params = random_params(seed, count) if given_params else None
    m = KeyMotion(keys, params)
    at = m.params
    assert m.degree == min(3, count - 1)
    for key, t in zip(keys, at):
        np.testing.assert_allclose(m.matrix(t), key, atol=1e-12)
    np.testing.assert_allclose(m.matrices(at), np.array(keys), atol=1e-12)
    assert_rigid_stack(m.matrices(np.linspace(0, 1, 101)))


def third_difference_growth(path, h=1e-3):
    """max |third difference| / h^3 of a curve sampled every h/2, over the same at h.

    About 1 for a C2 curve (it tends to max |x'''|), about 2 when x'' jumps anywhere
    (a jump J gives J / h)."""
    def d3(step):
        x = path(np.arange(0.0, 1.0 + step / 2, step))
        return np.abs(np.diff(x, 3, axis=0)).max() / step ** 3
    return d3(h / 2) / d3(h)


def test_growth_detector_sees_a_c1_kink():
    kink = lambda t: np.c_[t, np.abs(t - 0.4003) * (t - 0.4003), t ** 3]   # x'' jumps by 4
    assert third_difference_growth(kink) == pytest.approx(2.0, rel=0.05)
    smooth = lambda t: np.c_[np.sin(3 * t), t ** 4, np.abs(t - 0.4003) ** 3]  # C2, x''' jumps
    assert third_difference_growth(smooth) == pytest.approx(1.0, rel=0.05)


@settings(max_examples=20, deadline=None)
@given(seed=seed, count=st.integers(5, 8))
def test_key_motion_is_c2(seed, count):
    m = KeyMotion(random_keys(seed, count, turn=0.8, step=1.0))
    P = np.array([[1.0, 0.5, -0.3], [-2.0, 1.0, 0.7]])
    growth = third_difference_growth(lambda t: apply(m.matrices(t), P))
    assert growth < 1.2


@settings(max_examples=50, deadline=None)
@given(seed=seed, t=st.floats(0.0, 1.0), count=st.integers(2, 6))
def test_key_motion_velocity_is_the_trajectory_tangent(seed, t, count):
    m = KeyMotion(random_keys(seed, count))
    P = np.array([[1.0, 2.0, -1.0], [0.0, -3.0, 0.5]])
    h = 1e-6

    def x(at):
        return apply(m.matrix(at), P)

    if h <= t <= 1.0 - h:  # central difference, or second-order one-sided at the ends
        fd = (x(t + h) - x(t - h)) / (2 * h)
    else:
        sign = 1.0 if t < h else -1.0
        fd = sign * (-3 * x(t) + 4 * x(t + sign * h) - x(t + 2 * sign * h)) / (2 * h)
    np.testing.assert_allclose(m.velocity(P, t), fd, atol=1e-5 * (1 + np.abs(fd).max()))


@settings(max_examples=50, deadline=None)
@given(seed=seed)
def test_two_key_motion_screws_about_the_axis_of_T(seed):
    """Linear blending of two dual quaternions: every M(t) is a screw about T's axis, with
    the angle rising from 0 to T's (not uniformly), and the motion rigid to rounding."""
    T = random_rigid(seed)
    ref = ScrewMotion(T)
    m = KeyMotion([np.eye(4), T])
    assert m.degree == 1
    ts = np.linspace(0.05, 1.0, 20)
    M = m.matrices(ts)
    assert_rigid_stack(M)
    angles = []
    for Mt in M:
        s = ScrewMotion(Mt)
        angles.append(s.angle)
        if ref.angle > 1e-3:
            np.testing.assert_allclose(Mt[:3, :3] @ ref.axis_direction, ref.axis_direction,
                                       atol=1e-12)
            np.testing.assert_allclose(apply(Mt, ref.axis_point[None])[0] - ref.axis_point,
                                       (s.slide * s.axis_direction @ ref.axis_direction)
                                       * ref.axis_direction, atol=1e-10)
    assert np.all(np.diff(angles) > -1e-12)
    assert angles[-1] == pytest.approx(ref.angle, abs=1e-12)


def test_two_key_motions_for_a_translation_and_a_rotation():
    d = np.array([1.0, -2.0, 0.5])
    m = KeyMotion([np.eye(4), translation(d)])
    np.testing.assert_allclose(m.matrices(T_GRID), translation(T_GRID[:, None] * d), atol=1e-15)
    c, k = np.array([0.0, 3.0, 1.0]), np.array([1.0, 1.0, 0.0])
    m = KeyMotion([np.eye(4), rotation(c, k, 2.0)])
    P = np.array([[1.0, 0, 0], [0, 0, 4.0]])
    traj = apply(m.matrices(T_GRID), P)                  # rational quadratic: circular arcs
    np.testing.assert_allclose(distance_to_line(traj, c, k), np.broadcast_to(
        distance_to_line(P, c, k), traj.shape[:2]), atol=1e-12)
    # a rational quadratic is not at constant speed: the mid parameter is not half the angle
    mid = ScrewMotion(m.matrix(0.5)).angle
    assert mid == pytest.approx(np.arctan2(np.sin(2.0), 1 + np.cos(2.0)), abs=1e-12)


def test_key_motion_half_turn_key():
    """A half turn between neighbours is still well defined (the quaternions are orthogonal,
    their blend never vanishes)."""
    T = rotation([1.0, 0, 0], [0, 0, 1], np.pi)
    m = KeyMotion([np.eye(4), T])
    np.testing.assert_allclose(m.matrix(1.0), T, atol=1e-12)
    assert_rigid_stack(m.matrices(T_GRID))


def test_key_motion_bad_keys():
    R = rotation([0, 0, 0], [0, 0, 1], 0.5)
    cases = [([R, R @ R], None), ([np.eye(4)], None), ([np.eye(4), R, R @ R], [0, 0.7, 0.5]),
             ([np.eye(4), R], [0.0, 0.8]), ([np.eye(4), np.diag([1.0, 1, 2, 1])], None)]
    for keys, params in cases:
        with pytest.raises(DeformError) as err:
            KeyMotion(keys, params)
        assert err.value.prop == "Keys", (keys, params)


# ---------------------------------------------------------------- profile frames

MOTIONS = {
    "bend": ScrewMotion(rotation([0.0, -3.0, 0.0], [1.0, 0, 0], np.pi / 2)),
    "screw": ScrewMotion(random_rigid(7)),
    "keys": KeyMotion(random_keys(3, 5, turn=0.6), [0, 0.2, 0.5, 0.7, 1.0]),
}


@pytest.mark.parametrize("name", list(MOTIONS))
def test_profile_frames_are_normal_to_the_path(name):
    motion = MOTIONS[name]
    P1, x0 = np.array([0.2, 0.1, 0.0]), np.array([1.0, 0.0, 0.0])
    ts = np.linspace(0.0, 1.0, 9)
    F = profile_frames(motion, P1, ts, x0)
    assert F.shape == (9, 4, 4)
    assert_rigid_stack(F)
    M = motion.matrices(ts)
    np.testing.assert_allclose(F[:, :3, 3], apply(M, P1[None])[:, 0], atol=1e-12)
    for i, t in enumerate(ts):
        lo, hi = t - 1e-6, t + 1e-6                    # both motions extend past [0, 1]
        tangent = (apply(motion.matrix(hi), P1[None]) - apply(motion.matrix(lo), P1[None]))[0]
        tangent /= np.linalg.norm(tangent)
        z = F[i, :3, 2]
        np.testing.assert_allclose(z, tangent, atol=1e-6)
        x = M[i, :3, :3] @ x0
        x -= (x @ z) * z
        np.testing.assert_allclose(F[i, :3, 0], x / np.linalg.norm(x), atol=1e-12)


def test_profile_frames_of_a_bend_keep_the_axis_as_x():
    """Revolving about the x axis: the path is a quarter circle, the profile's x axis stays
    the bend axis and its z axis turns from +z to -y."""
    motion = MOTIONS["bend"]
    F = profile_frames(motion, [0.5, 0.0, 0.0], [0.0, 0.5, 1.0], [1.0, 0, 0])
    np.testing.assert_allclose(F[:, :3, 0], np.tile([1.0, 0, 0], (3, 1)), atol=1e-15)
    np.testing.assert_allclose(F[0, :3, 2], [0, 0, 1.0], atol=1e-15)
    np.testing.assert_allclose(F[2, :3, 2], [0, -1.0, 0], atol=1e-15)
    np.testing.assert_allclose(F[2, :3, 3], [0.5, -3.0, 3.0], atol=1e-14)


def test_profile_frames_need_a_moving_point():
    with pytest.raises(DeformError) as err:
        profile_frames(MOTIONS["bend"], [4.0, -3.0, 0.0], [0.0, 1.0])
    assert err.value.prop == "Axis"
