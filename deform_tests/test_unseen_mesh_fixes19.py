"""Mesh Twist (and two-plane mesh Bend: the same kernel, geometry/mesh/sweep.map_between)
left facets crossing each other, Up-to-date (stop 19; found on trimesh's multibody.stl and
7_8ths_cube.stl, see /work/notes/unseen_mesh18.md and mesh19.md). Between two Samples planes
a flat facet follows the map only at its corners; where that strays far (a long facet, a
part far from the axis) the facets cross. Where a triangle's bound on that (sweep.
slab_deviation) is large the ops now search the result for crossing facets, split the
edges that stray (sweep.follow_map) when it has some and refuse, naming Samples, a result
that still crosses; a two-plane Bend that turns the far part into the near part is refused naming
Angle, as the one-plane Bend is.

Oracles, independent of the code: an exact segment-triangle test written here (float64
filter, then rational arithmetic) over every pair of facets of the stored result that share
no vertex; the closed 2-manifold check (deform_tests/oracles/mesh).
"""
from fractions import Fraction

import numpy as np

from .features import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402

import freecad_deform as fd  # noqa: E402

from .oracles.mesh import arrays, assert_closed_manifold  # noqa: E402

V = App.Vector


def _det(a, b, c):
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))


def segment_through(p, q, a, b, c):
    """The open segment p-q passes through the open triangle abc (rational arithmetic:
    p + t (q - p) = a + u (b - a) + v (c - a), 0 < t < 1, u, v > 0, u + v < 1)."""
    p, q, a, b, c = ([Fraction(float(x)) for x in y] for y in (p, q, a, b, c))
    cols = ([q[i] - p[i] for i in range(3)], [a[i] - b[i] for i in range(3)],
            [a[i] - c[i] for i in range(3)])
    rhs = [a[i] - p[i] for i in range(3)]
    det = _det(*cols)
    if det == 0:
        return False
    t = _det(rhs, cols[1], cols[2]) / det
    u = _det(cols[0], rhs, cols[2]) / det
    v = _det(cols[0], cols[1], rhs) / det
    return 0 < t < 1 and u > 0 and v > 0 and u + v < 1


def crossing_pairs(X, T):
    """Pairs of facets sharing no vertex where an edge of one passes through the other:
    every pair whose boxes overlap, in plain numpy, each hit confirmed exactly."""
    tri = X[T]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    found = []
    for i in range(len(T)):
        j = np.arange(i + 1, len(T))
        j = j[(lo[j] <= hi[i]).all(axis=1) & (hi[j] >= lo[i]).all(axis=1)]
        j = j[~np.isin(T[j], T[i]).any(axis=1)]
        for k in j:
            if any(segment_through(*edge, *tri[other])
                   for one, other in ((i, k), (k, i))
                   for edge in ((tri[one][e], tri[one][(e + 1) % 3]) for e in range(3))):
                found.append((i, int(k)))
    return found


def prism_mesh(section, levels):
    """A prism along y over the quadrilateral `section` ((x, z) corners), with a ring of
    vertices at each of `levels` (y): 8 facets a ring gap and 2 a cap, outward."""
    q = np.asarray(section, float)
    P = np.array([[x, y, z] for y in levels for x, z in q])
    T = []
    for k in range(len(levels) - 1):
        for i in range(4):
            a_, b = 4 * k + i, 4 * k + (i + 1) % 4
            T += [(a_, b, b + 4), (a_, b + 4, a_ + 4)]
    last = 4 * (len(levels) - 1)
    T += [(0, 2, 1), (0, 3, 2), (last, last + 1, last + 2), (last, last + 2, last + 3)]
    X = P[np.array(T)]
    if np.einsum("ij,ij->", X[:, 0], np.cross(X[:, 1], X[:, 2])) < 0:
        T = [t[::-1] for t in T]
    return Mesh.Mesh([[V(*P[i]) for i in t] for t in T])


# the tilted quadrilateral and the y stations of both classes' prism
TILTED = ([(0.0233, 0.1910), (0.0999, 0.1677), (0.1252, 0.2657), (0.0485, 0.2880)],
          (-0.37, 0.0, 0.37))


class MeshDocument:
    """A document per test holding an empty Mesh::Feature, self.base, named `name`."""
    name = "Base"

    def setup_method(self):
        self.doc = fc.new_document(type(self).__name__)
        self.base = self.doc.addObject("Mesh::Feature", self.name)

    def teardown_method(self):
        App.closeDocument(self.doc.Name)


class PrismDocument(MeshDocument):
    """A document holding the prism over TILTED as the Base mesh."""
    name = "Prism"

    def setup_method(self):
        super().setup_method()
        self.base.Mesh = prism_mesh(*TILTED)


def assert_refused_or_clean(obj, prop):
    """A refusal naming `prop`, or an Up-to-date result without crossing facets."""
    if "Invalid" in obj.State:
        assert prop in obj.getStatusString()
        return
    assert not crossing_pairs(*arrays(obj.Mesh)), "crossing facets in an Up-to-date result"


class TestTwistFarFromTheAxis(PrismDocument):
    """trimesh's multibody.stl twisted at z 70 % about its default axis (its flipped facets
    put the section's centroid some 4000 sizes away): each slab turns the part far from
    the axis by a long shear, and at Samples 16 the box's flat facets crossed, 14 pairs,
    Up-to-date. Here a tilted box 0.08 x 0.74 x 0.1, twisted 30 deg between z = 0.186 and
    0.220 about a z axis 4200 away, as in that model: a prism along y over a tilted
    quadrilateral, with a ring at y = 0."""

    def twist(self, samples):
        n = V(0, 0, 1)
        obj = fd.make_twist(self.base, (V(0, 0, 0.186), n), (V(0, 0, 0.220), n), 30.0,
                            (V(-3507.7, 2311.7, 0.186), n))
        obj.Samples = samples
        self.doc.recompute()
        return obj

    def test_coarse_samples_refused_or_clean(self):
        assert not crossing_pairs(*arrays(self.base.Mesh))
        assert_refused_or_clean(self.twist(16), "Samples")

    def test_enough_samples_up_to_date_and_clean(self):
        obj = self.twist(64)
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        X, T = arrays(obj.Mesh)
        assert_closed_manifold(X, T)
        assert not crossing_pairs(X, T)


class TestTwoPlaneBendOfAPrism(PrismDocument):
    """The same prism bent between z = 0.186 and 0.220 about a line along y in Plane (the
    two-plane mesh Bend runs the Twist's kernel): bent toward the near part (the far part
    swinging into it) the region was swept through the near part, 10 crossing pairs,
    Up-to-date (the one-plane Bend and the solids refuse it naming Angle); bent away about
    a line 3500 away, at Samples 16 each slab's facets sheared through each other, 24
    pairs, Up-to-date."""

    def bend(self, angle, axis_x, samples):
        n = V(0, 0, 1)
        obj = fd.make_bend(self.base, (V(0, 0, 0.186), n), angle,
                           (V(axis_x, 0, 0.186), V(0, 1, 0)), (V(0, 0, 0.220), n))
        obj.Samples = samples
        self.doc.recompute()
        return obj

    def test_toward_the_near_part_refused(self):
        assert_refused_or_clean(self.bend(30.0, -20.0, 64), "Angle")

    def test_far_axis_coarse_refused_or_clean(self):
        assert_refused_or_clean(self.bend(-30.0, -3500.0, 16), "Samples")

    def test_far_axis_enough_samples_clean(self):
        obj = self.bend(-30.0, -3500.0, 64)
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        X, T = arrays(obj.Mesh)
        assert_closed_manifold(X, T)
        assert not crossing_pairs(X, T)
