"""The command line: argument parsing and help; the work is in run, sweep and solve."""
import argparse
import sys

HELP = """\
Deform batch runs: recompute FreeCAD models headless, study design variants, goal seek.

A model's parameters are named Object.Property, as in FreeCAD's property editor:
Stretch.Distance is the Distance of the object named (or labelled) Stretch. Outputs are
the read-only results of the features (Stretch.VolumeChange, AreaConstrain.AchievedArea)
or any attribute below an object (Stretch.Shape.Volume, Stretch.Shape.BoundBox.XLength).
Lengths are in mm and angles in degrees unless a unit is given ("2.5 cm").

examples:
  python3 -m freecad_deform run part.FCStd --export step,stl --out out/
  python3 -m freecad_deform run part.step --recipe stretch.json --out out/
  python3 -m freecad_deform sweep part.FCStd --table designs.csv --out study/
  python3 -m freecad_deform sweep part.FCStd --grid Stretch.Distance=10:50:5 --out study/
  python3 -m freecad_deform sweep part.FCStd --table designs.csv --out study/ \\
      --scheduler tcp://10.0.0.5:8786        # on a Dask cluster instead of local cores
  python3 -m freecad_deform solve part.FCStd --vary Stretch.Distance=0:100 \\
      --target Stretch.Shape.Volume=6.5e6 --out solved.FCStd
  freecadcmd freecad_deform/batch/freecadcmd.py -- run part.FCStd   # inside FreeCAD
"""

RUN = """\
Recompute one document and export its results. With a model file (STEP, BREP, IGES, STL,
OBJ, PCD) instead of a document, the model becomes the object "Model" and --recipe lists
the features to make on it, as JSON:
  {"steps": [{"make": "stretch", "base": "Model", "label": "S",
              "args": [[[150, 0, 0], [1, 0, 0]], 40]}],
   "set": {"S.Distance": "3 cm"}}
("make" is a make_* function of the macro API without make_, "args" and "kwargs" its
arguments: [x, y, z] is a point or vector, [[origin], [normal]] a plane or an axis.)
Prints every output property with validity and seconds per object and saves them in
OUT/results.csv (object, output, value). Exit status 1 if an object failed."""

SWEEP = """\
Recompute one variant per row of a design table and collect the results.
TABLE.csv has a header of Object.Property columns and one variant per row, e.g.
  Stretch.Distance,Bend.Angle
  10,-30
  20,-45
(or give --grid instead). OUT/results.csv gets, per variant and in table order, the
table's columns, every output property as Object.Output, then valid, seconds and error.
A variant that fails is recorded with its error and the sweep goes on. Run the same
command again to continue an interrupted sweep: rows already in results.csv are skipped.
Variants run in parallel, each worker its own FreeCAD process (--jobs, default: every
core); --scheduler tcp://HOST:8786 sends them to a Dask distributed cluster instead (its
workers need FreeCAD and this package). Exports go to OUT/exports/variant-NNNN_Object.ext
(NNNN the table row)."""

REACH = """\
The inverse problem: a feature of the far part (a hole's centre and axis, or a planar
face's centre and normal, picked as --feature FaceN of --base) must land at --target
POINT:AXIS. The far part's motion is the least rotation taking the axis to the target
axis, then the translation taking the centre there. A translation along the Plane's
normal becomes a Stretch; a turn about one axis an exact Bend (which one is printed as
"Method = ..."). A motion that is neither (a screw, a slide across the normal) is swept
through key frames (Method = KeyFrames: a Stretch whose far part ends at EndPlacement).
Vectors are written x,y,z."""

SOLVE = """\
Goal seek: find the property values within their bounds that make outputs hit targets
(Brent's method for one property and one target, bounded least squares otherwise), or
that minimise or maximise one output. Prints iterations and residual, and last the
solution as "Object.Property = value" lines; --out saves the solved document."""


def parser():
    top = argparse.ArgumentParser(prog="python3 -m freecad_deform", description=HELP,
                                  formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = top.add_subparsers(dest="command", required=True,
                             metavar="{run,sweep,solve,reach}")
    fmt = argparse.RawDescriptionHelpFormatter
    r = sub.add_parser("run", help="recompute and export one model", description=RUN,
                       formatter_class=fmt)
    r.add_argument("model", help="a .FCStd document, or a model file to apply --recipe to")
    r.add_argument("--recipe", help="JSON list of make_* steps (see above)")
    r.add_argument("--out", default=".", help="folder for results.csv and the exports "
                   "(default: here)")
    r.add_argument("--export", default="", metavar="FORMATS",
                   help="comma-separated: step, brep, stl, ply, fcstd")
    s = sub.add_parser("sweep", help="one variant per row of a design table",
                       description=SWEEP, formatter_class=fmt)
    s.add_argument("doc", help="the .FCStd document to vary")
    s.add_argument("--table", help="CSV design table, header Object.Property,...")
    s.add_argument("--grid", action="append", default=[], metavar="OBJ.PROP=LO:HI:N",
                   help="instead of --table: N values from LO to HI (or =a,b,c); repeat for "
                   "a full factorial grid, written to OUT/table.csv")
    s.add_argument("--out", required=True, help="folder for results.csv and the exports")
    s.add_argument("--jobs", type=int, default=None, help="worker processes (default: "
                   "every core; 1 runs in this process)")
    s.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, e.g. "
                   "tcp://10.0.0.5:8786")
    s.add_argument("--export", default="", metavar="FORMATS",
                   help="comma-separated: step, brep, stl, ply, fcstd")
    s.add_argument("--retry-failed", action="store_true",
                   help="on a rerun, run the failed variants again too")
    h = sub.add_parser("reach", help="make a feature of the far part land at a target",
                       description=REACH, formatter_class=fmt)
    h.add_argument("doc", help="the .FCStd document")
    h.add_argument("--base", required=True, help="the object to deform (Name or Label)")
    h.add_argument("--plane", required=True, metavar="X,Y,Z:NX,NY,NZ",
                   help="the split plane: a point on it and its normal, toward the far part")
    h.add_argument("--feature", required=True, metavar="FaceN|X,Y,Z:AX,AY,AZ",
                   help="a face of the base (a hole's cylinder, or a planar face), or a "
                   "point and an axis")
    h.add_argument("--target", required=True, metavar="X,Y,Z:AX,AY,AZ",
                   help="where the feature's point must land, and its axis there")
    h.add_argument("--out", help="save the document with the new feature here (.FCStd)")
    v = sub.add_parser("solve", help="goal seek: properties that make outputs hit targets",
                       description=SOLVE, formatter_class=fmt)
    v.add_argument("doc", help="the .FCStd document")
    v.add_argument("--vary", action="append", required=True, metavar="OBJ.PROP=LO:HI",
                   help="a property to change and its bounds (repeat for several)")
    goal = v.add_mutually_exclusive_group(required=True)
    goal.add_argument("--target", action="append", metavar="OBJ.OUTPUT=VALUE",
                      help="an output and the value it must reach (repeat for several)")
    goal.add_argument("--minimize", metavar="OBJ.OUTPUT", help="make this output least")
    goal.add_argument("--maximize", metavar="OBJ.OUTPUT", help="make this output greatest")
    v.add_argument("--out", help="save the solved document here (.FCStd)")
    return top


def main(argv=None):
    args = parser().parse_args(argv)
    from . import model  # imports FreeCAD: after --help, which needs none
    try:
        return COMMANDS[args.command](args)
    except model.BatchError as e:
        sys.stderr.write(f"error: {e}\n")
        return 2


def _run(args):
    from . import model, run
    rows, valid = run.run(args.model, args.recipe, args.out, model.formats_of(args.export),
                          stream=sys.stdout)
    return 0 if valid else 1


def _sweep(args):
    from . import model, sweep
    if args.jobs is not None and args.jobs < 1:
        raise model.BatchError("--jobs must be 1 or more.")
    columns, rows = sweep.sweep(args.doc, args.out, args.table, args.grid, args.jobs,
                                args.scheduler, model.formats_of(args.export),
                                args.retry_failed)
    failed = sum(r[-3] != "True" for r in rows)
    print(f"{len(rows)} variants in {args.out}/results.csv: {len(rows) - failed} valid, "
          f"{failed} failed")
    return 0


def _solve(args):
    import os
    from . import model, solve
    vary = solve.parse_ranges(args.vary)
    target = solve.parse_targets(args.target) if args.target else None
    doc = model.open_document(args.doc)
    try:
        found = solve.solve(doc, vary, target, args.minimize, args.maximize)
        if args.out:
            doc.saveAs(os.path.abspath(args.out))
    finally:
        model.App.closeDocument(doc.Name)
    for key in ("iterations", "residual", "minimum", "maximum"):
        if key in found:
            print(f"{key} = {found[key]!r}")
    for name in vary:
        print(f"{name} = {found[name]!r}")
    return 0


def _frame(text, option):
    """"x,y,z:ax,ay,az" -> two 3-vectors."""
    try:
        point, axis = ([float(c) for c in part.split(",")] for part in text.split(":"))
        if len(point) == 3 and len(axis) == 3:
            return point, axis
    except ValueError:
        pass
    from . import model
    raise model.BatchError(f"{option} {text!r} needs x,y,z:ax,ay,az (a point and an axis).")


def _reach(args):
    import os
    from . import model, reach
    plane = _frame(args.plane, "--plane")
    feature = args.feature if ":" not in args.feature else _frame(args.feature, "--feature")
    target = _frame(args.target, "--target")
    doc = model.open_document(args.doc)
    try:
        found = reach.reach(doc, args.base, plane, feature, target)
        if args.out:
            doc.saveAs(os.path.abspath(args.out))
    finally:
        model.App.closeDocument(doc.Name)
    for key, value in found.items():
        print(f"{key} = {value!r}")
    print(f"Method = {found['method']}")
    return 0


COMMANDS = {"run": _run, "sweep": _sweep, "solve": _solve, "reach": _reach}
