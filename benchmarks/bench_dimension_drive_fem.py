"""DimensionDrive on tetrahedral FEM meshes (issue 17): binding and update, next to the
sparse-product floor.

    /usr/bin/python3 benchmarks/bench_dimension_drive_fem.py            # median of 5 runs
    /usr/bin/python3 benchmarks/bench_dimension_drive_fem.py --quick    # 1 run

Prints a table, asserts nothing about time. Rows per mesh (the sfepy wheelset, FreeCAD's
CalculiX rotor): reading the FemMesh into arrays; binding (the boundary's handle, the
Laplacian factorized); a drive (constraint vectors, the handle product, the harmonic
solve, flip and inversion ranges, the self-intersection check); the update of every node
for a new s once the field is known (x + s * field); writing the FemMesh back (FreeCAD);
Rehandle to a radius beyond Reachable (each handle after the first a new binding).
The floor is a CSR product of the handle's shape and non-zeros, random values, plus the
interior solve's own cost (splu solve of 3 right-hand sides), measured in the same run.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from bench_stretch import (machine_line, options, print_table, run_as_script,  # noqa: E402
                           testdata)

import FreeCAD  # noqa: E402,F401  (before Fem)
import numpy as np  # noqa: E402
from scipy.sparse import csr_matrix  # noqa: E402

FEM_MOD = "/usr/share/freecad/Mod/Fem"
if os.path.isdir(FEM_MOD) and FEM_MOD not in sys.path:
    sys.path.append(FEM_MOD)
import Fem  # noqa: E402
from feminout import importInpMesh  # noqa: E402

from freecad_deform.ops import dimension_drive as op  # noqa: E402
from freecad_deform.shapes.fem import fem_arrays, fem_with_nodes  # noqa: E402

# name, file, reader, picks, target, a target beyond Reachable for Rehandle (or None)
CASES = (("wheelset radius", "sfepy_wheelset.vtk", Fem.read, [(0.0, 0.075, 0.0)], 0.08, 0.21),
         ("rotor radius", "fcfem_constraint_centrif.inp", importInpMesh.read,
          [(102.5, 0, 5)], 100.0, None))


def ms(t):
    return f"{t * 1e3:.3f}"


def rows_of(timer, name, path, read, picks, target, beyond):
    femmesh = read(testdata(path))
    t_read, n_read = timer.median(lambda: fem_arrays(femmesh))
    ids, X, _, E = fem_arrays(femmesh)
    size = f"{len(X)} nodes, {len(E)} tets"
    t_bind, n_bind = timer.median(lambda: op.fem_handle(X, E))
    model = op.fem_handle(X, E)
    t_drive, n_drive = timer.median(
        lambda: op.fem(model, femmesh, ids, "Radius", picks, target))
    drive = model.drive("Radius", picks, target)
    t_update, n_update = timer.median(lambda: model.nodes + drive.step * drive.field)
    W = model.surface.handle.weights
    rng = np.random.default_rng(0)
    floor_matrix = csr_matrix((rng.random(W.nnz), W.indices, W.indptr), shape=W.shape)
    moves = rng.random((W.shape[1], 3))
    ext = model.extension
    rhs = rng.random((len(ext.interior), 3))
    t_floor, n_floor = timer.median(lambda: (floor_matrix @ moves,
                                             ext.solver.solve(rhs)))
    t_write, n_write = timer.median(lambda: fem_with_nodes(femmesh, ids, X))
    return [(name, size, "read arrays", n_read, ms(t_read), ""),
            (name, size, "bind (1 time)", n_bind, ms(t_bind), ""),
            (name, size, "op.fem (new target, written)", n_drive, ms(t_drive), ms(t_floor)),
            (name, size, "update x + s f", n_update, ms(t_update), ""),
            (name, size, "write FemMesh", n_write, ms(t_write), "")] + \
        rehandle_rows(timer, name, size, model, femmesh, ids, picks, beyond)


def rehandle_rows(timer, name, size, model, femmesh, ids, picks, beyond):
    """Rehandle to a target beyond Reachable: every handle after the first is a binding."""
    if beyond is None:
        return []
    t, n = timer.median(lambda: op.fem(model, femmesh, ids, "Radius", picks, beyond,
                                       rehandle=True))
    handles = op.fem(model, femmesh, ids, "Radius", picks, beyond, rehandle=True)[1]["Handles"]
    return [(name, size, f"Rehandle to {beyond:g} ({handles} handles)", n, ms(t), "")]


def main(argv):
    args, timer = options(argv, __doc__, budget=60.0)
    print(machine_line())
    rows = []
    for case in CASES:
        rows += rows_of(timer, *case)
    print_table("DimensionDrive on FEM meshes; floor: handle-shaped CSR product + the "
                "interior solve", ("case", "input", "step", "runs", "ms", "floor ms"), rows)


run_as_script(main, __name__, __file__)
