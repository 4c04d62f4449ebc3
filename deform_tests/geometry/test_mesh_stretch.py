"""Mesh Stretch kernel against oracles computed here, independently of the module."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from scipy.spatial import ConvexHull, cKDTree

from freecad_deform.geometry.errors import DeformError
from freecad_deform.geometry.mesh.cut import cut
from freecad_deform.geometry.mesh.stretch import stretch_mesh

from ..oracles.mesh import assert_closed_manifold, blob, volume

Z = np.array([0.0, 0.0, 1.0])
LEVELS = [0.0, 0.7, 1.9, 3.0]                 # uneven rings, so cuts land inside wall quads


# ---------------------------------------------------------------- test meshes

def prism(loops, levels, cap):
    """Closed prism: 2D `loops` (outer counter-clockwise, holes clockwise) extruded through
    the z `levels`; `cap` triangulates the section (counter-clockwise, indices into the
    concatenated loops). Wall quads alternate their diagonal."""
    pts = np.concatenate(loops)
    P = len(pts)
    V = np.array([[x, y, z] for z in levels for x, y in pts])
    T, start = [], 0
    for loop in loops:
        for j in range(len(loop)):
            p, q = start + j, start + (j + 1) % len(loop)
            for lv in range(len(levels) - 1):
                p0, q0, p1, q1 = lv * P + p, lv * P + q, (lv + 1) * P + p, (lv + 1) * P + q
                T += [(p0, q0, q1), (p0, q1, p1)] if (j + lv) % 2 else [(p0, q0, p1), (q0, q1, p1)]
        start += len(loop)
    top = (len(levels) - 1) * P
    T += [(top + a, top + b, top + c) for a, b, c in cap] + [(a, c, b) for a, b, c in cap]
    return V, np.array(T)


def ngon_prism(k, levels=LEVELS, r=1.0):
    """Regular k-gon of circumradius r extruded along z; returns mesh and section area."""
    ang = 2 * np.pi * np.arange(k) / k + 0.1
    loop = r * np.c_[np.cos(ang), np.sin(ang)]
    V, T = prism([loop], levels, [(0, i, i + 1) for i in range(1, k - 1)])
    return V, T, 0.5 * k * r * r * np.sin(2 * np.pi / k)


def box_with_hole(levels=LEVELS):
    """4 x 4 square with a 2 x 2 square through hole, extruded along z; section area 12."""
    outer = np.array([[-2, -2], [2, -2], [2, 2], [-2, 2]], float)
    inner = outer[[0, 3, 2, 1]] / 2                            # clockwise
    o, i = (lambda k: k % 4), (lambda k: 4 + (-k) % 4)
    cap = [t for k in range(4) for t in ((o(k), o(k + 1), i(k + 1)), (o(k), i(k + 1), i(k)))]
    V, T = prism([outer, inner], levels, cap)
    return V, T, 12.0


def lofted_square(levels, per_side):
    """Closed 2 x 2 square prism whose ring at levels[l] has per_side[l] points on each side
    (1 at the ends, so the caps are two triangles); neighbouring rings are joined by walking
    both rings in step, so a coarse ring meets a fine one in fans."""
    corner = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)

    def ring(k):
        t = np.arange(4 * k) / k                                # param along the perimeter
        side = t.astype(int)
        f = (t - side)[:, None]
        return t / 4, corner[side] * (1 - f) + corner[(side + 1) % 4] * f

    rings = [ring(k) for k in per_side]
    start = np.cumsum([0] + [len(t) for t, _ in rings])
    V = np.concatenate([np.c_[xy, np.full(len(xy), z)] for (_, xy), z in zip(rings, levels)])
    T = []
    for lv in range(len(levels) - 1):
        (a, _), (b, _), i, j = rings[lv], rings[lv + 1], 0, 0
        A, B = start[lv], start[lv + 1]
        while i < len(a) or j < len(b):
            ta = a[i + 1] if i + 1 < len(a) else 1.0
            tb = b[j + 1] if j + 1 < len(b) else 1.0
            if j == len(b) or (i < len(a) and ta <= tb):
                T.append((A + i, A + (i + 1) % len(a), B + j % len(b)))
                i += 1
            else:
                T.append((A + i % len(a), B + (j + 1) % len(b), B + j))
                j += 1
    top = start[-2]
    T += [(0, 2, 1), (0, 3, 2), (top, top + 1, top + 2), (top, top + 2, top + 3)]
    return V, np.array(T), 4.0


BLOB = blob()


# ---------------------------------------------------------------- oracles

def edges(T):
    return np.unique(np.sort(np.r_[T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]], axis=1), axis=0)


def plane_points(V, T, origin, n, tol=1e-12):
    """Where the mesh edges meet the plane, in 2D plane coordinates."""
    s = (V - origin) @ n
    a, b = edges(T).T
    x = (s[a] > tol) & (s[b] < -tol) | (s[a] < -tol) & (s[b] > tol)
    t = s[a[x]] / (s[a[x]] - s[b[x]])
    pts = np.r_[V[a[x]] + t[:, None] * (V[b[x]] - V[a[x]]), V[np.abs(s) <= tol]]
    u = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    return pts @ np.c_[u, np.cross(n, u)]


def convex_section_area(V, T, origin, n):
    """Area of a section that is one convex polygon."""
    return ConvexHull(plane_points(V, T, origin, n)).volume


def convex_slab_volume(V, T, origin, n, gap):
    """Volume of a convex mesh between s = 0 and s = gap."""
    s = (V - origin) @ n
    a, b = edges(T).T
    pts = [V[(s >= 0) & (s <= gap)]]
    for h in (0.0, gap):
        x = (s[a] - h) * (s[b] - h) < 0
        t = (s[a[x]] - h) / (s[a[x]] - s[b[x]])
        pts.append(V[a[x]] + t[:, None] * (V[b[x]] - V[a[x]]))
    return ConvexHull(np.concatenate(pts)).volume


def assert_rigid(V0, V, mask, shift, tol):
    """Input vertices under `mask`, moved by `shift` (per vertex or common), are in the output
    (bit-identical when tol is 0)."""
    moved = V0[mask] + shift
    if tol == 0:
        assert set(map(tuple, moved)) <= set(map(tuple, V))
    else:
        assert cKDTree(V).query(moved)[0].max() <= tol


unit = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(lambda v: np.linalg.norm(v) > 0.2)
inside = st.tuples(*[st.floats(-0.4, 0.4)] * 3).map(np.array)


# ---------------------------------------------------------------- cut

def check_cut(V0, T0, origin, n):
    V, T = cut(V0, T0, origin, n)
    n = n / np.linalg.norm(n)
    s0 = (V0 - origin) @ n
    far = np.abs(s0) > 1e-9
    assert np.array_equal(V[:len(V0)][far], V0[far])             # kept at their indices
    s = (V - origin) @ n
    assert np.abs(s[len(V0):]).max(initial=0) < 1e-12            # new vertices on the plane
    st_ = s[T]
    assert not ((st_.max(axis=1) > 1e-12) & (st_.min(axis=1) < -1e-12)).any()
    assert volume(V, T) == pytest.approx(volume(V0, T0), rel=1e-12)
    assert_closed_manifold(V, T)
    return V, T


def test_cut_box_with_hole_oblique():
    V0, T0, _ = box_with_hole()
    V, T = check_cut(V0, T0, [0.1, 0.2, 1.4], np.array([0.3, -0.2, 1.0]))
    assert len(T) > len(T0)


@settings(max_examples=60, deadline=None)
@given(n=unit, origin=inside)
def test_cut_random_planes_on_blob(n, origin):
    check_cut(*BLOB, origin, n)


@settings(max_examples=30, deadline=None)
@given(n=unit, k=st.integers(0, len(BLOB[0]) - 1))
def test_cut_through_a_vertex(n, k):
    V, _ = check_cut(*BLOB, BLOB[0][k], n)
    assert np.array_equal(V[k], BLOB[0][k])


def test_cut_snaps_vertices_within_eps():
    V0, T0, _ = ngon_prism(6)
    V, T = cut(V0, T0, [0, 0, 0.7 + 1e-10], Z)
    assert len(V) == len(V0) and len(T) == len(T0)               # the ring is the cut
    ring = np.abs(V0[:, 2] - 0.7) < 1e-6
    assert np.abs(V[ring, 2] - (0.7 + 1e-10)).max() < 1e-15
    assert np.array_equal(V[~ring], V0[~ring])


@pytest.mark.parametrize("apex", [(0.0, 2.0, 0.0), (2.0, 2.0, 0.0), (-3.0, 2.0, 0.0)])
def test_cut_splits_the_quad_along_its_shorter_diagonal(apex):
    V0 = np.array([[0.0, 0, 0], [1.0, 0, 0], apex])
    V, T = cut(V0, [[0, 1, 2]], [0, 1.0, 0], [0, 1.0, 0])       # cuts both edges at mid-height
    assert len(V) == 5 and len(T) == 3
    pairs = np.sort(np.r_[T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]], axis=1)
    inner, count = np.unique(pairs, axis=0, return_counts=True)
    (diagonal,) = [e for e in inner[count == 2] if min(e) < 3]  # the other one is the cut
    shorter = min(np.linalg.norm(V0[0] - (V0[1] + V0[2]) / 2), np.linalg.norm(V0[1] - V0[2] / 2))
    assert np.linalg.norm(V[diagonal[0]] - V[diagonal[1]]) == pytest.approx(shorter, rel=1e-12)
    assert sum(np.linalg.det(V[T] - [0, 0, 1])) == pytest.approx(np.linalg.det(V0 - [0, 0, 1]))


# ---------------------------------------------------------------- one plane, grow

@pytest.mark.parametrize("normal", [Z, np.array([0.2, -0.1, 1.0])])
@pytest.mark.parametrize("d", [0.4, 2.5])
def test_extend_box_with_hole(normal, d):
    V0, T0, area = box_with_hole()
    n = normal / np.linalg.norm(normal)
    origin = np.array([0.3, -0.2, 1.5])
    V, T = stretch_mesh(V0, T0, origin, normal, d)
    assert_closed_manifold(V, T)
    section = area / n[2]                                        # oblique section of a prism
    assert volume(V, T) - volume(V0, T0) == pytest.approx(section * d, rel=1e-9)
    s0 = (V0 - origin) @ n
    assert_rigid(V0, V, s0 < 0, 0.0, 0)
    assert_rigid(V0, V, s0 > 0, d * n, 1e-12)
    assert ((V - origin) @ n).max() == pytest.approx(s0.max() + d, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(n=unit, origin=inside, d=st.floats(0.01, 2.0))
def test_extend_random_planes_on_blob(n, origin, d):
    V, T = stretch_mesh(*BLOB, origin, n, d)
    assert_closed_manifold(V, T)
    section = convex_section_area(*BLOB, origin, n / np.linalg.norm(n))
    assert volume(V, T) - volume(*BLOB) == pytest.approx(section * d, rel=1e-9)


def test_extend_from_the_bottom_face():
    V0, T0, area = ngon_prism(3)
    V, T = stretch_mesh(V0, T0, [0, 0, 0], Z, 0.8)
    assert_closed_manifold(V, T)
    assert volume(V, T) - volume(V0, T0) == pytest.approx(area * 0.8, rel=1e-9)
    assert V[:, 2].min() == 0 and V[:, 2].max() == pytest.approx(3.8, abs=1e-12)


def test_extend_with_plane_touching_one_vertex_moves_the_part():
    V0, T0 = BLOB
    k = 7
    n = -V0[k]                                  # tangent plane at k, normal pointing inward
    V, T = stretch_mesh(V0, T0, V0[k], n, 0.3)
    assert_closed_manifold(V, T)
    assert len(V) == len(V0)
    assert_rigid(V0, V, np.ones(len(V0), bool), 0.3 * n, 1e-12)
    assert volume(V, T) == pytest.approx(volume(V0, T0), rel=1e-12)


# ---------------------------------------------------------------- one plane, shrink

@pytest.mark.parametrize("mesh", [ngon_prism(7), box_with_hole(), ngon_prism(3),
                                  lofted_square([0, 1, 1.9, 3], [1, 2, 5, 1])],
                         ids=["heptagon", "hole", "triangle", "loft"])
@pytest.mark.parametrize("z, D", [(1.2, 1.1), (0.7, 1.2), (0.0, 1.1), (0.3, 2.65)])
def test_shrink_prism(mesh, z, D):
    V0, T0, area = mesh
    V, T = stretch_mesh(V0, T0, [0, 0, z], Z, -D)
    assert_closed_manifold(V, T)
    assert volume(V0, T0) - volume(V, T) == pytest.approx(area * D, rel=1e-9)
    assert_rigid(V0, V, V0[:, 2] < z, 0.0, 0)
    assert_rigid(V0, V, V0[:, 2] > z + D, -D * Z, 1e-12)
    assert V[:, 2].max() == pytest.approx(3.0 - D, abs=1e-12)


def test_shrink_across_a_slight_taper():
    V0, T0, _ = ngon_prism(6)
    V0[V0[:, 2] > 2, :2] *= 1 + 1e-6                            # top ring widened by 1e-6
    with pytest.raises(DeformError, match="constant cross-section"):
        stretch_mesh(V0, T0, [0, 0, 0.3], Z, -2.0)


def test_shrink_past_the_end():
    V0, T0, _ = ngon_prism(5)
    for D in (1.8 - 5e-10, 1.8, 2.5):                          # the first is within eps
        with pytest.raises(DeformError, match="shrinks past the end") as err:
            stretch_mesh(V0, T0, [0, 0, 1.2], Z, -D)
        assert err.value.prop == "Distance" and "less than 1.8 " in str(err.value)


@pytest.mark.parametrize("mesh, origin, normal", [
    (BLOB, [0, 0, 0.2], [0.3, 0.5, 0.8]),
    (ngon_prism(6)[:2], [0, 0, 1.2], [0.2, 0.0, 1.0]),          # oblique slab of a prism
])
def test_shrink_across_a_changing_section(mesh, origin, normal):
    with pytest.raises(DeformError, match="constant cross-section") as err:
        stretch_mesh(*mesh, origin, normal, -0.3)
    assert err.value.prop == "Distance"


# ---------------------------------------------------------------- two planes

@pytest.mark.parametrize("d", [0.7, -0.5, -1.2])
def test_between_planes_prism(d):
    V0, T0, area = box_with_hole()
    o1, o2 = np.array([0, 0, 0.9]), np.array([0.5, 0.1, 2.2])
    L = 1.3
    V, T = stretch_mesh(V0, T0, o1, Z, d, o2, 2 * Z)
    assert_closed_manifold(V, T)
    between = area * L
    assert volume(V, T) - volume(V0, T0) == pytest.approx(between * d / L, rel=1e-9)
    s = V0[:, 2] - 0.9
    assert_rigid(V0, V, s < 0, 0.0, 0)
    assert_rigid(V0, V, s > L, d * Z, 1e-12)
    mid = (s > 0) & (s < L)
    assert_rigid(V0, V, mid, (s[mid] / L * d)[:, None] * Z, 1e-12)


@settings(max_examples=40, deadline=None)
@given(n=unit, origin=st.tuples(*[st.floats(-0.25, 0.25)] * 3).map(np.array),
       L=st.floats(0.1, 0.45), frac=st.floats(-0.9, 3.0), h=st.floats(0.05, 0.95))
def test_between_planes_blob(n, origin, L, frac, h):
    d = frac * L
    assume(abs(d) > 0.01)
    n = n / np.linalg.norm(n)
    V, T = stretch_mesh(*BLOB, origin, n, d, origin + L * n, n)
    assert_closed_manifold(V, T)
    between = convex_slab_volume(*BLOB, origin, n, L)
    assert volume(V, T) - volume(*BLOB) == pytest.approx(between * d / L, rel=1e-9)
    for s_in, s_out in [(0, 0), (h * L, h * (L + d)), (L, L + d)]:
        assert convex_section_area(V, T, origin + s_out * n, n) == pytest.approx(
            convex_section_area(*BLOB, origin + s_in * n, n), rel=1e-9)


def test_between_planes_snaps_rings_within_eps():
    V0, T0, area = ngon_prism(5)
    z1, z2, d = 0.7 - 4e-10, 1.9 + 4e-10, 0.6                    # rings just off the planes
    V, T = stretch_mesh(V0, T0, [0, 0, z1], Z, d, [0, 0, z2], Z)
    assert_closed_manifold(V, T)
    assert len(V) == len(V0)
    ring1, ring2 = np.isclose(V0[:, 2], 0.7), np.isclose(V0[:, 2], 1.9)
    assert np.abs(V[ring1, 2] - z1).max() < 1e-15
    assert np.abs(V[ring2, 2] - (z2 + d)).max() < 1e-15
    assert volume(V, T) - volume(V0, T0) == pytest.approx(area * d, rel=1e-9)


def test_between_planes_errors():
    V0, T0, _ = ngon_prism(5)
    with pytest.raises(DeformError) as err:
        stretch_mesh(V0, T0, [0, 0, 1], Z, 0.5, [0, 0, 2], [0.1, 0, 1])
    assert err.value.prop == "Plane2"
    for d in (-1.0, -1.5):
        with pytest.raises(DeformError, match=r"above -1\b") as err:
            stretch_mesh(V0, T0, [0, 0, 1], Z, d, [0, 0, 2], Z)
        assert err.value.prop == "Distance"
    with pytest.raises(DeformError, match="misses") as err:
        stretch_mesh(V0, T0, [0, 0, 1], Z, 0.5, [0, 0, 3.5], Z)
    assert err.value.prop == "Plane2"


# ---------------------------------------------------------------- plane misses, no-op

@pytest.mark.parametrize("z", [-0.5, 3.5])
@pytest.mark.parametrize("extra", [(0.5,), (-0.5,), (0.5, [0, 0, 5], Z)])
def test_plane_misses(z, extra):
    V0, T0, _ = ngon_prism(4)
    with pytest.raises(DeformError, match="misses the part") as err:
        stretch_mesh(V0, T0, [0, 0, z], Z, *extra)
    assert err.value.prop == "Plane"


def test_zero_distance_returns_copies():
    V0, T0, _ = box_with_hole()
    V, T = stretch_mesh(V0, T0, [0, 0, 1], Z, 0.0)
    assert np.array_equal(V, V0) and np.array_equal(T, T0)
    assert not np.shares_memory(V, V0) and not np.shares_memory(T, T0)
