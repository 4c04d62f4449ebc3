"""DimensionDrive on FEM meshes of tetrahedra (issue 17): the sfepy wheelset (.vtk, metres)
and FreeCAD's CalculiX rotor (.inp, mm), linear and quadratic.

Oracles written here: a cylinder and planes fitted by the test to the nodes it selects
by coordinates, signed volumes of every tetrahedron (its quadratic elements split by the
test), node and element numbers and connectivity read off both FEM meshes, groups, and
FreeCAD's CalculiX input writer with the written file read back by FreeCAD's .inp reader.
"""
import os
import re
import sys
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402

FEM_MOD = "/usr/share/freecad/Mod/Fem"
if os.path.isdir(FEM_MOD) and FEM_MOD not in sys.path:
    sys.path.append(FEM_MOD)
import Fem  # noqa: E402
import ObjectsFem  # noqa: E402
from feminout import importInpMesh  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402
from ..oracles.fits import cylinder_fit_free as fit_cylinder, radial  # noqa: E402
from ..oracles.mesh import tet_volumes as volumes_of  # noqa: E402

MIDS = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))   # SMDS order of mid-edge nodes


def nodes_of(femmesh):
    points = femmesh.Nodes                   # a new dict at every access: read it once
    ids = np.array(sorted(points))
    return ids, np.array([tuple(points[i]) for i in ids.tolist()])


def elements_of(femmesh):
    return {v: tuple(femmesh.getElementNodes(v)) for v in femmesh.Volumes}


def tet_volumes(femmesh):
    """Signed volumes of the corner tetrahedra, and for quadratic elements of the 8 parts
    the test cuts each into (oracles.mesh.tet_volumes)."""
    ids, X = nodes_of(femmesh)
    return volumes_of(X, np.searchsorted(ids, np.array(list(elements_of(femmesh).values()))))


def quadratic(femmesh, radii=()):
    """A 10-node tetrahedral copy of a linear mesh (new node numbers after the largest,
    element numbers and order kept), its mid-edge nodes as a second-order mesher places
    them: on the boundary edges of the coaxial z cylinders of `radii`, on the circle through
    the edge's ends; elsewhere at the edge's midpoint."""
    out = Fem.FemMesh()
    ids, X = nodes_of(femmesh)
    for i, p in zip(ids.tolist(), X.tolist()):
        out.addNode(*p, i)
    position = dict(zip(ids.tolist(), X))
    conn = np.array(list(elements_of(femmesh).values()))
    faces = np.sort(conn[:, [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]].reshape(-1, 3), 1)
    uniq, count = np.unique(faces, axis=0, return_counts=True)
    outer = {tuple(sorted(e)) for f in uniq[count == 1].tolist()
             for e in ((f[0], f[1]), (f[1], f[2]), (f[0], f[2]))}
    mid, nxt = {}, int(ids.max()) + 1
    for v, corners in elements_of(femmesh).items():
        extra = []
        for a, b in MIDS:
            key = tuple(sorted((corners[a], corners[b])))
            if key not in mid:
                p = (position[key[0]] + position[key[1]]) / 2
                ra, rb = (np.hypot(*position[k][:2]) for k in key)
                if key in outer and any(abs(ra - r) < 1e-9 * r and abs(rb - r) < 1e-9 * r
                                        for r in radii):
                    p[:2] *= ra / np.hypot(*p[:2])
                out.addNode(*p.tolist(), nxt)
                mid[key], nxt = nxt, nxt + 1
            extra.append(mid[key])
        out.addVolume(list(corners) + extra, v)
    return out


class FemDriveCase(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("DimensionDriveFem")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def base(self, femmesh, name):
        obj = self.doc.addObject("Fem::FemMeshObject", name)
        obj.FemMesh = femmesh
        self.doc.recompute()
        return obj

    def wheelset(self):
        return self.base(Fem.read(fc.testdata("sfepy_wheelset.vtk")), "Wheelset")

    def rotor(self, order=1):
        mesh = importInpMesh.read(fc.testdata("fcfem_constraint_centrif.inp"))
        return self.base(mesh if order == 1 else quadratic(mesh, (97.5, 102.5)), "Rotor")

    def check_same_mesh(self, base, obj):
        """Same node numbers, elements, connectivity and groups; nothing inverted."""
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertEqual(obj.TypeId, "Fem::FemMeshObjectPython")
        a, b = base.FemMesh, obj.FemMesh
        self.assertEqual((a.NodeCount, a.VolumeCount), (b.NodeCount, b.VolumeCount))
        np.testing.assert_array_equal(nodes_of(a)[0], nodes_of(b)[0])
        self.assertEqual(elements_of(a), elements_of(b))
        groups = [(a.getGroupName(g), a.getGroupElementType(g), a.getGroupElements(g))
                  for g in a.Groups]
        self.assertEqual(groups, [(b.getGroupName(g), b.getGroupElementType(g),
                                   b.getGroupElements(g)) for g in b.Groups])
        before, after = tet_volumes(a), tet_volumes(b)
        self.assertEqual(int(np.count_nonzero(np.sign(before) != np.sign(after))), 0)
        self.assertGreater(obj.QualityAfter, 0)
        self.assertGreater(obj.QualityBefore, 0)

    def check_cylinder(self, base, obj, select, target):
        """Every node the test finds on the picked cylinder ends on the cylinder it fits to
        them afterwards, whose radius is the target (1e-6 of the mesh size)."""
        ids, X = nodes_of(base.FemMesh)
        size = np.linalg.norm(np.ptp(X, axis=0))
        on = select(X)
        point, axis, r0, dev0 = fit_cylinder(X[on])
        on &= np.abs(radial(X, point, axis) - r0) < 1e-9 * size
        self.assertGreater(on.sum(), 50)
        Y = nodes_of(obj.FemMesh)[1]
        point1, axis1, r1, dev1 = fit_cylinder(Y[on])
        self.assertLess(abs(r1 - target), 1e-6 * size)
        self.assertLess(np.abs(radial(Y[on], point1, axis1) - target).max(), 1e-6 * size)
        self.assertLess(np.linalg.norm(np.cross(axis, axis1)), 1e-9)
        return abs(r1 - target) / size, np.abs(radial(Y[on], point1, axis1) - target).max() / size

    def check_planes(self, base, obj, coordinate, moving, fixed, target):
        """Nodes on the moving and the fixed plane (selected by coordinate) on planes the
        test fits, the distance between them the target, the fixed plane unmoved."""
        _, X = nodes_of(base.FemMesh)
        Y = nodes_of(obj.FemMesh)[1]
        size = np.linalg.norm(np.ptp(X, axis=0))
        a = np.abs(X[:, coordinate] - moving) < 1e-9 * size
        b = np.abs(X[:, coordinate] - fixed) < 1e-9 * size
        self.assertGreater(min(a.sum(), b.sum()), 20)

        def plane(P):
            c = P.mean(axis=0)
            n = np.linalg.svd(P - c)[2][-1]
            return c, n, np.abs((P - c) @ n).max()
        ca, na, da = plane(Y[a])
        cb, nb, db = plane(Y[b])
        self.assertLess(max(da, db), 1e-6 * size)
        self.assertLess(np.linalg.norm(np.cross(na, nb)), 1e-9)
        error = abs(abs((ca - cb) @ nb) - target)
        self.assertLess(error, 1e-6 * size)
        self.assertLessEqual(np.abs(Y[b] - X[b]).max(), 1e-12 * size)
        return error / size

    def check_calculix(self, obj):
        """FreeCAD's CalculiX writer writes the result; its .inp reads back with the same
        nodes and elements."""
        from femmesh import meshsetsgetter
        from femsolver.calculix import writer
        from femtools import membertools
        analysis = ObjectsFem.makeAnalysis(self.doc, "Analysis")
        make_solver = getattr(ObjectsFem, "makeSolverCalculiXCcxTools", None) or \
            ObjectsFem.makeSolverCalculixCcxTools   # FreeCAD 1.1 spells it CalculiX
        solver = make_solver(self.doc)
        material = ObjectsFem.makeMaterialSolid(self.doc, "Steel")
        values = material.Material
        values.update({"Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.3",
                       "Density": "7900 kg/m^3"})
        material.Material = values
        for o in (solver, material, ObjectsFem.makeConstraintFixed(self.doc), obj):
            analysis.addObject(o)
        self.doc.recompute()
        sets = meshsetsgetter.MeshSetsGetter(analysis, solver, obj,
                                             membertools.AnalysisMember(analysis))
        sets.get_mesh_sets()
        path = writer.FemInputWriterCcx(analysis, solver, obj, sets.member, tempfile.mkdtemp(),
                                        sets.mat_geo_sets).write_solver_input()
        with open(path) as f:
            text = f.read()
        self.assertIn("*Element, TYPE=C3D", text)
        back = importInpMesh.read(path)
        self.assertEqual((back.NodeCount, back.VolumeCount),
                         (obj.FemMesh.NodeCount, obj.FemMesh.VolumeCount))
        ids, X = nodes_of(obj.FemMesh)
        ids2, X2 = nodes_of(back)
        np.testing.assert_array_equal(ids, ids2)
        self.assertLess(np.abs(X - X2).max(), 1e-9 * np.abs(X).max())


class TestWheelset(FemDriveCase):
    def test_axle_radius(self):
        base = self.wheelset()
        mesh = base.FemMesh
        g = mesh.addGroup("AxleEnd", "Node")
        mesh.addGroupElements(g, [1, 2, 3, 4])
        g = mesh.addGroup("SomeVolumes", "Volume")
        mesh.addGroupElements(g, list(mesh.Volumes[:5]))
        base.FemMesh = mesh
        self.doc.recompute()
        obj = fd.make_dimension_drive(base, "Radius", [(0.0, 0.075, 0.0)], 0.08)
        self.check_same_mesh(base, obj)
        self.assertEqual(len(obj.FemMesh.Groups), 2)
        print("\nwheelset radius: fit error / size %.2g, node deviation / size %.2g, quality "
              "%.4f -> %.4f" % (*self.check_cylinder(
                  base, obj, lambda X: (np.abs(X[:, 0]) < 0.6801)
                  & (np.abs(np.hypot(X[:, 1], X[:, 2]) - 0.075) < 1e-3), 0.08),
                  obj.QualityBefore, obj.QualityAfter))
        self.assertAlmostEqual(obj.Current, 0.075, delta=1e-9)
        self.assertAlmostEqual(obj.Achieved, 0.08, delta=1e-9)
        self.check_calculix(obj)

    def test_wheel_thickness(self):
        base = self.wheelset()
        obj = fd.make_dimension_drive(base, "Distance", [(-0.68, 0.2, 0.2), (-0.76, 0.2, 0.2)],
                                      0.09)
        self.check_same_mesh(base, obj)
        error = self.check_planes(base, obj, 0, -0.68, -0.76, 0.09)
        print(f"\nwheelset thickness: distance error / size {error:.2g}, quality "
              f"{obj.QualityBefore:.4f} -> {obj.QualityAfter:.4f}")


class TestRotor(FemDriveCase):
    def check_rotor(self, order):
        base = self.rotor(order)
        obj = fd.make_dimension_drive(base, "Radius", [(102.5, 0, 5)], 100)
        self.check_same_mesh(base, obj)
        errors = self.check_cylinder(base, obj, lambda X: (X[:, 2] < 10.001)
                                     & (np.abs(np.hypot(X[:, 0], X[:, 1]) - 102.5) < 1e-6), 100)
        self.check_calculix(obj)
        # the sub-tetrahedra of the quadratic mesh are half as thick: it reaches 9.16
        thickness = 8 if order == 1 else 9.5
        thick = fd.make_dimension_drive(base, "Distance", [(0, 50, 10), (0, 50, 0)], thickness)
        self.check_same_mesh(base, thick)
        error = self.check_planes(base, thick, 2, 10, 0, thickness)
        print(f"\nrotor order {order}: radius fit error / size {errors[0]:.2g}, node "
              f"deviation / size {errors[1]:.2g}, thickness error / size {error:.2g}; quality "
              f"{obj.QualityBefore:.4f} -> {obj.QualityAfter:.4f} (radius), "
              f"{thick.QualityAfter:.4f} (thickness)")

    def test_linear(self):
        self.check_rotor(1)

    def test_quadratic(self):
        self.check_rotor(2)

    def test_inverting_target_is_refused_and_the_base_stays(self):
        base = self.rotor()
        ids, X = nodes_of(base.FemMesh)
        obj = fd.make_dimension_drive(base, "Radius", [(102.5, 0, 5)], 100)
        obj.Target = 96                       # the outer wall through the inner one (97.5)
        self.doc.recompute()
        self.assertIn("Invalid", obj.State)
        status = obj.getStatusString()
        self.assertIn("Target", status)
        # the outer wall stops short of the inner one (97.5), by how much depends on the
        # handle: 97.x when the rotor was collapsed whole, 98.2 from its outlines
        reach = re.search(r"reachable ([0-9.]+) to [0-9.]+", status)
        self.assertIsNotNone(reach, status)
        self.assertTrue(97.5 < float(reach.group(1)) < 99, status)
        np.testing.assert_array_equal(nodes_of(base.FemMesh)[1], X)
        obj.Target = 99
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State)
        self.assertAlmostEqual(obj.Achieved, 99, delta=1e-9)

    def test_disc_driven_into_the_other_disc_is_refused(self):
        """No tetrahedron inverts when the lower disc's top rises past the upper disc's
        bottom at 20 mm (two bodies, 10 mm apart): the crossing is found and the range
        that stays clear given (within 1/128 of the step, 15 mm, below 20)."""
        base = self.rotor()
        X = nodes_of(base.FemMesh)[1]
        obj = fd.make_dimension_drive(base, "Distance", [(0, 50, 10), (0, 50, 0)], 25)
        self.assertIn("Invalid", obj.State)
        status = obj.getStatusString()
        self.assertRegex(status, r"Target makes the mesh cut through itself: it stays clear "
                                 r"from 10 to [0-9.]+")
        clear = float(status.split(" to ")[1].split(";")[0])
        self.assertTrue(20 - 15 / 128 - 1e-9 <= clear <= 20, clear)
        np.testing.assert_array_equal(nodes_of(base.FemMesh)[1], X)
        obj.Target = 19
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertAlmostEqual(obj.Achieved, 19, delta=1e-9)

    def test_other_features_refuse_it_naming_dimension_drive(self):
        """Stretch and Twist take no FEM mesh: refused at make, naming Base and the one
        feature that does; nothing is left in the document and the Base is unchanged."""
        base = self.rotor()
        before = nodes_of(base.FemMesh)[1].copy()
        V = App.Vector
        for make in (lambda: fd.make_stretch(base, (V(0, 0, 0), V(0, 0, 1)), 5.0),
                     lambda: fd.make_twist(base, (V(0, 0, 0), V(0, 0, 1)),
                                           (V(0, 0, 5), V(0, 0, 1)), 30.0, None)):
            with self.assertRaises(DeformError) as caught:
                make()
            self.assertEqual(caught.exception.prop, "Base")
            self.assertIn("only DimensionDrive", str(caught.exception))
            self.assertEqual([o.Name for o in self.doc.Objects], [base.Name])
        np.testing.assert_array_equal(nodes_of(base.FemMesh)[1], before)

    def test_save_and_reopen(self):
        base = self.rotor()
        obj = fd.make_dimension_drive(base, "Radius", [(102.5, 0, 5)], 101)
        name, base_name = obj.Name, base.Name
        path = os.path.join(tempfile.mkdtemp(), "fem_drive.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(name)
        again.Target = 100.5
        self.doc.recompute()
        self.assertNotIn("Invalid", again.State, again.getStatusString())
        self.assertAlmostEqual(again.Achieved, 100.5, delta=1e-9)
        self.assertEqual(again.FemMesh.NodeCount, self.doc.getObject(base_name).FemMesh.NodeCount)


if __name__ == "__main__":
    unittest.main()
