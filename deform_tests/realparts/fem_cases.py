"""The real-parts rows for FEM meshes (issue 17): DimensionDrive on the sfepy wheelset
(.vtk, metres) and FreeCAD's CalculiX rotor (.inp, mm): a radius and a thickness changed.
Oracles: a cylinder fitted to the nodes selected by coordinates (every one of them at the
target radius to 1e-6 of the size), planes fitted to the nodes of the two faces (their
distance the target), signed volumes of every tetrahedron (none inverted), node and
element counts, numbers and connectivity unchanged."""
import time

import numpy as np

from .cases import Case, Outcome, outcome_of
from ..features import fc
from ..features.test_dimension_drive_fem import elements_of, nodes_of, tet_volumes
from ..oracles.fits import cylinder_fit_free, plane, radial

import freecad_deform as fd  # noqa: E402

WHEELSET, ROTOR = "sfepy_wheelset.vtk", "fcfem_constraint_centrif.inp"


def _axle(X):
    return (np.abs(X[:, 0]) < 0.6801) & (np.abs(np.hypot(X[:, 1], X[:, 2]) - 0.075) < 1e-3)


def _rim(X):
    return (X[:, 2] < 10.001) & (np.abs(np.hypot(X[:, 0], X[:, 1]) - 102.5) < 1e-6)


# id: (model, kind, regions, target, oracle); oracle: ("cylinder", node selection) or
# ("planes", coordinate, moving value, fixed value)
FEM = {
    "fem-wheelset-radius": (WHEELSET, "Radius", [(0.0, 0.075, 0.0)], 0.08,
                            ("cylinder", _axle)),
    "fem-wheelset-thickness": (WHEELSET, "Distance", [(-0.68, 0.2, 0.2), (-0.76, 0.2, 0.2)],
                               0.09, ("planes", 0, -0.68, -0.76)),
    "fem-rotor-radius": (ROTOR, "Radius", [(102.5, 0.0, 5.0)], 100.0, ("cylinder", _rim)),
    "fem-rotor-thickness": (ROTOR, "Distance", [(0.0, 50.0, 10.0), (0.0, 50.0, 0.0)], 8.0,
                            ("planes", 2, 10.0, 0.0)),
}


def fem_cases():
    out = [Case(k, "fem", v[0], "DimensionDrive", {}) for k, v in FEM.items()]
    out.append(Case("fem-rotor-radius-inverting", "fem", ROTOR, "DimensionDrive",
                    {"like": "fem-rotor-radius", "target": 96.0}, "Target"))
    # beyond Reachable (0.2009 m): Rehandle goes on with handles rebuilt on the shape reached
    out.append(Case("fem-wheelset-radius-rehandle", "fem", WHEELSET, "DimensionDrive",
                    {"like": "fem-wheelset-radius", "target": 0.21, "rehandle": True}))
    return out


def load(doc, model):
    """A Fem::FemMeshObject of the test data file `model`."""
    import Fem
    obj = doc.addObject("Fem::FemMeshObject", "Base")
    if model.endswith(".inp"):
        from feminout import importInpMesh
        obj.FemMesh = importInpMesh.read(fc.testdata(model))
    else:
        obj.FemMesh = Fem.read(fc.testdata(model))
    doc.recompute()
    return obj


def run_fem(case, doc, floor):
    model, kind, regions, target, oracle = FEM[case.params.get("like", case.id)]
    target = case.params.get("target", target)
    base = load(doc, model)
    ids, X = nodes_of(base.FemMesh)
    elements = elements_of(base.FemMesh)
    before = tet_volumes(base.FemMesh)
    size = float(np.linalg.norm(np.ptp(X, axis=0)))
    t0 = time.perf_counter()
    rehandle = case.params.get("rehandle", False)
    obj = fd.make_dimension_drive(base, kind, regions, target, rehandle=rehandle)
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
    ids1, Y = nodes_of(obj.FemMesh)
    errors = {
        "node count": (abs(obj.FemMesh.NodeCount - base.FemMesh.NodeCount), 0.5),
        "element count": (abs(obj.FemMesh.VolumeCount - base.FemMesh.VolumeCount), 0.5),
        "numbering": (float(not (np.array_equal(ids, ids1)
                                 and elements_of(obj.FemMesh) == elements)), 0.5),
        "inverted": (float(np.count_nonzero(np.sign(tet_volumes(obj.FemMesh))
                                            != np.sign(before))), 0.5),
        "Achieved": (abs(obj.Achieved - target), 1e-6 * size),
    }
    if rehandle:
        errors["beyond one handle"] = (float(obj.Reachable[1] >= target or obj.Handles < 2), 0.5)
    tol = 1e-6 * size
    if oracle[0] == "cylinder":
        on = oracle[1](X)
        point, axis, r0, _ = cylinder_fit_free(X[on])
        on &= np.abs(radial(X, point, axis) - r0) < 1e-9 * size
        if on.sum() < 50:
            raise AssertionError(f"the test's cylinder has {on.sum()} nodes")
        point1, axis1, r1, _ = cylinder_fit_free(Y[on])
        errors["radius"] = (abs(r1 - target), tol)
        errors["nodes on the cylinder"] = (float(np.abs(radial(Y[on], point1, axis1)
                                                        - target).max()), tol)
        errors["axis kept"] = (float(np.linalg.norm(np.cross(axis, axis1))), 1e-9)
    else:
        _, coordinate, moving, fixed = oracle
        a = np.abs(X[:, coordinate] - moving) < 1e-9 * size
        b = np.abs(X[:, coordinate] - fixed) < 1e-9 * size
        ca, na, da = plane(Y[a])
        cb, nb, db = plane(Y[b])
        errors["planes flat"] = (float(max(da, db)), tol)
        errors["parallel"] = (float(np.linalg.norm(np.cross(na, nb))), 1e-9)
        errors["distance"] = (abs(abs((ca - cb) @ nb) - target), tol)
        errors["fixed plane kept"] = (float(np.abs(Y[b] - X[b]).max()), 1e-12 * size)
    return Outcome("ok", "", errors, seconds)
