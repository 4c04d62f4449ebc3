"""Mesh Twist's crossing search (geometry/mesh/sweep.map_following) on a Base that already
crosses itself (stop 20; found on trimesh's counter, see /work/notes/mesh20.md). Where a
triangle's bound on how far its flat pieces stray from the twist exceeds 2e-3 of the
diagonal, the result is searched for facets that cross. At stop 19 that search covered every
piece of the region and, when it found a crossing, the Base's region too; a crossing the Base
already had made it accept the result whatever else crossed. The counter (a flange whose Base
crosses itself) twisted 30 deg at 50 % took 7.7-10.8 s instead of 0.12 s, and a result with
new crossings beside a Base crossing was Up-to-date. Now only the pieces of the triangles
that stray are searched, and a crossing counts unless its two facets are pieces of two
triangles that cross in the Base.

Oracles, independent of the code: the exact crossing test of test_unseen_mesh_fixes19
(rational arithmetic over every pair of facets sharing no vertex), the facets' distance from
the twist axis (which the twist keeps) and the mesh's connected pieces.

Below that bound the pieces beside a needle facet (a crack where a corner lies on another
facet's edge, filled by a facet of no width) are searched too: there the facets lie against
each other, and any stray crosses them (trimesh's 7_8ths_cube twisted at Samples 256).
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.mesh import intersect  # noqa: E402

from .oracles.mesh import arrays  # noqa: E402
from .test_unseen_mesh_fixes19 import (TILTED, MeshDocument,  # noqa: E402
                                        assert_refused_or_clean, crossing_pairs, prism_mesh)

V = App.Vector


def square(x, z, half):
    """The (x, z) corners of a square section, for prism_mesh."""
    return [(x - half, z - half), (x + half, z - half), (x + half, z + half),
            (x - half, z + half)]


def crossing_boxes(x, z, half, shift, low, high):
    """Two boxes along y (sections `square(x, z, half)` and the same moved by `shift` in x
    and z, between y = low and high, the second's y range moved by half its length) that
    pass through each other: a Base crossing itself."""
    first = prism_mesh(square(x, z, half), (low, high))
    second = prism_mesh(square(x + shift[0], z + shift[1], half),
                        (low + 0.125 * (high - low), high + 0.125 * (high - low)))
    return first, second


def joined(*meshes):
    out = Mesh.Mesh()
    for m in meshes:
        out.addMesh(m)
    return out


def pieces(X, T):
    """Connected piece of each facet (by shared vertices)."""
    e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]]])
    _, label = connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])),
                                               shape=(len(X), len(X))), directed=False)
    return label[T[:, 0]]


class TestCrossingAwayFromTheStray(MeshDocument):
    """A coarse box 3 from the y axis (facets from y = -0.5 to 1.5, none between) twisted
    90 deg about it between y = 0 and 1, Samples 16: its facets' bound is 5.4e-3 of the
    diagonal, so the result is searched; it has no crossing of its own. Beside the axis
    two small boxes pass through each other (12 crossing pairs in the Base; their bound
    4.3e-4 of the diagonal). At stop 19 the search took every piece of the region, found
    the small boxes' crossings in the result and searched the Base's region for them:
    15,180 pairs tested, 8,614 with a facet of the small boxes. Their pieces follow the
    twist too closely to cross anything new; the search need not look at them."""

    def test_the_small_boxes_not_searched(self, monkeypatch):
        far = prism_mesh(square(3.25, 0.0, 0.25), (-0.5, 1.5))
        self.base.Mesh = joined(far, *crossing_boxes(0.0, 0.0, 0.025, (0.02, 0.02), 0.3, 0.7))
        X0, T0 = arrays(self.base.Mesh)
        near = np.hypot(*X0[T0].mean(axis=1)[:, [0, 2]].T) < 1.0
        base_pairs = crossing_pairs(X0, T0)
        assert base_pairs and all(near[a] and near[b] for a, b in base_pairs)

        searched = []
        crossing = intersect.crossing

        def counted(X, T, pairs, touch=False):   # each pair's two facets' distances from
            c = np.asarray(X)[np.asarray(T)[pairs]].mean(axis=2)   # the origin, Plane's
            searched.append(np.linalg.norm(c, axis=2))   # point (the same in any frame
            return crossing(X, T, pairs, touch)          # the search turns the mesh to)

        monkeypatch.setattr(intersect, "crossing", counted)
        n = V(0, 1, 0)
        obj = fd.make_twist(self.base, (V(0, 0, 0), n), (V(0, 1, 0), n), 90.0,
                            (V(0, 0, 0), n))
        self.doc.recompute()
        monkeypatch.undo()
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        X, T = arrays(obj.Mesh)
        near = np.hypot(*X[T].mean(axis=1)[:, [0, 2]].T) < 1.0   # (the twist keeps it)
        assert all(near[a] and near[b] for a, b in crossing_pairs(X, T))
        tested = np.concatenate(searched) if searched else np.zeros((0, 2))
        assert len(tested), "the far box's pieces were not searched"
        small = tested < 1.5                     # (the small boxes lie within 0.8 of it,
        assert not small.any(), (                # the far box's facets 3 or more away)
            f"{int(small.any(axis=1).sum())} of {len(tested)} pairs searched hold a facet "
            f"of the small boxes")


class TestNewCrossingsBesideABaseCrossing(MeshDocument):
    """test_unseen_mesh_fixes19's tilted prism twisted 30 deg about a z axis 4200 away
    between z = 0.186 and 0.220 crosses itself at Samples 16 (refused there naming
    Samples). With two small boxes passing through each other inside the twisted slab
    beside it (14 crossing pairs in the Base), the stop 19 search saw that the Base crosses
    too and took the result as it was: Up-to-date, 35 crossing pairs with a prism facet."""

    def test_refused_or_the_prism_clean(self):
        boxes = crossing_boxes(0.3, 0.203, 0.01, (0.008, 0.004), -0.1, 0.1)
        self.base.Mesh = joined(prism_mesh(*TILTED), *boxes)
        X0, T0 = arrays(self.base.Mesh)
        piece = pieces(X0, T0)
        prism = piece == piece[0]
        base_pairs = crossing_pairs(X0, T0)
        assert base_pairs and not any(prism[a] or prism[b] for a, b in base_pairs)
        n = V(0, 0, 1)
        obj = fd.make_twist(self.base, (V(0, 0, 0.186), n), (V(0, 0, 0.220), n), 30.0,
                            (V(-3507.7, 2311.7, 0.186), n))
        obj.Samples = 16
        self.doc.recompute()
        if "Invalid" in obj.State:
            assert "Samples" in obj.getStatusString()
            return
        X, T = arrays(obj.Mesh)
        piece = pieces(X, T)
        prism = piece == np.bincount(piece).argmax()      # (the prism has the most facets)
        bad = [(a, b) for a, b in crossing_pairs(X, T) if prism[a] or prism[b]]
        assert not bad, f"{len(bad)} crossing pairs with a facet of the prism, Up-to-date"


# a 40 mm cube without the octant x, y, z > 0, its faces triangulated end to end as CAD
# exporters write them: the top face's diagonal from (20, -20, 20) to (-20, 20, 20) passes
# the notch's corner (0, 0, 20), whose crack a needle facet (5, 2, 8) fills; the corner lies
# 1e-5 off that diagonal, as float noise puts it
NOTCHED = ([(-20, -20, 20), (-20, -20, -20), (-20, 20, 20), (-20, 20, -20), (0, 0, 0),
            (-1e-5, 0, 20), (0, 20, 20), (0, 20, 0), (20, -20, 20), (20, 0, 0), (20, 0, 20),
            (20, -20, -20), (20, 20, -20), (20, 20, 0)],
           [(1, 12, 11), (12, 1, 3), (12, 7, 13), (6, 3, 2), (3, 7, 12), (7, 3, 6),
            (13, 11, 12), (8, 9, 10), (9, 11, 13), (11, 9, 8), (0, 11, 8), (11, 0, 1),
            (2, 1, 0), (1, 2, 3), (2, 5, 6), (8, 2, 0), (5, 8, 10), (5, 2, 8), (5, 7, 6),
            (7, 5, 4), (13, 4, 9), (4, 13, 7), (9, 5, 10), (5, 9, 4)])


class TestNeedleAtACrack(MeshDocument):
    """The notched cube twisted 5 deg about its diagonal between 60 % of the box and a
    tenth of its length beyond, Samples 16: the largest bound is 1.5e-3 of the diagonal,
    under the 2e-3 that starts the search, and stop 19 left it Up-to-date with 9 crossing
    pairs (the top facet's pieces through the notch's walls at the crack)."""

    def test_refused_or_clean(self):
        P, T = NOTCHED
        self.base.Mesh = Mesh.Mesh([[V(*P[i]) for i in t] for t in T])
        assert not crossing_pairs(*arrays(self.base.Mesh))
        d = np.ones(3) / np.sqrt(3)
        origin = np.full(3, 4.0)                          # 60 % of the box
        far = origin + 10 / np.sqrt(3) * d                # a tenth of its extent along d
        n = V(*d)
        obj = fd.make_twist(self.base, (V(*origin), n), (V(*far), n), 5.0, (V(*origin), n))
        self.doc.recompute()
        assert_refused_or_clean(obj, "Samples")
