"""DimensionDrive refuses a result that cuts through itself (issue 17): a bore with a
shaft in it (two shells of one mesh) shrunk onto the shaft, and the crossing test itself
against a brute-force oracle written here (every pair of triangles, edge through triangle
by the sign of volumes)."""
import numpy as np
import pytest

from freecad_deform.geometry.mesh import dimension_drive as dd
from freecad_deform.geometry.errors import DeformError
from freecad_deform.geometry.mesh.intersect import new_intersections

from .block_mesh import block_with_hole


def shaft(radius=6.0, centre=(50.0, 30.0), z=(-4.0, 36.0), n=32, rows=8):
    """Closed outward mesh of a capped cylinder, its own vertices; its rows are off the
    block's top and bottom (the crossing test does not count edges that only touch)."""
    a = 2 * np.pi * (np.arange(n) + 0.5) / n
    ring = np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])
    levels = np.linspace(*z, rows + 1)
    V = np.concatenate([np.column_stack([ring, np.full(n, h)]) for h in levels]
                       + [[[*centre, z[0]], [*centre, z[1]]]])
    T = []
    for k in range(rows):
        for i in range(n):
            j = (i + 1) % n
            a0, a1, b0, b1 = k * n + i, k * n + j, (k + 1) * n + i, (k + 1) * n + j
            T += [[a0, a1, b1], [a0, b1, b0]]
    bottom, top = len(V) - 2, len(V) - 1
    for i in range(n):
        j = (i + 1) % n
        T += [[bottom, j, i], [top, rows * n + i, rows * n + j]]
    return V, np.array(T)


def brute_crossings(X, T):
    """Pairs of triangles sharing no vertex where an edge of one passes through the other:
    its ends on opposite sides of the other's plane, and the crossing inside it (the three
    signed volumes with its edges of one sign)."""
    count = 0
    tri = X[T]
    for i in range(len(T)):
        for j in range(i + 1, len(T)):
            if set(T[i]) & set(T[j]):
                continue
            for a, b in ((tri[i], tri[j]), (tri[j], tri[i])):
                hit = False
                for k in range(3):
                    p, q = a[k], a[(k + 1) % 3]
                    sp = np.dot(np.cross(b[1] - b[0], b[2] - b[0]), p - b[0])
                    sq = np.dot(np.cross(b[1] - b[0], b[2] - b[0]), q - b[0])
                    if sp * sq >= 0:
                        continue
                    w = [np.dot(np.cross(b[m] - p, b[(m + 1) % 3] - p), q - p) for m in range(3)]
                    if all(x > 0 for x in w) or all(x < 0 for x in w):
                        hit = True
                if hit:
                    count += 1
                    break
    return count


def test_crossing_counts_match_brute_force():
    V, T = shaft(n=8, rows=2)
    W, U = shaft(radius=3.0, centre=(53.0, 30.0), n=8, rows=2)   # overlaps the first
    X = np.concatenate([V, W])
    T2 = np.concatenate([T, U + len(V)])
    moved = np.zeros(len(T2), bool)
    moved[len(T):] = True
    far = X.copy()
    far[len(V):, 0] += 100.0                                       # apart: no crossing
    assert new_intersections(far, X, T2, moved) == brute_crossings(X, T2) > 0
    assert new_intersections(far, far, T2, moved) == 0


def test_bore_shrunk_onto_its_shaft_is_refused_with_the_clear_range():
    V, T = block_with_hole()
    S, U = shaft()
    X = np.concatenate([V, S])
    T2 = np.concatenate([T, U + len(V)])
    model = dd.DimensionModel(X, T2, np.radians(40))
    before = model.vertices.copy()
    drive = dd.drive(model, "Radius", [(58, 30, 15)], 7.0)
    dd.deformed(model, drive)                                      # clear of the shaft
    drive = dd.drive(model, "Radius", [(58, 30, 15)], 5.5)
    assert drive.reach[0] < 5.5 - 8.0                              # no triangle flips
    with pytest.raises(DeformError, match=r"cut through itself: it stays clear from 8 to "
                                          r"6\.0[0-9]*") as e:
        dd.deformed(model, drive)
    assert e.value.prop == "Target"
    assert np.array_equal(model.vertices, before)
    clear = float(str(e.value).split(" to ")[1].split(";")[0])
    # the oracle: the bore polygon's chords (radius r cos(pi/32)) reach the shaft's vertices
    # (radius 6, between the bore's) at r = 6 / cos(pi / 32); the bisection stops below it
    assert 6 / np.cos(np.pi / 32) <= clear <= 6 / np.cos(np.pi / 32) + 2.5 / 128
