"""Point-cloud bend / twist / general motions: rigid parts exact, the fill on the revolved
section, and the paper's turbine blade (Wu & Ilies, Fig. 9) extended 3x and twisted 30 deg."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.mesh.sweep import bend_motion, twist_motion
from freecad_deform.geometry.sweep.motion import ScrewMotion, rotation, translation
from freecad_deform.geometry.points.stretch import stretch_points
from freecad_deform.geometry.points.sweep import map_points_between, sweep_points

X, Z = np.array([1.0, 0, 0]), np.array([0.0, 0, 1.0])


def box_surface(step=0.5, size=(10.0, 6.0, 4.0)):
    """Points on the surface of an axis-aligned box on a regular grid of `step`."""
    axes = [np.arange(0.0, s + 1e-9, step) for s in size]
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(3, -1).T
    return grid[np.any(np.isclose(grid, 0.0) | np.isclose(grid, size), axis=1)]


BOX = box_surface()


def turned(points, c, k, angle):
    k = np.asarray(k, float) / np.linalg.norm(k)
    return Rotation.from_rotvec(angle * k).apply(np.asarray(points) - c) + c


# ---------------------------------------------------------------- Case 1: sweep_points

@settings(max_examples=30, deadline=None)
@given(angle=st.floats(0.2, 3.0), offset=st.floats(0.5, 5.0), plane_x=st.floats(2.2, 7.8))
def test_bend_cloud(angle, offset, plane_x):
    """Bend about the line x = plane_x, y = -offset (along -z, so the far part turns toward
    +x first): rigid parts exact, fill points are section points turned about the axis by
    angles strictly inside (0, angle), at spacing ~step along the centroid's arc."""
    c, k = np.array([plane_x, -offset, 0.0]), -Z
    motion = ScrewMotion(rotation(c, k, angle))
    out = sweep_points(BOX, [plane_x, 0, 0], X, motion)
    s = BOX[:, 0] - plane_x
    base = out[:len(BOX)]
    np.testing.assert_array_equal(base[s <= 0], BOX[s <= 0])
    np.testing.assert_allclose(base[s > 0], turned(BOX[s > 0], c, k, angle), atol=1e-12)
    fill = out[len(BOX):]
    # angle of each fill point about the axis, from the plane (where the section lies)
    rel = fill - c
    phi = np.arctan2(rel[:, 0], rel[:, 1])                          # from +y toward +x
    assert phi.min() > 1e-9 and phi.max() < angle - 1e-9
    back = np.array([turned(p[None], c, k, -a)[0] for p, a in zip(fill, phi)])
    near = np.abs(s) <= 0.25
    section = BOX[near] - np.outer(s[near], X)
    assert cKDTree(section).query(back)[0].max() < 1e-12
    # layers of equal angle, the centroid's arc between them about one step
    levels = np.unique(np.round(phi, 9))
    r_c = np.linalg.norm((section.mean(axis=0) - c)[:2])
    layers = int(np.ceil(r_c * angle / 0.5 - 1e-9))
    assert len(levels) == layers - 1
    np.testing.assert_allclose(levels, np.arange(1, layers) * angle / layers, atol=1e-6)
    assert r_c * angle / layers <= 0.5 + 1e-9
    assert len(fill) == len(section) * (layers - 1)


@pytest.mark.parametrize("normal, d", [(X, 3.0), (np.array([1.0, 0.3, -0.2]), 2.2)])
def test_translation_fill_is_the_stretch_fill(normal, d):
    n = normal / np.linalg.norm(normal)
    origin = np.array([5.0, 1.0, 2.0])
    expect = stretch_points(BOX, origin, n, d)
    got = sweep_points(BOX, origin, n, ScrewMotion(translation(d * n)))
    assert got.shape == expect.shape
    np.testing.assert_allclose(got, expect, atol=1e-12)


def test_step_sets_the_fill_density():
    motion = ScrewMotion(translation(3.0 * X))
    coarse = sweep_points(BOX, [5.0, 0, 0], X, motion, step=1.0)
    fine = sweep_points(BOX, [5.0, 0, 0], X, motion, step=0.25)
    layers = lambda out: np.unique(np.round(out[len(BOX):, 0], 9))
    np.testing.assert_allclose(layers(coarse), [6.0, 7.0])
    np.testing.assert_allclose(np.diff(layers(fine)), 0.25)


# ---------------------------------------------------------------- Case 2: map_points_between

def test_twist_cloud_between_planes():
    c, angle, gap = np.array([0.0, 3.0, 2.0]), 0.8, 4.0
    f = twist_motion([3.0, 0, 0], X, gap, angle, c, X)
    out = map_points_between(BOX, [3.0, 0, 0], X, gap, f)
    s = BOX[:, 0] - 3.0
    assert out.shape == BOX.shape
    np.testing.assert_array_equal(out[s <= 0], BOX[s <= 0])
    frac = np.clip(s / gap, 0, 1)
    expect = np.array([turned(p[None], c, X, a * angle)[0] for p, a in zip(BOX, frac)])
    np.testing.assert_allclose(out, expect, atol=1e-12)
    np.testing.assert_array_equal(out[:, 0], BOX[:, 0])          # length along the axis kept


def test_bend_cloud_between_planes_lands_on_the_revolved_section():
    c, k, angle, gap = np.array([4.0, -1.0, 0.0]), -Z, 1.0, 2.0
    f = bend_motion(c, k, angle, [4.0, 0, 0], X, gap)
    out = map_points_between(BOX, [4.0, 0, 0], X, gap, f)
    s = BOX[:, 0] - 4.0
    mid = (s > 0) & (s < gap)
    expect = np.array([turned(p[None] - si * X, c, k, si / gap * angle)[0]
                       for p, si in zip(BOX[mid], s[mid])])
    np.testing.assert_allclose(out[mid], expect, atol=1e-12)
    # distance to the axis is the distance of the projected section point
    np.testing.assert_allclose(np.linalg.norm((out[mid] - c)[:, :2], axis=1),
                               np.abs(BOX[mid, 1] - c[1]), atol=1e-12)
    far = s >= gap
    np.testing.assert_allclose(out[far], turned(BOX[far] - gap * X, c, k, angle), atol=1e-12)


# ---------------------------------------------------------------- the turbine blade

def naca4(code="2412", count=60):
    """Closed outline of a NACA 4-digit profile of chord 1 (cosine spacing, closed trailing
    edge), upper surface from the trailing edge to the nose then the lower back, no repeats."""
    m, p, t = int(code[0]) / 100, int(code[1]) / 10, int(code[2:]) / 100
    x = (1 - np.cos(np.linspace(0, np.pi, count))) / 2
    yt = 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3
                  - 0.1036 * x ** 4)
    yc = np.where(x < p, m / p ** 2 * (2 * p * x - x ** 2),
                  m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x ** 2))
    dyc = np.where(x < p, 2 * m / p ** 2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
    th = np.arctan(dyc)
    upper = np.c_[x - yt * np.sin(th), yc + yt * np.cos(th)]
    lower = np.c_[x + yt * np.sin(th), yc - yt * np.cos(th)]
    return np.r_[upper[::-1], lower[1:-1]]


def blade(length=4.0, levels=81):
    """Stacked airfoil sections along z: chord tapering from 1 to 0.7, a 10 degree built-in
    twist; each section's point centroid on the z axis."""
    profile = naca4()
    zs = np.linspace(0.0, length, levels)
    rings = []
    for z in zs:
        frac = z / length
        xy = (profile - profile.mean(axis=0)) * (1 - 0.3 * frac)
        xy = xy @ Rotation.from_euler("z", 10 * frac, degrees=True).as_matrix()[:2, :2].T
        rings.append(np.c_[xy, np.full(len(xy), z)])
    return np.concatenate(rings), zs


def test_naca_outline():
    outline = naca4()
    assert len(np.unique(np.round(outline, 12), axis=0)) == len(outline)
    area = 0.5 * np.sum(outline[:, 0] * np.roll(outline[:, 1], -1)
                        - np.roll(outline[:, 0], -1) * outline[:, 1])
    assert 0.07 < abs(area) < 0.09            # a 12% thick profile: about 0.0822 c^2


def test_turbine_blade_extended_3x_and_twisted_30_degrees():
    pts, zs = blade()
    L = zs[-1]
    twist = twist_motion([0, 0, 0], Z, L, np.radians(30.0))       # about the z axis (x = y = 0)
    grow = lambda frac: twist(frac) @ translation(frac * 2 * L * Z)  # s -> 3 s
    out = map_points_between(pts, [0, 0, 0], Z, L, grow)
    heights = np.round(out[:, 2], 9)
    assert set(heights) == set(np.round(3 * zs, 9))
    for z in zs:
        before = pts[pts[:, 2] == z]
        after = out[heights == np.round(3 * z, 9)]
        assert len(after) == len(before)
        # the centroid of every horizontal cross-section stays on the vertical line
        np.testing.assert_allclose(after[:, :2].mean(axis=0), [0.0, 0.0], atol=1e-9)
        expect = turned(before, [0, 0, 0], Z, np.radians(30.0) * z / L) + [0, 0, 2 * z]
        np.testing.assert_allclose(after, expect, atol=1e-12)
    top = out[heights == np.round(3 * L, 9)]
    top_before = pts[pts[:, 2] == L]
    np.testing.assert_allclose(top[:, 2], 3 * L, atol=1e-12)
    cos = np.einsum("ij,ij->i", top[:, :2], top_before[:, :2]) / (
        np.linalg.norm(top[:, :2], axis=1) * np.linalg.norm(top_before[:, :2], axis=1))
    np.testing.assert_allclose(np.degrees(np.arccos(np.clip(cos, -1, 1))), 30.0, atol=1e-6)
    cross = top_before[:, 0] * top[:, 1] - top_before[:, 1] * top[:, 0]
    assert (cross > 0).all()                                       # counter-clockwise about z
    root = pts[:, 2] == 0
    np.testing.assert_array_equal(out[root], pts[root])


# ---------------------------------------------------------------- errors

BEND = ScrewMotion(rotation([5.0, -2.0, 0.0], -Z, 1.0))
TWIST = twist_motion([3.0, 0, 0], X, 2.0, 0.5)


@pytest.mark.parametrize("call, prop", [
    (lambda: sweep_points(BOX, [12.0, 0, 0], X, BEND), "Plane"),
    (lambda: sweep_points(BOX, [-1.0, 0, 0], X, BEND), "Plane"),
    (lambda: sweep_points(BOX, [5.0, 0, 0], [0, 0, 0], BEND), "Plane"),
    (lambda: sweep_points(BOX, [5.0, 0, 0], X, BEND, step=0.0), "Step"),
    (lambda: sweep_points(np.repeat(BOX[:1], 3, axis=0), BOX[0], X, BEND), "Base"),  # spacing
    (lambda: map_points_between(BOX, [12.0, 0, 0], X, 1.0, TWIST), "Plane"),
    (lambda: map_points_between(BOX, [3.0, 0, 0], X, 8.0, TWIST), "Plane2"),
    (lambda: map_points_between(BOX, [3.0, 0, 0], X, 0.0, TWIST), "Plane2"),
    (lambda: map_points_between(BOX, [3.0, 0, 0], X, -2.0, TWIST), "Plane2"),
])
def test_errors_name_the_property(call, prop):
    with pytest.raises(DeformError) as err:
        call()
    assert err.value.prop == prop
    assert prop in str(err.value)
