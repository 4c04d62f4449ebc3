"""map_between's band cut at every Samples plane at once (mesh_sweep.slab_cut), without
FreeCAD, against oracles written for the tests (deform_tests/oracles/mesh.py): the number of
pieces a triangle crossing k planes must give, half-edge counts, the input's sections (edge
crossings) turned by scipy, and the divergence-theorem volume."""
import os
import signal

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.sweep import space_map
from freecad_deform.geometry.mesh.sweep import map_between, slab_cut, twist_motion

from ..oracles.mesh import assert_closed_manifold, blob, centres_from, check_centres, volume
from ..oracles.mesh import distance_to_segments, expected_count, section_segments

BLOB = blob(300)
BIG = blob(140000, seed=3)         # over 8 blocks of vertices: cut on two threads


def twisted(V0, T0, origin, n, gap, angle, samples, centre=None):
    centre = np.zeros(3) if centre is None else centre
    f = twist_motion(origin, n, gap, angle, centre, n)
    return map_between(V0, T0, origin, n, gap, f, samples)


def untwist(origin, n, gap, angle, centre=None):
    """Moved points (k, 3) -> their input places: turned back by -angle clip(s / gap)
    about the axis (scipy)."""
    centre = np.zeros(3) if centre is None else np.asarray(centre, float)

    def back(P):
        f = np.clip((P - origin) @ n / gap, 0, 1)
        return Rotation.from_rotvec(-angle * f[:, None] * n).apply(P - centre) + centre
    return back


def counted_with_centres(V0, T0, V, T, origin, n, gap, samples, eps=1e-9, removed=0):
    """The piece count with the quadrilaterals' centres: each centre turns a two-triangle
    quadrilateral into four, so 2 more triangles than expected_count per centre (less
    `removed`); the centres where check_centres wants them. Returns how many."""
    first = centres_from(V, V0, origin, n, gap, samples)
    assert len(T) == expected_count(V0, T0, origin, n, gap, samples, eps) - removed + 2 * (
        len(V) - first)
    check_centres(V, T, first, 1e-9 * max(1.0, np.abs(V).max()))
    return len(V) - first


@pytest.mark.parametrize("samples", [1, 7, 64, 512, 4096])
def test_blob_pieces_closed_and_counted(samples):
    V0, T0 = BLOB
    n = np.array([0.3, -0.2, 1.0])
    n /= np.linalg.norm(n)
    origin, gap = -0.55 * n, 1.1
    V, T = twisted(V0, T0, origin, n, gap, 2.0, samples)
    assert_closed_manifold(V, T, min_area=0.0)
    centres = counted_with_centres(V0, T0, V, T, origin, n, gap, samples)
    # the vertices: the input's, one per (edge, plane crossed) and the centres, nothing else
    E = np.unique(np.sort(np.r_[T0[:, [0, 1]], T0[:, [1, 2]], T0[:, [2, 0]]], axis=1), axis=0)
    level = ((V0 - origin) @ n) * samples / gap
    lo, hi = np.sort(level[E], axis=1).T
    crossings = np.maximum(np.minimum(np.ceil(hi) - 1, samples) - np.maximum(np.floor(lo) + 1, 0)
                           + 1, 0).sum()
    assert len(V) == len(V0) + crossings + centres


@pytest.mark.parametrize("samples", [3, 16, 100])
def test_section_at_every_plane_is_the_input_section_turned(samples):
    """On plane j the result's vertices turned back by -angle * j / samples are exactly the
    input's edge crossings there (both ways, 1e-12)."""
    V0, T0 = BLOB
    n = np.array([1.0, 0.2, -0.1])
    n /= np.linalg.norm(n)
    origin, gap, angle = -0.6 * n, 1.3, 2.5
    V, _ = twisted(V0, T0, origin, n, gap, angle, samples)
    s = (V - origin) @ n
    for j in range(samples + 1):
        level = gap * j / samples
        on = np.abs(s - level) < 1e-12
        back = Rotation.from_rotvec(-angle * j / samples * n).apply(V[on])
        p, q = section_segments(V0, T0, origin, n, level)
        assert distance_to_segments(back, p, q).max() < 1e-12
        assert cKDTree(back).query(np.r_[p, q])[0].max() < 1e-12


@settings(max_examples=40, deadline=None)
@given(tilt=st.tuples(st.floats(-1, 1), st.floats(-1, 1)), start=st.floats(-0.9, 0.3),
       part=st.floats(0.02, 1.0), angle=st.floats(-7, 7), samples=st.integers(1, 300))
def test_twisted_blob_closed_counted_and_volume_kept(tilt, start, part, angle, samples):
    """Closed 2-manifold and the piece count for any planes; the volume of the twisted
    convex blob equals the input's up to the flat facets between rings turned by
    delta = angle / samples, over the band's area (2 pi gap on the unit sphere): each facet
    sags off the twisted surface by at most r delta^2 / 8 (r = 1), and each quadrilateral
    between two rings, at most w wide (the blob's longest edge), is twisted out of its plane
    by w delta, so either diagonal cuts at most w delta / 12 off its area. Measured over
    300 random cases: at most 0.30 of this bound."""
    n = np.array([tilt[0], tilt[1], 1.0])
    n /= np.linalg.norm(n)
    V0, T0 = BLOB
    origin, gap = start * n, part * (0.9 - start)   # both planes cross the unit sphere
    V, T = twisted(V0, T0, origin, n, gap, angle, samples)
    assert_closed_manifold(V, T, min_area=0.0)
    counted_with_centres(V0, T0, V, T, origin, n, gap, samples)
    delta = abs(angle) / samples
    band = 2 * np.pi * gap                      # area of the band, within a unit sphere
    w = np.linalg.norm(V0[T0] - V0[np.roll(T0, 1, axis=1)], axis=2).max()
    assert abs(volume(V, T) - volume(V0, T0)) <= band * (delta ** 2 / 8 + w * delta / 12) + 1e-12


def needle_tetrahedron():
    """A regular tetrahedron A B C D (outward) whose face A B C is split at M, 1e-6 inside
    the face from the midpoint of A B: the facet A B M is a needle, 2e-6 rad wide at A."""
    A, B, C, D = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
    inward = (A + B) / 2 - C
    M = (A + B) / 2 - 1e-6 * inward / np.linalg.norm(inward)
    V0 = np.array([A, B, C, D, M])
    T0 = np.array([[0, 1, 4], [1, 2, 4], [2, 0, 4], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
    if volume(V0, T0) < 0:
        T0 = T0[:, ::-1]
    return V0, T0


def test_needle_tip_cut_points_merge_and_stay_closed():
    """Plane 5e-9 past the needle's tip A: the cut points on A B and A M lie about 1e-14
    apart (one float32 point), closer than eps = 1e-9, and become one (the two facets on
    that tiny edge vanish: two triangles fewer than the piece count); those on A C and A D
    stay apart. Closed 2-manifold, the volume kept up to the twist's sampling."""
    V0, T0 = needle_tetrahedron()
    A = V0[0]
    n = -A / np.linalg.norm(A)                    # from the tip toward the centre
    origin, gap, eps = A + 5e-9 * n, 1.0, 1e-9
    V, T = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, 0.3), 4, eps=eps)
    assert_closed_manifold(V, T, min_area=0.0)
    counted_with_centres(V0, T0, V, T, origin, n, gap, 4, eps, removed=2)
    on = np.abs((V - origin) @ n) < 1e-12
    assert on.sum() == 3
    assert cKDTree(V[on]).query(V[on], 2)[0][:, 1].min() > eps


def test_non_finite_vertex_is_refused_naming_base():
    """A NaN vertex would make the plane counts meaningless (and the arrays unbounded)."""
    V0, T0 = BLOB
    V0 = V0.copy()
    V0[5, 1] = np.nan
    with pytest.raises(DeformError) as err:
        twisted(V0, T0, np.array([0, 0, -0.5]), np.array([0, 0, 1.0]), 1.0, 1.0, 8)
    assert err.value.prop == "Base" and "Base" in str(err.value)


def loose_triangles():
    """Separate triangles (levels s of their corners a, b, c along x, planes at s = 0..4),
    each crossing none, one or several sample planes in every way the cut tells apart:
    a alone below the plane, c alone above it, b on it, b and c on one level (a and b
    too), two planes, and one through all five (so both end planes cross the mesh). Each
    lies in its own tilted plane, away from the others."""
    levels = [(1.2, 1.8, 1.5), (2.5, 3.4, 3.6), (0.2, 0.6, 1.5), (1.5, 2.0, 2.5),
              (0.5, 1.5, 1.5), (0.4, 0.4, 1.7), (0.5, 2.5, 1.7), (-0.5, 4.5, 2.2),
              (3.6, 2.5, 3.4), (2.0, 2.5, 1.5)]
    V0 = []
    for i, (x0, x1, x2) in enumerate(levels):
        y, z = 3.0 * i, 1.0 + 0.3 * i
        V0 += [[x0, y, z], [x1, y + 1.0, z + 0.2 * x1], [x2, y + 0.3, z + 1.1 - 0.1 * x2]]
    return np.array(V0), np.arange(3 * len(levels)).reshape(-1, 3)


def triangle_normals(V, T):
    return np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])


@pytest.mark.parametrize("flipped", [False, True])
def test_triangles_crossing_none_one_or_several_planes(flipped):
    """Each piece lies in one slab (no plane strictly between its corners' levels), in the
    plane of one input triangle and facing its way; the pieces of a triangle add up to
    its area, and their count is 2k + 1 for k planes crossed (2k with b on a plane). Twisted
    by 1.3 rad, every vertex turned back by -1.3 clip(s / gap) about the axis (scipy) is
    where the untwisted cut put it, and the pieces are the untwisted ones but for the
    quadrilaterals that got a centre (four triangles about it, check_centres)."""
    V0, T0 = loose_triangles()
    if flipped:                                   # the other orientation of every triangle
        T0 = T0[:, ::-1].copy()
    n, origin, gap, samples = np.array([1.0, 0, 0]), np.zeros(3), 4.0, 4
    normals = triangle_normals(V0, T0)
    unit_normals = normals / np.linalg.norm(normals, axis=1)[:, None]

    def parents(V, T):                            # each piece's input triangle, checked
        level = V[:, 0] * samples / gap
        lo, hi = level[T].min(axis=1), level[T].max(axis=1)
        assert (np.floor(lo + 1e-12) + 1 >= np.ceil(hi - 1e-12)).all()
        off = np.abs(np.einsum("pk,tk->pt", V[T].mean(axis=1), unit_normals)
                     - np.einsum("tk,tk->t", V0[T0[:, 0]], unit_normals))
        parent = off.argmin(axis=1)
        assert off.min(axis=1).max() < 1e-12
        piece_normals = triangle_normals(V, T)
        assert (np.einsum("pk,pk->p", piece_normals, normals[parent]) > 0).all()
        area = np.bincount(parent, np.linalg.norm(piece_normals, axis=1) / 2, len(T0))
        np.testing.assert_allclose(area, np.linalg.norm(normals, axis=1) / 2, rtol=1e-12)
        return parent

    V, T = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, 0.0), samples)
    assert len(V) == centres_from(V, V0, origin, n, gap, samples)     # flat: no centre
    assert len(T) == expected_count(V0, T0, origin, n, gap, samples, 1e-9)
    parent = parents(V, T)
    top, bottom = V0[T0, 0].max(axis=1), V0[T0, 0].min(axis=1)    # planes strictly between
    crossed = np.maximum(np.minimum(np.ceil(top) - 1, samples) - np.maximum(np.floor(bottom) + 1, 0)
                         + 1, 0)
    b_on = np.array([np.sort(x)[1] % 1 == 0 and 0 <= np.sort(x)[1] <= samples
                     and np.sort(x)[0] < np.sort(x)[1] < np.sort(x)[2] for x in V0[T0, 0]])
    pieces = np.bincount(parent, minlength=len(T0))
    np.testing.assert_array_equal(pieces, np.where(crossed == 0, 1, 2 * crossed + 1 - b_on))
    angle = 1.3
    Vt, Tt = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, angle), samples)
    back = untwist(origin, n, gap, angle)(Vt)
    np.testing.assert_allclose(back[:len(V)], V, atol=1e-12)
    centres = counted_with_centres(V0, T0, Vt, Tt, origin, n, gap, samples)
    assert centres > 0
    plain = Tt[(Tt < len(V)).all(axis=1)]
    assert set(map(tuple, plain.tolist())) <= set(map(tuple, T.tolist()))


def test_a_mesh_of_many_blocks_is_cut_on_every_core_as_on_one(monkeypatch):
    """slab_cut's vertex pass and triangle scan split a large mesh (over 8 blocks of
    vertices) between two threads: the same vertices and triangles as one thread gives, a
    closed 2-manifold with the oracle's piece count and the input's volume to the
    flat-facet bound of the test above."""
    from freecad_deform.geometry import blocks
    V0, T0 = BIG
    assert len(V0) > 8 * blocks.BLOCK
    n = np.array([0.2, -0.3, 1.0])
    n /= np.linalg.norm(n)
    origin, gap, angle, samples = -0.5 * n, 1.2, 2.0, 16
    monkeypatch.setattr(blocks, "_workers", lambda: 2)     # (split on any machine)
    V, T = twisted(V0, T0, origin, n, gap, angle, samples)
    monkeypatch.setattr(blocks, "_workers", lambda: 1)
    V1, T1 = twisted(V0, T0, origin, n, gap, angle, samples)
    np.testing.assert_array_equal(V, V1)
    np.testing.assert_array_equal(T, T1)
    assert_closed_manifold(V, T, min_area=0.0)
    counted_with_centres(V0, T0, V, T, origin, n, gap, samples)
    delta = angle / samples
    w = np.linalg.norm(V0[T0] - V0[np.roll(T0, 1, axis=1)], axis=2).max()
    assert abs(volume(V, T) - volume(V0, T0)) <= 2 * np.pi * gap * (delta ** 2 / 8
                                                                     + w * delta / 12)


def test_uncut_rows_kept_and_pieces_split_along_the_shorter_diagonal():
    """A triangle crossing no plane keeps its row; each one crossing one plane (no corner
    on it) gives its lone corner's triangle and a quadrilateral on the other side: four
    triangles about a centre where the twist takes it out of its plane, else two; not
    twisted, split along the shorter of its two diagonals, whichever side of the plane
    the quadrilateral lies on."""
    rng = np.random.default_rng(7)
    n, origin, gap, samples = np.array([1.0, 0, 0]), np.zeros(3), 3.0, 3
    V0, T0 = [], []
    for k in range(300):                  # loose triangles, 3 apart in y
        P = rng.uniform(-1, 1, (3, 3)) + [0, 3.0 * k, 0]
        P[:, 0] = rng.uniform(-0.5, 3.5, 3)
        V0.extend(P)
        T0.append([3 * k, 3 * k + 1, 3 * k + 2])
    V0, T0 = np.array(V0), np.array(T0)
    V, flat = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, 0.0), samples)
    cells = np.floor(V0[T0, 0] * samples / gap)
    uncut = cells.min(axis=1) == cells.max(axis=1)
    one = (cells.max(axis=1) - cells.min(axis=1) == 1) & (cells.max(axis=1) <= samples) & (
        cells.max(axis=1) >= 0)
    checked = [0, 0]
    for angle in (0.9, 0.0):                  # twisted (most get a centre), then flat
        _, T = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, angle,
                                                                [0, 450.0, 0]), samples)
        np.testing.assert_array_equal(T[:len(T0)][uncut], T0[uncut])
        parent = np.full(max(len(V), T.max() + 1), -1)
        parent[:len(V0)] = np.arange(len(V0)) // 3
        while (parent[T] < 0).any():          # a new vertex belongs to its piece's triangle
            for x in T:
                known = parent[x][parent[x] >= 0]
                if len(known):
                    parent[x[parent[x] < 0]] = known[0]
        of = parent[T].max(axis=1)
        for t in np.flatnonzero(one & ~uncut):
            mine = [set(x) for x in T[of == t]]
            c = cells[t]
            lone = T0[t][np.flatnonzero(c != np.median(c))[0]]  # the corner alone on its side
            quad = [x for x in mine if lone not in x]
            centre = set().union(*mine) - set(range(len(V)))
            if centre:                        # four triangles about the one new vertex
                assert len(mine) == 5 and len(quad) == 4 and len(centre) == 1
                assert all(centre <= x for x in quad)
                checked[1] += 1
                continue
            assert len(mine) == 3 and len(quad) == 2
            diagonal = quad[0] & quad[1]
            across = (quad[0] | quad[1]) - diagonal
            assert len(diagonal) == 2 and len(across) == 2
            if angle == 0.0:                  # (flat to 1e-9 when twisted: any diagonal)
                length = [np.linalg.norm(np.subtract(*V[sorted(e)])) for e in (diagonal,
                                                                                across)]
                assert length[0] <= length[1]
                checked[0] += 1
    assert min(checked) > 40


@settings(max_examples=60, deadline=None)
@given(count=st.integers(0, 3000), bound=st.sampled_from([2, 50, 10 ** 6, 10 ** 12, 2 ** 62]),
       stride=st.sampled_from([1, 2 ** 20, 2 ** 40]), seed=st.integers(0, 2 ** 32 - 1))
def test_edge_keys_numbered_as_np_unique_numbers_them(count, bound, stride, seed):
    """slab_cut numbers the edges of cut triangles by a hash table (_numbered): the
    distinct keys are np.unique's, each once, and every key gets the number of its own
    value; also for keys that share slots (strided keys, few slots)."""
    from freecad_deform.geometry.mesh.sweep import _numbered
    keys = np.random.default_rng(seed).integers(0, bound, count) // stride * stride
    at, number = _numbered(keys)
    distinct = keys[at]
    np.testing.assert_array_equal(np.sort(distinct), np.unique(keys))
    np.testing.assert_array_equal(distinct[number], keys)


@pytest.mark.parametrize("eps", [0.6, 0.7, 0.8])
def test_cut_points_merged_about_a_vertex_leave_no_fin(eps):
    """A tolerance about a fifth of the plane spacing (3.6): on this scaled blob every cut
    point about one vertex near Plane merges into one, and two pieces came out as the same
    triangle both ways round (a fin: two directed edges used twice). Each directed edge
    once and its reverse present; the vertex left without a piece is the only one unused,
    and the volume changes by at most eps times the surface's area (no point moves farther
    than eps: a snap along the normal, a merge within a plane)."""
    V0, T0 = blob(200, seed=0)
    V0 = V0 * [9.506504706260397, 23.03312725742691, 13.945191067628295]
    n = np.array([0, 1.0, 0])
    origin, gap = -13.921508532552478 * n, 36.23920459772926
    V, T = map_between(V0, T0, origin, n, gap, twist_motion(origin, n, gap, 0.0), 10, eps)
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    directed, count = np.unique(a * len(V) + b, return_counts=True)
    assert count.max() == 1
    assert np.isin(b * len(V) + a, directed).all()
    assert len(np.setdiff1d(np.arange(len(V)), T)) <= 1
    area = np.linalg.norm(triangle_normals(V0, T0), axis=1).sum() / 2
    assert abs(volume(V, T) - volume(V0, T0)) <= eps * area


@pytest.mark.parametrize("levels", [(0, 20), (0, 5, 10, 15, 20)])
@pytest.mark.parametrize("start, gap", [(4.0, 2.0), (3.0, 10.0)])
def test_coarse_box_twisted_keeps_its_volume_to_the_sag_of_its_facets(levels, start, gap):
    """A 20 mm box with walls of 2 to 8 tall triangles a side, twisted 30 deg about its
    axis, Samples 16: its volume changes by at most the sag of flat facets between rings
    turned by delta, r delta^2 / 8 over the twisted walls (perimeter x gap), r the
    section's corner radius (the real-parts oracle's bound). Splitting each twisted
    quadrilateral along the diagonal shorter after the turn put every facet on one side
    of the twisted surface: +4.2 to +23.8 mm^3 against bounds of 0.30 and 1.51."""
    from .test_mesh_sweep import SQUARE, prism
    V0, T0 = prism(10 * SQUARE, levels=levels)
    n = np.array([0, 0, 1.0])
    origin, angle, samples = start * n, np.radians(30), 16
    V, T = map_between(V0, T0, origin, n, gap,
                       twist_motion(origin, n, gap, angle, np.zeros(3), n), samples)
    assert_closed_manifold(V, T)
    sag = 80 * gap * 10 * np.sqrt(2) * (angle / samples) ** 2 / 8
    assert abs(volume(V, T) - volume(V0, T0)) <= sag



def big_twist(V0, T0):
    n = np.array([0.2, -0.3, 1.0])
    n /= np.linalg.norm(n)
    return twisted(V0, T0, -0.5 * n, n, 1.2, 2.0, 16)


def test_int32_triangles_cut_as_int64_ones(monkeypatch):
    """slab_cut numbers edges by keys up to N^2, which int32 triangles overflowed (a mesh
    with 4x the vertices, open, no error): it takes them as int64."""
    from freecad_deform.geometry import blocks
    from freecad_deform.geometry.mesh.sweep import slab_cut, twist_motion as tm
    monkeypatch.setattr(blocks, "_workers", lambda: 2)
    V0, T0 = BIG
    n = np.array([0.0, 0.0, 1.0])
    args = (V0, -0.5 * n, n, 1.2, 16, 1e-9, tm(-0.5 * n, n, 1.2, 2.0))
    V, T = slab_cut(args[0], T0.astype(np.int32), *args[1:])
    V1, T1 = slab_cut(args[0], T0.astype(np.int64), *args[1:])
    np.testing.assert_array_equal(V, V1)
    np.testing.assert_array_equal(T, T1)
    assert_closed_manifold(V, T, min_area=0.0)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="os.fork is POSIX")
def test_a_forked_child_cuts_a_large_mesh(monkeypatch):
    """After a cut on two threads, a child made by os.fork (multiprocessing's default on
    Linux before Python 3.14) has the thread pool but none of its threads: its cut waited
    for ever. The child cuts within 60 s and gets the parent's result."""
    from freecad_deform.geometry import blocks
    monkeypatch.setattr(blocks, "_workers", lambda: 2)
    V0, T0 = BIG
    V, T = big_twist(V0, T0)
    pid = os.fork()
    if pid == 0:                              # the child: exit 0 when its cut is the same
        signal.alarm(60)
        try:
            Vc, Tc = big_twist(V0, T0)
            os._exit(0 if np.array_equal(Vc, V) and np.array_equal(Tc, T) else 1)
        finally:
            os._exit(2)
    _, status = os.waitpid(pid, 0)
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status


def test_worker_threads_run_under_the_callers_error_state(monkeypatch):
    """Under np.errstate(over="raise"), a vertex whose distance overflows raised in the
    range the caller's thread cut and only warned in a worker's: now it raises in both."""
    from freecad_deform.geometry import blocks
    monkeypatch.setattr(blocks, "_workers", lambda: 2)
    V0, T0 = BIG
    for row in (10, len(V0) - 10):            # in the worker's range, in the caller's
        V = V0 * 1e300
        V[row] = [1.7e308, 1.7e308, 1.7e308]
        n = np.array([0.6, 0.0, 0.8])
        with np.errstate(over="raise"), pytest.raises(FloatingPointError):
            twisted(V, T0, np.zeros(3), n, 1e300, 1.0, 4)


def test_an_error_in_one_range_waits_for_the_others(monkeypatch):
    """in_parallel raises the caller's range's error only once the worker's range has
    ended, so no worker is left running into the next call."""
    import time
    from freecad_deform.geometry import blocks
    monkeypatch.setattr(blocks, "_workers", lambda: 2)
    ended = []

    def fn(start, stop):
        if start == 0:                        # the worker's range, slow
            time.sleep(0.3)
            ended.append(start)
            return start
        raise ValueError("the caller's range")

    with pytest.raises(ValueError):
        blocks.in_parallel(fn, 8 * blocks.BLOCK)
    assert ended == [0]


def rod(r, length, k):
    """A closed k-sided rod along z: its sides two long triangles each, end to end, and a
    fan at each end."""
    a = 2 * np.pi * np.arange(k) / k
    ring = np.c_[r * np.cos(a), r * np.sin(a)]
    V = np.r_[np.c_[ring, np.zeros(k)], np.c_[ring, np.full(k, length)], [[0, 0, 0],
                                                                          [0, 0, length]]]
    i = np.arange(k)
    j = (i + 1) % k
    T = np.r_[np.c_[i, j, k + j], np.c_[i, k + j, k + i], np.c_[np.full(k, 2 * k), j, i],
              np.c_[np.full(k, 2 * k + 1), k + i, k + j]]
    return V, T if volume(V, T) > 0 else T[:, ::-1]


def test_long_facets_twisted_across_keep_the_volume_to_second_order():
    """A 24-sided rod 2.54 x 61 twisted 30 deg over 0.508 across it (Plane across y, the
    axis along y through its middle): its sides are long facets, and each quadrilateral a
    facet leaves between two planes is twisted out of its plane. Split along a diagonal,
    they cut the same side every slab: -3.8 / -1.0 / -0.25 % of the slab at Samples 16 /
    64 / 256 (first order). With a centre each: +0.30 / +0.019 / +0.0012 %."""
    V0, T0 = rod(2.54, 60.96, 24)
    n, origin, gap = np.array([0, 1.0, 0]), np.zeros(3), 0.508
    slab = 2 * 2.54 * 60.96 * gap
    change = []
    for samples in (16, 64):
        V, T = twisted(V0, T0, origin, n, gap, np.radians(30), samples, [0, 0, 30.48])
        assert_closed_manifold(V, T, min_area=0.0)
        counted_with_centres(V0, T0, V, T, origin, n, gap, samples)
        change.append((volume(V, T) - volume(V0, T0)) / slab)
    assert abs(change[0]) < 4e-3
    assert abs(change[1]) < abs(change[0]) / 10          # second order: 1/16


def test_long_facets_tapered_across_keep_the_exact_volume():
    """The same rod tapered to Scale 0.5 across it (ops/taper.mesh: slab_cut, then the taper
    map at every vertex): a quadrilateral with two corners on each of its planes stays flat
    (the taper scales each plane's section about the axis, keeping its directions), so the
    diagonal splits lose nothing to first order, unlike the twist's. Against the image's
    exact volume, the integral over x of the section's chord x length x k(x)^2, per piece
    between the polygon's corners and the planes by 3-point Gauss-Legendre (exact: a cubic):
    -1.4e-5 / -8.9e-7 of the slab at Samples 16 / 64 (-7.3e-5 / -9.1e-6 over a gap of the
    whole width)."""
    r, length, k = 2.54, 60.96, 24
    V0, T0 = rod(r, length, k)
    ring = r * np.c_[np.cos(2 * np.pi * np.arange(k) / k), np.sin(2 * np.pi * np.arange(k) / k)]
    nodes, weights = np.polynomial.legendre.leggauss(3)

    def chord(x):                         # the polygon's width in y at x
        y = [p[1] + (x - p[0]) / (q[0] - p[0]) * (q[1] - p[1])
             for p, q in zip(ring, np.roll(ring, -1, axis=0)) if p[0] != q[0]]
        inside = [(x - p[0]) * (x - q[0]) <= 0 for p, q in zip(ring, np.roll(ring, -1, axis=0))
                  if p[0] != q[0]]
        ys = np.where(inside, y, np.nan)
        return np.nanmax(ys, axis=0) - np.nanmin(ys, axis=0)

    for lo, gap, bounds in ((-1.27, 2.54, (2e-5, 1.5e-6)), (-2.54, 5.08, (1e-4, 1.5e-5))):
        origin, n = np.array([lo, 0, 0.0]), np.array([1.0, 0, 0])
        factor = (lambda x: 1 - 0.5 * np.clip((x - lo) / gap, 0, 1))
        cuts = np.unique(np.r_[ring[:, 0], lo, lo + gap])
        cuts = cuts[(cuts >= -r) & (cuts <= r)]
        a, b = cuts[:-1, None], cuts[1:, None]
        x = 0.5 * (a + b) + 0.5 * (b - a) * nodes
        w = 0.5 * (b - a) * weights
        exact = float((w * chord(x) * length * factor(x) ** 2).sum())
        slab = float((w * chord(x) * length * ((x >= lo) & (x <= lo + gap))).sum())
        smap = space_map.taper_map(origin, n, gap, 0.5, np.array([0, 0, length / 2]))
        for samples, bound in zip((16, 64), bounds):
            W, T = slab_cut(V0, T0, origin, n, gap, samples, 1e-9)
            W = smap(W)
            assert_closed_manifold(W, T, min_area=0.0)
            assert abs(volume(W, T) - exact) < bound * slab
