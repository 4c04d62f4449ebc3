"""A cut face whose arc lies at parameters shifted by a whole period (a real file's split gives
them) revolves into a sweep that OCCT's slice still cuts: the Bend of occt_Bottom lost a
region of its mid-angle section. Oracles: the half disc's area and Pappus, written here."""
import unittest

from . import fc  # noqa: F401  (FreeCAD on the path)

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

from freecad_deform.shapes import brep  # noqa: E402

V = App.Vector


def shifted_half_disc(r=10.0):
    """A half disc in z = 0 (centre (0, 50, 0)) bounded by its diameter and a circle edge
    at parameters 2 pi .. 3 pi (FreeCAD trims arcs into the first period, so the range is
    written into the BREP text, as a real file's split leaves it)."""
    arc = Part.Circle(V(0, 50, 0), V(0, 0, 1), r).toShape(0, np.pi)
    face = Part.Face(Part.Wire([arc, Part.makeLine(arc.Vertexes[-1].Point,
                                                    arc.Vertexes[0].Point)]))
    text = face.exportBrepToString()
    plain = f"1  1 0 0 {np.pi:.15g}\n"
    assert text.count(plain) == 1, text
    shifted = Part.Shape()
    shifted.importBrepFromString(text.replace(plain, f"1  1 0 {2 * np.pi:.15g} "
                                                     f"{3 * np.pi:.15g}\n"))
    return shifted.Faces[0]


class RevolvePeriod(unittest.TestCase):
    def test_mid_angle_section_and_pappus(self):
        r = 10.0
        face = shifted_half_disc(r)
        self.assertGreaterEqual(face.Edges[0].FirstParameter, 2 * np.pi - 1e-9)
        solid = brep.revolved([face], np.zeros(3), np.array([1.0, 0, 0]), np.radians(30))[0]
        self.assertTrue(solid.isValid())
        area = np.pi * r * r / 2
        centroid_y = 50 + 4 * r / (3 * np.pi)
        self.assertAlmostEqual(solid.Volume, area * centroid_y * np.radians(30),
                               delta=1e-6 * solid.Volume)
        n = V(0, -np.sin(np.radians(15)), np.cos(np.radians(15)))  # the mid-angle plane
        wires = solid.slice(n, 0.0)
        self.assertTrue(wires and all(w.isClosed() for w in wires))
        got = sum(Part.Face(w).Area for w in wires)
        self.assertAlmostEqual(got, area, delta=1e-6 * area)  # the slice fits its curves


if __name__ == "__main__":
    unittest.main()
