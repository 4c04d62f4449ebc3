"""Mesh Twist at many Samples on real FreeCAD meshes (issue 11: the band is cut at every
Samples plane in time linear in Samples), through the document object.

Oracles: FreeCAD's own mesh checks on the result (isSolid, hasNonManifolds, countComponents),
a half-edge count and a float64 divergence-theorem volume written here, the number of pieces
of the triangles crossing k planes (deform_tests/oracles/mesh.expected_count) less two
per section segment shorter than the snapping distance, and the input's sections from
FreeCAD's Mesh.crossSections, turned by a rotation written here.
"""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.features.planes import MAX_SAMPLES  # noqa: E402

from ..oracles.mesh import (arrays, distance_to_segments, expected_count,  # noqa: E402
                                     section_segments)

V = App.Vector
ANGLE = 90.0


def volume(V, T):
    """Enclosed volume by the divergence theorem in float64 (Mesh.Volume sums in float32:
    0.07 mm^3 off on the 65,564-facet box)."""
    return np.linalg.det(V[T]).sum() / 6


def half_edges_closed(T):
    """Every directed edge once and its reverse present (closed, consistently oriented)."""
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    key = a * (T.max() + 1) + b
    twin = b * (T.max() + 1) + a
    return len(np.unique(key)) == len(key) and bool(np.isin(twin, key).all())


def turned(points, centre, axis, degrees):
    """Points turned about the line (centre, axis) by Rodrigues' formula, written out."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    phi = np.radians(degrees)
    r = np.asarray(points, float) - centre
    return (centre + r * np.cos(phi) + np.cross(k, r) * np.sin(phi)
            + np.outer(r @ k, k) * (1 - np.cos(phi)))


def centres_in(V1, V0, origin, n, gap, samples, centre):
    """How many of the result's vertices are quadrilaterals' centres: neither on a plane
    (a cut point) nor an input vertex (turned back by -ANGLE clip(s / gap), within the
    float32 storage)."""
    s = (V1 - origin) @ n
    level = s * samples / gap
    step = 4 * float(np.finfo(np.float32).eps) * max(1.0, np.abs(V1).max())   # stored
    on = np.abs(level - np.round(level)) * gap / samples < step
    back = np.array([turned(p, centre, n, -ANGLE * f)
                     for p, f in zip(V1, np.clip(s / gap, 0, 1))]).reshape(-1, 3)
    known = cKDTree(V0).query(back)[0] < step
    return int((~on & ~known).sum())


def sampling_error(segments, gap, centre, n, samples, V0, area):
    """How far the twisted mesh's volume may be off: the band (perimeter P x gap) is flat
    facets between section rings turned by step = angle / samples. Each facet sags off the
    twisted surface by at most r step^2 / 8 (r the largest radius), and a quadrilateral
    between two rings, w wide (the longest section segment), is twisted out of its plane by
    w step, so either diagonal cuts at most w step / 12 off its area. Float32 storage moves
    each vertex by 6e-8 of its coordinates. (Measured on the housing: at most 0.21 of it.)"""
    P = max(np.linalg.norm(q - p, axis=1).sum() for p, q in segments)
    w = max(np.linalg.norm(q - p, axis=1).max() for p, q in segments)
    r = max(np.linalg.norm(np.cross(np.r_[p, q] - centre, n), axis=1).max() for p, q in segments)
    step = np.radians(ANGLE) / samples
    return P * gap * (r * step ** 2 / 8 + w * step / 12) + 1e-7 * np.abs(V0).max() * area


def plane_sections(V0, T0, origin, n, levels, eps):
    """At each level: the section segments (p, q) of the input with the vertices within eps
    of a plane put onto it (as the cut must), those vertices, and how many segments of
    triangles with no such vertex are shorter than eps (one float32 point: their two cut
    points must become one, taking the two facets on that tiny edge)."""
    s = (V0 - origin) @ n
    spacing = levels[1] - levels[0]
    plane = np.clip(np.round(s / spacing), 0, len(levels) - 1)
    near = np.abs(s - plane * spacing) <= eps
    put = V0 - np.outer(np.where(near, s - plane * spacing, 0.0), n)
    sp = np.where(near, plane * spacing, s)[T0]
    lo, hi = sp.min(axis=1), sp.max(axis=1)
    order = np.argsort(lo)
    out = []
    for j, level in enumerate(levels):
        cand = order[:np.searchsorted(lo[order], level)]
        cand = cand[hi[cand] > level]                    # the triangles crossing the plane
        p, q = section_segments(put, T0[cand], origin, n, level)
        clear = T0[cand][~(near & (plane == j))[T0[cand]].any(axis=1)]
        a, b = section_segments(put, clear, origin, n, level)
        tiny = int((np.linalg.norm(b - a, axis=1) <= eps).sum())
        out.append((p, q, put[near & (plane == j)], tiny))
    return out, near.any()


def snap_distance(vertices):
    """Four float32 steps of the largest coordinate, as FreeCAD stores the mesh."""
    return 4 * float(np.finfo(np.float32).eps) * float(np.abs(vertices).max())


class MeshSamplesTest(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document()

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def twist(self, mesh, lo, hi):
        """A Twist of the mesh between the planes at the fractions lo and hi of its longest
        side, about the centre line; returns (obj, origin, normal, gap, centre)."""
        base = self.doc.addObject("Mesh::Feature", "Base")
        base.Mesh = mesh
        box = mesh.BoundBox
        low = np.array([box.XMin, box.YMin, box.ZMin])
        size = np.array([box.XLength, box.YLength, box.ZLength])
        k = int(np.argmax(size))
        n = np.eye(3)[k]
        origin = low + lo * size * n
        gap = (hi - lo) * size[k]
        centre = low + size / 2
        obj = fd.make_twist(base, (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n)), ANGLE,
                            (V(*centre), V(*n)))
        return obj, origin, n, gap, centre

    def test_housing_twist_at_growing_samples(self):
        """The finned housing (7,196 triangles) twisted 90 deg at Samples 16 to 1024: closed,
        manifold, one piece; the triangle count is the pieces of the triangles crossing the
        planes (linear in Samples); the volume kept up to the sampling error; on every plane
        the result's vertices are the input's section turned."""
        mesh = Mesh.Mesh(fc.testdata("occt_sh2.stl"))
        V0, T0 = arrays(mesh)
        eps = snap_distance(V0)
        obj, origin, n, gap, centre = self.twist(mesh, 0.3, 0.8)
        most = max(len(section_segments(V0, T0, origin, n, level)[0])
                   for level in np.linspace(0, gap, 101))     # triangles a plane crosses
        checked_by_freecad = 0
        for samples in (16, 64, 256, 1024):
            obj.Samples = samples
            self.doc.recompute()
            self.assertEqual(obj.State, ["Up-to-date"], obj.getStatusString())
            out = obj.Mesh
            self.assertTrue(out.isSolid())
            self.assertFalse(out.hasNonManifolds())
            self.assertEqual(out.countComponents(), mesh.countComponents())
            V1, T1 = arrays(out)
            self.assertTrue(half_edges_closed(T1))
            levels = gap * np.arange(samples + 1) / samples
            sections, snapped = plane_sections(V0, T0, origin, n, levels, eps)
            tiny = sum(x[3] for x in sections)
            centres = centres_in(V1, V0, origin, n, gap, samples, centre)   # 2 more each
            self.assertEqual(out.CountFacets, expected_count(V0, T0, origin, n, gap, samples,
                                                             eps) - 2 * tiny + 2 * centres)
            self.assertLessEqual(out.CountFacets - 2 * centres,
                                 len(T0) + 2 * (samples + 1) * most)
            tol = sampling_error([x[:2] for x in sections], gap, centre, n, samples, V0,
                                 mesh.Area)
            self.assertLess(abs(volume(V1, T1) - volume(V0, T0)), tol)
            # on every plane the result's vertices there, turned back, are the input's section
            # (plane_sections), both ways, to float32; and where no vertex needed putting onto
            # a plane they cover FreeCAD's own section of the input (computed in float32: its
            # points lie up to 7.5e-5 off the facets)
            s1 = (V1 - origin) @ n
            lines = mesh.crossSections([(V(*(origin + level * n)), V(*n)) for level in levels])
            for j, (polylines, (p, q, on_plane, _)) in enumerate(zip(lines, sections)):
                back = turned(V1[np.abs(s1 - levels[j]) <= eps], centre, n, -ANGLE * j / samples)
                points = np.r_[p, q, on_plane]
                self.assertLess(np.minimum(distance_to_segments(back, p, q),
                                           cKDTree(points).query(back)[0]).max(), 1e-4)
                self.assertLess(cKDTree(back).query(points)[0].max(), 1e-4)
                if not snapped:
                    theirs = np.array([tuple(x) for line in polylines for x in line])
                    self.assertLess(cKDTree(back).query(theirs)[0].max(), 5e-4)
            checked_by_freecad += not snapped
        self.assertGreaterEqual(checked_by_freecad, 2)

    def test_box_at_the_bound(self):
        """The 12-triangle box 40 x 20 x 20 at Samples = MAX_SAMPLES: closed, its 8 side
        triangles each crossing all MAX_SAMPLES + 1 planes (2k + 1 pieces each, 2 more for
        each quadrilateral the twist takes out of its plane: centres_in) and its 4 end
        triangles whole; the volume kept up to the sampling error; one Sample more
        is refused naming Samples and the bound."""
        box = Mesh.Mesh(Part.makeBox(40, 20, 20).tessellate(1.0))
        self.assertEqual(box.CountFacets, 12)
        obj, origin, n, gap, centre = self.twist(box, 0.25, 0.75)
        obj.Samples = MAX_SAMPLES
        self.doc.recompute()
        self.assertEqual(obj.State, ["Up-to-date"], obj.getStatusString())
        self.assertTrue(obj.Mesh.isSolid())
        self.assertFalse(obj.Mesh.hasNonManifolds())
        V0, T0 = arrays(box)
        centres = centres_in(arrays(obj.Mesh)[0], V0, origin, n, gap, MAX_SAMPLES, centre)
        self.assertEqual(obj.Mesh.CountFacets,
                         4 + 8 * (2 * (MAX_SAMPLES + 1) + 1) + 2 * centres)
        segments = [section_segments(V0, T0, origin, n, level) for level in (0.0, gap)]
        tol = sampling_error(segments, gap, centre, n, MAX_SAMPLES, V0, box.Area)
        self.assertLess(abs(volume(*arrays(obj.Mesh)) - volume(*arrays(box))), tol)
        obj.Samples = MAX_SAMPLES + 1
        self.doc.recompute()
        self.assertIn("Invalid", obj.State)
        self.assertIn(f"Samples {MAX_SAMPLES + 1}", obj.getStatusString())
        self.assertIn(str(MAX_SAMPLES), obj.getStatusString())
