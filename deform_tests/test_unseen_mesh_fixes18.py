"""Robustness defects found by running the mesh and cloud features on public meshes and
scans the project had not seen (trimesh's models, PCL's test clouds; see
/work/notes/unseen_mesh18.md), each rebuilt here on a generated base.

Oracles: FreeCAD's own mesh algorithms run on the result in a forked process (its exit
status: FreeCAD's self-intersection test ends the process on a mesh whose kept bounding
box no longer holds its points), the driven dimension measured on the vertices, the
closed 2-manifold check (deform_tests/oracles/mesh).
"""
import os

import numpy as np

from .features import fc

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

from .oracles.mesh import assert_closed_manifold  # noqa: E402

V = App.Vector


def arrays(mesh):
    points, facets = mesh.Topology
    return (np.array([tuple(p) for p in points], float).reshape(-1, 3),
            np.array(facets, np.int64).reshape(-1, 3))


def exit_status(fn):
    """The exit status of a forked process that runs fn() and exits 0 (FreeCAD ends the
    process itself, status 1, when its mesh grid meets a point outside the box)."""
    pid = os.fork()
    if pid == 0:   # the child: never back into pytest
        status = 2
        try:
            fn()
            status = 0
        finally:
            os._exit(status)
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])


class TestDriveBeyondTheBaseBox:
    """trimesh's round.stl (a rod 60.96 long): a DimensionDrive of its length to 1.02 x
    gave a mesh whose points lay beyond the bounding box the copied Base kernel kept
    (moved_mesh set each point with setPoint, which does not update it): FreeCAD's
    hasSelfIntersections() on the result (Mesh workbench, Evaluate and repair) ended
    the whole process, on 0.20 and 1.1."""

    def setup_method(self):
        self.doc = fc.new_document("UnseenDrive")

    def teardown_method(self):
        App.closeDocument(self.doc.Name)

    def drive(self, target):
        base = self.doc.addObject("Mesh::Feature", "Rod")
        base.Mesh = MeshPart.meshFromShape(Shape=Part.makeBox(10, 10, 60),
                                           LinearDeflection=0.1, AngularDeflection=0.5)
        obj = fd.make_dimension_drive(base, "Distance", [(5, 5, 60), (5, 5, 0)], target)
        assert "Invalid" not in obj.State
        return base, obj

    def test_lengthened_mesh_survives_freecads_checks(self):
        base, obj = self.drive(70.0)
        V1, T1 = arrays(obj.Mesh)
        assert V1[:, 2].max() - V1[:, 2].min() == np.float32(70.0)   # the oracle: vertices
        assert_closed_manifold(V1, T1)
        assert exit_status(lambda: obj.Mesh.hasSelfIntersections()) == 0
        assert exit_status(lambda: obj.Mesh.copy().hasSelfIntersections()) == 0
        bb = obj.Mesh.BoundBox
        assert (bb.ZMin, bb.ZMax) == (0.0, 70.0)
        V0, _ = arrays(base.Mesh)
        assert V0[:, 2].max() == 60.0                                   # Base kept
