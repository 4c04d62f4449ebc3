"""`run`: one document (or a model file and a JSON recipe of make_* calls) recomputed,
exported, and its outputs tabulated: every output property, validity and seconds per
object, printed and saved as DIR/results.csv (object, output, value)."""
import csv
import json
import os
import time

from . import model

App = model.App

SHAPE_FILES = (".step", ".stp", ".brep", ".brp", ".iges", ".igs")
MESH_FILES = (".stl", ".obj", ".ply", ".off")
CLOUD_FILES = (".pcd", ".asc")


def load_model(doc, path):
    """The model file as object "Model": a shape, a mesh or a point cloud."""
    ext = os.path.splitext(path)[1].lower()
    if ext in SHAPE_FILES:
        import Part
        obj = doc.addObject("Part::Feature", "Model")
        obj.Shape = Part.read(path)
    elif ext in MESH_FILES:
        import Mesh
        obj = doc.addObject("Mesh::Feature", "Model")
        obj.Mesh = Mesh.Mesh(path)
    elif ext in CLOUD_FILES:
        import Points
        before = set(doc.Objects)
        Points.insert(path, doc.Name)  # Points.read refuses .pcd on FreeCAD 0.20
        obj = next(o for o in doc.Objects if o not in before)
        obj.Label = "Model"
    else:
        raise model.BatchError(f"{path}: {ext or 'no extension'} is not a model this "
                               f"reads; give a .FCStd document, a STEP/BREP/IGES shape, an "
                               f"STL/OBJ/PLY mesh or a PCD cloud.")
    return obj


def _argument(value):
    """JSON to what make_* takes: [x, y, z] -> Vector; [[x, y, z], [x, y, z]] -> (origin,
    normal) or (point, direction) pairs as tuples of Vectors; anything else as is."""
    def triple(v):
        return (isinstance(v, list) and len(v) == 3
                and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v))
    if triple(value):
        return App.Vector(*value)
    if isinstance(value, list):
        items = [_argument(v) for v in value]
        return tuple(items) if len(value) == 2 and all(map(triple, value)) else items
    return value


def apply_recipe(doc, recipe):
    """Each step {"make": "stretch", "base": "Model", "args": [...], "kwargs": {...},
    "label": "S1"} calls fd.make_stretch(base, *args, **kwargs); then "set":
    {"Object.Property": value} is applied. Returns the objects made."""
    import freecad_deform as fd
    made = []
    for n, step in enumerate(recipe.get("steps", []), 1):
        maker = getattr(fd, f"make_{step.get('make', '')}", None)
        if maker is None:
            raise model.BatchError(f"step {n} of the recipe: make {step.get('make')!r} is "
                                   f"not known; use one of "
                                   f"{', '.join(n[5:] for n in fd.__all__ if n[:5] == 'make_')}.")
        base = model.find_object(doc, step.get("base", "Model"))
        obj = maker(base, *map(_argument, step.get("args", [])),
                    **{k: _argument(v) for k, v in step.get("kwargs", {}).items()})
        if step.get("label"):
            obj.Label = step["label"]
        made.append(obj)
    for path, value in recipe.get("set", {}).items():
        model.set_value(doc, path, value)
    return made


def recompute_timed(doc):
    """Recompute every object, each on its own in dependency order: {Name: seconds}."""
    for obj in doc.Objects:
        obj.touch()
    seconds = {}
    for obj in reversed(doc.TopologicalSortedObjects):
        start = time.perf_counter()
        obj.recompute()
        seconds[obj.Name] = round(time.perf_counter() - start, 3)
    doc.recompute()
    return seconds


def table(doc, seconds):
    """Rows (object, output, value): each output, then valid, seconds and error."""
    outputs = model.output_names(doc)
    rows = []
    for obj in doc.Objects:
        for path in outputs:
            name, (prop,) = model.split_path(path)
            if name == obj.Name:
                rows.append((obj.Name, prop, model.text(model.plain(getattr(obj, prop)))))
        failed = "Invalid" in obj.State or "Error" in obj.State
        shape = getattr(obj, "Shape", None) if not hasattr(obj, "Mesh") else None
        valid = not failed and (shape is None or (not shape.isNull() and shape.isValid()))
        error = obj.getStatusString() if failed else ""
        rows += [(obj.Name, "valid", str(valid)), (obj.Name, "seconds",
                                                  repr(seconds.get(obj.Name, 0.0))),
                 (obj.Name, "error", error)]
    return rows


def run(path, recipe=None, out=".", formats=(), stream=None):
    """Open or build the document, recompute, export, tabulate; returns (rows, valid)."""
    if path.lower().endswith(".fcstd"):
        doc = model.open_document(path)
    else:
        doc = App.newDocument("DeformRun")
        load_model(doc, path)
    try:
        if recipe:
            with open(recipe) as f:
                apply_recipe(doc, json.load(f))
        seconds = recompute_timed(doc)
        rows = table(doc, seconds)
        os.makedirs(out, exist_ok=True)
        with open(os.path.join(out, "results.csv"), "w", newline="") as f:
            csv.writer(f).writerows([("object", "output", "value")] + rows)
        stem = os.path.splitext(os.path.basename(path))[0]
        written = model.export(doc, formats, out, stem)
        valid, _ = model.status(doc)
    finally:
        App.closeDocument(doc.Name)
    if stream is not None:
        width = max((len(f"{o}.{p}") for o, p, _ in rows), default=0)
        for obj, prop, value in rows:
            stream.write(f"{obj + '.' + prop:<{width}}  {value}\n")
        for name in written:
            stream.write(f"wrote {os.path.join(out, name)}\n")
    return rows, valid
