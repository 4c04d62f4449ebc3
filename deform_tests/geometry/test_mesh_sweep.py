"""Bend / twist / general motions on closed meshes, against oracles computed here: Pappus and
the exact volume of a chord-sampled revolve, divergence-theorem volumes, closed-manifold edge
counts and scipy rotations."""
import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st
from scipy.spatial import ConvexHull, cKDTree
from scipy.spatial.transform import Rotation

from freecad_deform.geometry import DeformError

from ..oracles import mesh as oracles
from ..oracles.mesh import blob, volume
from freecad_deform.geometry.mesh.stretch import stretch_mesh
from freecad_deform.geometry.mesh.sweep import (bend_motion, map_between, move_by_fraction,
                                                sweep_mesh, twist_motion)
from freecad_deform.geometry.sweep.motion import KeyMotion, ScrewMotion, rotation, translation

Z = np.array([0.0, 0.0, 1.0])
LEVELS = [0.0, 0.7, 1.9, 3.0]


# ---------------------------------------------------------------- test meshes and oracles

def prism(loop, levels=LEVELS):
    """Closed prism: the counter-clockwise convex 2D `loop` extruded through the z levels,
    wall quads with alternating diagonals, caps fanned from vertex 0."""
    P = len(loop)
    V = np.array([[x, y, z] for z in levels for x, y in loop])
    T = []
    for j in range(P):
        q = (j + 1) % P
        for lv in range(len(levels) - 1):
            p0, q0, p1, q1 = lv * P + j, lv * P + q, (lv + 1) * P + j, (lv + 1) * P + q
            T += [(p0, q0, q1), (p0, q1, p1)] if (j + lv) % 2 else [(p0, q0, p1), (q0, q1, p1)]
    top = (len(levels) - 1) * P
    T += [(top, top + i, top + i + 1) for i in range(1, P - 1)]
    T += [(0, i + 1, i) for i in range(1, P - 1)]
    return V, np.array(T)


def ngon(k, r=1.0):
    ang = 2 * np.pi * np.arange(k) / k + 0.1
    return r * np.c_[np.cos(ang), np.sin(ang)], 0.5 * k * r * r * np.sin(2 * np.pi / k)


SQUARE = np.array([[-1.0, -1], [1, -1], [1, 1], [-1, 1]])


BLOB = blob(400)


def assert_closed_manifold(V, T):
    """Closed 2-manifold, and no triangle flat to rounding: twice its area over its longest
    edge squared above 1e-10. Not an absolute area: a plane passing 4.7e-7 from a vertex
    (beyond the kernel's 1e-9 snap) rightly cuts off a well-shaped corner of area 1e-13."""
    oracles.assert_closed_manifold(V, T, min_area=0.0)
    P = np.asarray(V, float)[np.asarray(T)]
    edges = np.linalg.norm(P - np.roll(P, 1, axis=1), axis=2).max(axis=1)
    twice = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    assert (twice / edges ** 2).min() > 1e-10


def turned(points, c, k, angle):
    """Oracle rotation by scipy: points turned by angle about the line (c, k)."""
    k = np.asarray(k, float) / np.linalg.norm(k)
    return Rotation.from_rotvec(angle * k).apply(np.asarray(points) - c) + c


def present(V, points, tol):
    """Every one of `points` is a vertex of V (within tol)."""
    return cKDTree(V).query(np.asarray(points).reshape(-1, 3))[0].max() <= tol


def section_points(V0, T0, z):
    """Where the edges of a mesh cross the plane at height z (and vertices on it)."""
    E = np.unique(np.sort(np.r_[T0[:, [0, 1]], T0[:, [1, 2]], T0[:, [2, 0]]], axis=1), axis=0)
    a, b = E.T
    s = V0[:, 2] - z
    x = s[a] * s[b] < 0
    t = s[a[x]] / (s[a[x]] - s[b[x]])
    return np.r_[V0[a[x]] + t[:, None] * (V0[b[x]] - V0[a[x]]), V0[s == 0]]


# ---------------------------------------------------------------- Case 1: sweep_mesh

BEND_C, BEND_K, BEND_Z = np.array([-2.0, 0.0, 1.2]), np.array([0.0, -1.0, 0.0]), 1.2


def bent_prism(samples, angle=np.pi / 2, k=12):
    loop, area = ngon(k)
    V0, T0 = prism(loop)
    motion = ScrewMotion(rotation(BEND_C, BEND_K, angle))
    V, T = sweep_mesh(V0, T0, [0, 0, BEND_Z], Z, motion, samples)
    return V0, T0, V, T, area


@pytest.mark.parametrize("samples", [1, 4, 16, 64])
def test_bend_prism_is_closed_with_rigid_ends_and_exact_rings(samples):
    angle = np.pi / 2
    V0, T0, V, T, _ = bent_prism(samples, angle)
    assert_closed_manifold(V, T)
    near, far = V0[:, 2] < BEND_Z, V0[:, 2] > BEND_Z
    assert set(map(tuple, V0[near])) <= set(map(tuple, V))               # bit-identical
    assert present(V, turned(V0[far], BEND_C, BEND_K, angle), 1e-12)
    ring = section_points(V0, T0, BEND_Z)
    for i in range(samples + 1):                                        # every ring, exactly
        assert present(V, turned(ring, BEND_C, BEND_K, angle * i / samples), 1e-12)
    # nothing else: cut vertices, one copy of the ring per level, no stray vertex
    assert len(V) == len(V0) + len(ring) * (samples + 1)


def test_bend_prism_volume_converges_to_pappus():
    """The band is the section revolved along chords: each of the n slabs has volume
    A r_c sin(angle/n) exactly (a prismatoid with parallel chords), so the total converges
    from inside to Pappus' A r_c angle, with relative error 1 - sin(d)/d ~ d^2/6."""
    angle, r_c = np.pi / 2, 2.0
    errors = []
    for samples in (2, 4, 8, 16, 32):
        V0, T0, V, T, area = bent_prism(samples, angle)
        band = volume(V, T) - volume(V0, T0)
        assert band == pytest.approx(area * r_c * samples * np.sin(angle / samples), rel=1e-10)
        pappus = area * r_c * angle
        assert band < pappus
        errors.append((pappus - band) / pappus)
    assert errors[3] < 0.02
    assert all(b < a / 3.9 for a, b in zip(errors, errors[1:]))    # second order in 1/samples


def test_bend_with_a_rational_key_motion():
    """The same bend driven by a two-key rational motion: every M(t) turns about the bend
    axis, so each band vertex is a section point turned about it (rational quadratic arcs,
    17 levels unevenly spaced in angle); closed; far end exact; the chord band inside Pappus."""
    loop, area = ngon(10)
    V0, T0 = prism(loop)
    angle = np.pi / 2
    T_end = rotation(BEND_C, BEND_K, angle)
    V, T = sweep_mesh(V0, T0, [0, 0, BEND_Z], Z, KeyMotion([np.eye(4), T_end]), 16)
    assert_closed_manifold(V, T)
    far = V0[:, 2] > BEND_Z
    moved = turned(V0[far], BEND_C, BEND_K, angle)
    assert present(V, moved, 1e-12)
    rigid = (cKDTree(V0[~far]).query(V)[0] == 0) | (cKDTree(moved).query(V)[0] <= 1e-12)
    band = V[~rigid]
    phi = np.arctan2(band[:, 2] - BEND_Z, band[:, 0] - BEND_C[0])    # turn about the axis
    back = np.array([turned(v[None], BEND_C, BEND_K, -p)[0] for v, p in zip(band, phi)])
    assert present(section_points(V0, T0, BEND_Z), back, 1e-12)
    levels = np.unique(np.round(phi, 9))
    assert len(levels) == 17 and levels[0] == 0 and levels[-1] == pytest.approx(angle)
    assert np.ptp(np.diff(levels)) > 1e-3                            # not a constant speed
    band_volume = volume(V, T) - volume(V0, T0)
    assert 0.98 * area * 2.0 * angle < band_volume < area * 2.0 * angle


@pytest.mark.parametrize("normal, d", [(Z, 0.8), (np.array([0.2, -0.1, 1.0]), 1.7)])
def test_pure_translation_one_sample_is_the_stretch_band(normal, d):
    loop, _ = ngon(7)
    V0, T0 = prism(loop)
    n = normal / np.linalg.norm(normal)
    origin = np.array([0.1, 0.0, 1.4])
    V1, T1 = stretch_mesh(V0, T0, origin, normal, d)
    V2, T2 = sweep_mesh(V0, T0, origin, normal, ScrewMotion(translation(d * n)), 1)
    np.testing.assert_array_equal(T2, T1)
    np.testing.assert_allclose(V2, V1, atol=1e-12)
    V3, T3 = sweep_mesh(V0, T0, origin, normal, ScrewMotion(translation(d * n)), 5)
    assert_closed_manifold(V3, T3)
    assert volume(V3, T3) == pytest.approx(volume(V1, T1), rel=1e-12)


unit = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(lambda v: np.linalg.norm(v) > 0.2)
inside = st.tuples(*[st.floats(-0.4, 0.4)] * 3).map(np.array)


@settings(max_examples=40, deadline=None)
@given(n=unit, origin=inside, d=st.floats(0.05, 2.0), angle=st.floats(-2.0, 2.0),
       samples=st.integers(1, 12))
@example(n=np.array((-0.333333335846078, 1.0, 0.0)),  # 4.7e-7 from a vertex
         origin=np.array((-0.2862567901611333, 0.3059697076969321, 0.0)), d=1.0, angle=0.0,
         samples=1)
def test_screw_along_the_normal_on_blob(n, origin, d, angle, samples):
    """A screw about the plane normal (twist while extruding): closed, rigid parts exact;
    its band encloses A*d (Cavalieri) up to the sampling error of the turn d per ring:
    a first-order term from the diagonal of each twisted (non-planar) band quad, which
    shrinks with the mesh's edge length, plus the second-order chord term. Measured on
    this 400-vertex blob: error below 0.67 (0.05 d + d^2) over 400 random cases."""
    n = n / np.linalg.norm(n)
    T_end = rotation(origin, n, angle) @ translation(d * n)
    V, T = sweep_mesh(*BLOB, origin, n, ScrewMotion(T_end), samples)
    assert_closed_manifold(V, T)
    s = (BLOB[0] - origin) @ n
    assert set(map(tuple, BLOB[0][s < -1e-9])) <= set(map(tuple, V))
    far = BLOB[0][s > 1e-9]
    moved = far @ T_end[:3, :3].T + T_end[:3, 3]
    assert present(V, moved, 1e-12)
    u = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    area = ConvexHull(section_points_general(*BLOB, origin, n) @ np.c_[u, np.cross(n, u)]).volume
    delta = abs(angle) / samples
    assert volume(V, T) - volume(*BLOB) == pytest.approx(area * d, rel=0.05 * delta + delta ** 2 + 1e-9)


def section_points_general(V0, T0, origin, n):
    E = np.unique(np.sort(np.r_[T0[:, [0, 1]], T0[:, [1, 2]], T0[:, [2, 0]]], axis=1), axis=0)
    a, b = E.T
    s = (V0 - origin) @ n
    x = s[a] * s[b] < 0
    t = s[a[x]] / (s[a[x]] - s[b[x]])
    return V0[a[x]] + t[:, None] * (V0[b[x]] - V0[a[x]])


# ---------------------------------------------------------------- Case 2: map_between

Z1, Z2 = 0.4, 2.5                          # planes between the prism's rings


def twisted_square(samples, angle=np.pi / 2):
    V0, T0 = prism(SQUARE)
    f = twist_motion([0, 0, Z1], Z, Z2 - Z1, angle)
    V, T = map_between(V0, T0, [0, 0, Z1], Z, Z2 - Z1, f, samples)
    return V0, T0, V, T


@pytest.mark.parametrize("samples", [1, 3, 16])
def test_twist_square_prism(samples):
    angle = np.pi / 2
    V0, T0, V, T = twisted_square(samples, angle)
    assert_closed_manifold(V, T)
    near, far = V0[:, 2] < Z1, V0[:, 2] > Z2
    np.testing.assert_array_equal(V[:len(V0)][near], V0[near])           # bit-identical, in place
    np.testing.assert_allclose(V[:len(V0)][far], turned(V0[far], [0, 0, 0], Z, angle),
                               atol=1e-12)
    # the twisted walls' quadrilaterals get centres (check_centres); the other vertices ...
    first = oracles.centres_from(V, V0, [0, 0, Z1], Z, Z2 - Z1, samples)
    assert first < len(V)
    oracles.check_centres(V, T, first, 1e-12)
    V = V[:first]
    np.testing.assert_array_equal(np.unique(np.round(V[:, 2], 12)),      # heights kept
                                  np.unique(np.round(np.r_[V0[:, 2], Z1 + (Z2 - Z1) *
                                                           np.arange(samples + 1) / samples], 12)))
    for i in range(samples + 1):
        z = Z1 + (Z2 - Z1) * i / samples
        on = np.abs(V[:, 2] - z) < 1e-12
        back = turned(V[on], [0, 0, 0], Z, -angle * i / samples)[:, :2]
        # the section there is the original square: every vertex on its outline ...
        assert np.abs(np.abs(back).max(axis=1) - 1.0).max() < 1e-12
        # ... and its corners all present, turned by the plane's fraction of the angle
        corners = np.c_[SQUARE, np.full(4, z)]
        assert present(V[on], turned(corners, [0, 0, 0], Z, angle * i / samples), 1e-12)


def test_twist_volume_error_is_second_order():
    """A 90 degree twist keeps the volume up to the flat-triangle error of each slab (the
    triangulated walls cut inside the ruled twisted walls), second order in the turn per
    slab: 0.15% of the twisted slab's volume at 16 samples (bound 0.2%), 0.56% at 8, 1.8%
    at 4, and a quarter of it for each doubling."""
    slab = 4.0 * (Z2 - Z1)
    errors = []
    for samples in (8, 16, 32, 64):
        V0, T0, V, T = twisted_square(samples)
        change = volume(V, T) - volume(V0, T0)
        assert change < 0                                     # flat walls cut inside
        errors.append(-change / slab)
    assert errors[1] < 0.002
    for a, b in zip(errors, errors[1:]):
        assert 0.22 < b / a < 0.29


def test_twist_about_an_offset_axis_with_a_plain_callable():
    """motion_of_s may be any callable frac -> 4x4; same result as the vectorized one."""
    V0, T0 = prism(SQUARE)
    c, axis = np.array([0.3, -0.2, 0.0]), np.array([0.0, 0.1, 1.0])
    f = twist_motion([0, 0, Z1], Z, Z2 - Z1, 1.1, c, axis)
    g = lambda frac: rotation(c, axis, frac * 1.1)
    V1, T1 = map_between(V0, T0, [0, 0, Z1], Z, Z2 - Z1, f, 8)
    V2, T2 = map_between(V0, T0, [0, 0, Z1], Z, Z2 - Z1, g, 8)
    np.testing.assert_array_equal(T1, T2)
    np.testing.assert_allclose(V1, V2, atol=1e-15)
    far = V0[:, 2] > Z2
    np.testing.assert_allclose(V1[:len(V0)][far], turned(V0[far], c, axis, 1.1), atol=1e-12)


@pytest.mark.parametrize("samples", [4, 16])
def test_bend_between_two_planes(samples):
    """Bend over a gap: the slab becomes the section at Plane revolved by the angle (chord
    sampled), the far part turned and pulled back by the gap. (No ring of the prism lies
    strictly between the planes, so each slab is the exact chord prismatoid.)"""
    loop, area = ngon(12)
    V0, T0 = prism(loop)
    angle, gap = np.pi / 2, 0.6
    f = bend_motion(BEND_C, BEND_K, angle, [0, 0, BEND_Z], Z, gap)
    V, T = map_between(V0, T0, [0, 0, BEND_Z], Z, gap, f, samples)
    assert_closed_manifold(V, T)
    change = volume(V, T) - volume(V0, T0)
    assert change == pytest.approx(area * (2.0 * samples * np.sin(angle / samples) - gap),
                                   rel=1e-10)
    far = V0[:, 2] > BEND_Z + gap
    expect = turned(V0[far] - gap * Z, BEND_C, BEND_K, angle)
    np.testing.assert_allclose(V[:len(V0)][far], expect, atol=1e-12)
    corners = np.c_[loop, np.full(len(loop), BEND_Z)]       # the wall edges cross each plane
    for i in range(samples + 1):                            # at the section's corners
        assert present(V, turned(corners, BEND_C, BEND_K, angle * i / samples), 1e-12)


def test_bend_motion_formula():
    f = bend_motion(BEND_C, BEND_K, 0.7, [0, 0, BEND_Z], Z, 1.1)
    for frac in (0.0, 0.3, 1.0):
        np.testing.assert_allclose(
            f(frac), rotation(BEND_C, BEND_K, frac * 0.7) @ translation(-frac * 1.1 * Z),
            atol=1e-15)
    np.testing.assert_allclose(f(np.array([0.3, 1.0]))[1], f(1.0), atol=1e-15)


@pytest.mark.parametrize("motion", [
    twist_motion([0, 0, 1.0], Z, 2.0, 1.3, [0.4, -0.2, 0], Z),
    twist_motion([0, 0, 1.0], Z, 2.0, -0.8, [0.4, -0.2, 0], [0.2, -0.3, 1.0]),
    bend_motion(BEND_C, BEND_K, 0.7, [0, 0, BEND_Z], Z, 1.1)])
def test_move_by_fraction_keeps_rows_at_zero_bit_for_bit(motion):
    """Rows with f = 0 (f > 0 at random among them, as in a cloud) keep their bits, signed
    zeros and a coordinate at infinity included; the others go where their own 4x4 takes
    them."""
    rng = np.random.default_rng(7)
    P = rng.normal(size=(40000, 3))
    for k, share in enumerate((0.2, 0.3, 0.3)):
        P[rng.random(len(P)) < share, k] = (-0.0, 0.0, -0.0)[k]
    f = np.clip(rng.normal(size=len(P)), 0.0, 1.0)
    f[rng.random(len(P)) < 0.1] = -0.0
    P[7, 1], f[7] = np.inf, 0.0
    with np.errstate(invalid="ignore"):                     # infinity times 0
        out = move_by_fraction(P, f, motion)
    still = f <= 0
    assert np.array_equal(out[still].view(np.uint64), P[still].view(np.uint64))
    moved = np.flatnonzero(~still)
    M = motion(f[moved])
    expected = np.einsum("kij,kj->ki", M[:, :3, :3], P[moved]) + M[:, :3, 3]
    np.testing.assert_allclose(out[moved], expected, rtol=0, atol=1e-14)


# ---------------------------------------------------------------- errors

BEND = ScrewMotion(rotation(BEND_C, BEND_K, 1.0))


@pytest.mark.parametrize("call, prop", [
    (lambda V, T: sweep_mesh(V, T, [0, 0, 3.5], Z, BEND), "Plane"),
    (lambda V, T: sweep_mesh(V, T, [0, 0, -0.5], Z, BEND), "Plane"),
    (lambda V, T: sweep_mesh(V, T, [0, 0, 1.2], Z, BEND, 0), "Samples"),
    (lambda V, T: sweep_mesh(V, T, [0, 0, 1.2], Z, BEND, 2.5), "Samples"),
    (lambda V, T: sweep_mesh(V, T, [0, 0, 1.2], Z, ScrewMotion(
        rotation([0.5, 0, 1.2], BEND_K, 1.0))), "Axis"),               # axis crosses section
    (lambda V, T: sweep_mesh(V, T, [0, 0, 1.2], Z, ScrewMotion(
        rotation(BEND_C, -BEND_K, 1.0))), "Angle"),                    # turns backward
    (lambda V, T: map_between(V, T, [0, 0, 3.5], Z, 1.0, twist_motion([0, 0, 3.5], Z, 1, 1)),
     "Plane"),
    (lambda V, T: map_between(V, T, [0, 0, 1.0], Z, 2.5, twist_motion([0, 0, 1], Z, 2.5, 1)),
     "Plane2"),
    (lambda V, T: map_between(V, T, [0, 0, 1.0], Z, 0.0, lambda f: np.eye(4)), "Plane2"),
    (lambda V, T: map_between(V, T, [0, 0, 1.0], Z, -1.0, lambda f: np.eye(4)), "Plane2"),
    (lambda V, T: map_between(V, T, [0, 0, 1.0], Z, 1.0, lambda f: np.eye(4), 0), "Samples"),
    (lambda V, T: twist_motion([0, 0, 1.0], Z, 0.0, 1.0), "Plane2"),
])
def test_errors_name_the_property(call, prop):
    V0, T0 = prism(SQUARE)
    with pytest.raises(DeformError) as err:
        call(V0, T0)
    assert err.value.prop == prop
    assert prop in str(err.value)


@pytest.mark.parametrize("origin", [(np.nan, 0, 0), (0, 0, np.nan), (np.inf, 0, 0)])
def test_twist_with_a_plane_not_finite_is_refused_naming_plane(origin):
    """map_between gave the mesh back unchanged for a NaN or infinite Plane (min and max of
    Python skip NaN, so the planes' ends looked like -inf..inf, which crosses)."""
    V0, T0 = prism(SQUARE)
    with np.errstate(invalid="ignore"), pytest.raises(DeformError) as err:
        map_between(V0, T0, np.array(origin, float), Z, Z2 - Z1,
                    twist_motion([0, 0, Z1], Z, Z2 - Z1, 0.5), 4)
    assert err.value.prop == "Plane"


def test_twist_of_an_empty_mesh_is_refused_naming_base():
    with pytest.raises(DeformError) as err:
        map_between(np.empty((0, 3)), np.empty((0, 3), np.int64), [0, 0, Z1], Z, Z2 - Z1,
                    twist_motion([0, 0, Z1], Z, Z2 - Z1, 0.5), 4)
    assert err.value.prop == "Base"
