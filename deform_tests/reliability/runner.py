"""Run one reliability case (issue 11) in this process and print its classification.

    /usr/bin/python3 deform_tests/reliability/runner.py '<case JSON>'

The last line of stdout is a JSON object: {"cls": ..., "problems": [...], "objects": [...]}.
The parent (campaign.py) classifies a timeout as a hang and a death as a crash; this
script classifies the rest. A case: {"feature", "base": spec, "params": {...},
"steps": [...], "undo": 0|1}.

Oracles are independent of the code under test: OCCT (isValid, Volume, Area, slice and a
face maker, distToShape, the BOP check), closed forms (A*d, Pappus), the Base's own
geometry and tolerances read before and after.
"""
import json
import math
import os
import re
import sys
import tempfile
import traceback

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
sys.path.insert(0, REPO)
for _path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(_path) and _path not in sys.path:
        sys.path.append(_path)

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import MeshPart  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402
import numpy as np  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.features import base as fbase  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402
from deform_tests.features import fc  # noqa: E402
from deform_tests.oracles.shapes import (closed_mesh, section_area_centroid, solid_volume,  # noqa: E402
                                         surface_area, volume_noise)

V = App.Vector
SEVERITY = ("runner_error", "leftover", "base_changed", "broken_save", "silent_wrong",
            "bad_refusal", "refused", "raised", "accepted")
# text that belongs to OCCT, numpy, C++ or Python internals, never to one of our sentences
RAW = ("::", "Standard_", "NCollection", "BRep", "Courbes", "zero-size array", "has no attribute",
       "Traceback", "StopIteration", "index out of", "invalid bounding box", "not subscriptable",
       "NoneType", "object is not", "unsupported operand", "math domain", "Singular matrix")

FEATURE = {"Stretch": "stretch", "Bend": "bend", "Twist": "twist", "Taper": "taper",
           "DimensionDrive": "dimension_drive", "AreaConstrain": "area_constrain",
           "DirectPush": "direct_push"}
UNBOUNDED = ("Reachable",)
EMPTY_MEANS_ALL = ("Poles",)  # AreaConstrain: no Poles listed frees every interior pole
def _compound():
    """A box, a free face beside it and a loose wire."""
    face = Part.Face(Part.makePolygon([V(-20, 15, -5), V(20, 15, -5), V(20, 15, 5),
                                       V(-20, 15, 5), V(-20, 15, -5)]))
    wire = Part.makePolygon([V(-20, -20, 0), V(0, -20, 3), V(20, -20, 0)])
    return Part.makeCompound([Part.makeBox(40, 20, 10, V(-20, -10, -5)), face, wire])


def _bspline_face():
    pts = [[V(x, y, 2.0 * math.sin(x / 8.0) * math.cos(y / 6.0)) for y in range(-10, 11, 5)]
           for x in range(-20, 21, 5)]
    s = Part.BSplineSurface()
    s.interpolate(pts)
    return s.toShape()


def _bspline_edge():
    c = Part.BSplineCurve()
    c.interpolate([V(x, 3.0 * math.sin(x / 6.0), 0) for x in range(-20, 21, 4)])
    return c.toShape()


def primitive(name):
    """The Base shapes, each about 40 long along x and centred on the origin."""
    box = Part.makeBox(40, 20, 10, V(-20, -10, -5))
    return {
        "box": lambda: box,
        "cylinder": lambda: Part.makeCylinder(8, 40, V(-20, 0, 0), V(1, 0, 0)),
        "cone": lambda: Part.makeCone(10, 0, 40, V(-20, 0, 0), V(1, 0, 0)),
        "sphere": lambda: Part.makeSphere(15),
        "torus": lambda: Part.makeTorus(15, 4),
        "compound": _compound,
        "reversed": lambda: box.reversed(),
        "void": lambda: Part.makeBox(40, 20, 20, V(-20, -10, -10)).cut(Part.makeSphere(5)),
        "face": lambda: box.Faces[4],  # z = -5
        "bspline_face": _bspline_face,
        "wire": lambda: Part.makePolygon([V(-20, 0, 0), V(0, 5, 0), V(20, 0, 3)]),
        "circle": lambda: Part.makeCircle(10),
        "bspline_edge": _bspline_edge,
        "vertex": lambda: Part.Vertex(V(1, 2, 3)),
        "empty": lambda: Part.Shape(),
    }[name]()


def make_base(doc, spec, label="Base"):
    """A document object from {"shape": primitive, "as": "shape" | "mesh" | "points" |
    "degenerate_mesh"}."""
    shape = primitive(spec["shape"])
    kind = spec.get("as", "shape")
    if kind == "shape":
        obj = doc.addObject("Part::Feature", label)
        obj.Shape = shape
        return obj
    if shape.isNull():
        pts, tris = [], []
    elif shape.Faces:  # small: 12 (box) to 1352 (torus) triangles
        m = MeshPart.meshFromShape(Shape=shape, LinearDeflection=0.5, AngularDeflection=0.5)
        pts = [p.Vector for p in m.Points]
        tris = [f.PointIndices for f in m.Facets]
    else:
        pts, tris = shape.discretize(20) if shape.Edges else [shape.Vertexes[0].Point], []
    if kind == "points":
        obj = doc.addObject("Points::Feature", label)
        obj.Points = Points.Points([tuple(p) for p in pts])
        return obj
    mesh = Mesh.Mesh([[tuple(pts[i]) for i in t] for t in tris]) if tris else Mesh.Mesh()
    if kind == "degenerate_mesh" and tris:  # a zero-area sliver on top of the mesh
        a, b = pts[tris[0][0]], pts[tris[0][1]]
        mesh.addFacet(V(*a), V(*b), (V(*a) + V(*b)) * 0.5)
    obj = doc.addObject("Mesh::Feature", label)
    obj.Mesh = mesh
    return obj


def snapshot(obj):
    """What must stay of a Base: geometry and tolerances (exact numbers)."""
    if obj.isDerivedFrom("Mesh::Feature"):
        return {"points": [tuple(p.Vector) for p in obj.Mesh.Points],
                "facets": [tuple(f.PointIndices) for f in obj.Mesh.Facets]}
    if obj.isDerivedFrom("Points::Feature"):
        return {"points": [tuple(p) for p in obj.Points.Points]}
    s = obj.Shape
    if s.isNull():
        return {"null": True}
    return {"vertices": [tuple(v.Point) for v in s.Vertexes],
            "volume": s.Volume if s.Solids else None,
            "tolerances": [v.Tolerance for v in s.Vertexes] + [e.Tolerance for e in s.Edges]
            + [f.Tolerance for f in s.Faces],
            "orientation": [f.Orientation for f in s.Faces]}


# ---------------------------------------------------------------- cases

def vec(v):
    return V(*[float(x) for x in v])


def plane(p):
    return (vec(p["o"]), vec(p["n"]))


def make(doc, base, case):
    f, p = case["feature"], case["params"]
    if f == "stretch":
        return fd.make_stretch(base, plane(p["plane"]), p["distance"],
                               plane2=plane(p["plane2"]) if p.get("plane2") else None)
    if f == "bend":
        return fd.make_bend(base, plane(p["plane"]), p["angle"], plane(p["axis"]),
                            plane2=plane(p["plane2"]) if p.get("plane2") else None)
    if f == "twist":
        return fd.make_twist(base, plane(p["plane"]), plane(p["plane2"]), p["angle"],
                             axis=plane(p["axis"]) if p.get("axis") else None)
    if f == "taper":
        return fd.make_taper(base, plane(p["plane"]), plane(p["plane2"]), p["scale"])
    if f == "dimension_drive":
        target = p["target"] if p["kind"] != "Position" else tuple(p["target"])
        return fd.make_dimension_drive(base, p["kind"], p["regions"], target,
                                       **p.get("options", {}))
    if f == "area_constrain":
        return fd.make_area_constrain(base, p["face"], p["target"], poles=p.get("poles"),
                                      dof=p.get("dof", "Normal"), **p.get("options", {}))
    if f == "direct_push":
        options = dict(p.get("options", {}))
        if "fixed" in options:
            options["fixed"] = [on_element(base, p["element"], options["fixed"]["uv"])]
        point = on_element(base, p["element"], p["point"]["uv"])
        return fd.make_direct_push(base, p["element"], point, point + vec(p["offset"]),
                                   **options)
    raise ValueError(f"unknown feature {f}")


def on_element(base, element, uv):
    """The point at fractions `uv` of the element's parameter range (the origin when the
    Base has no such element)."""
    try:
        e = base.Shape.getElement(element)
    except Exception:  # no such element: the feature must refuse it
        return V(0, 0, 0)
    if e.ShapeType == "Edge":
        a, b = e.ParameterRange
        return e.valueAt(a + uv[0] * (b - a))
    u0, u1, v0, v1 = e.ParameterRange
    return e.valueAt(u0 + uv[0] * (u1 - u0), v0 + uv[1] * (v1 - v0))


def placement(p):
    """A plane as a Placement (local Z the normal), and a turn about it when given."""
    rot = App.Rotation(V(0, 0, 1), vec(p["n"]))
    if "turn" in p:
        rot = App.Rotation(vec(p["n"]), p["turn"]).multiply(rot)
    return App.Placement(vec(p["o"]), rot)


def assign(obj, name, value):
    if isinstance(value, dict) and "o" in value:
        value = placement(value)
    elif isinstance(value, list) and value and isinstance(value[0], dict):
        value = [placement(v) for v in value]
    elif isinstance(value, list) and value and isinstance(value[0], list):
        value = [vec(v) for v in value]
    setattr(obj, name, value)


def is_feature(obj):
    return hasattr(obj, "Proxy") and isinstance(getattr(obj, "Proxy", None),
                                                fbase.DeformFeature)


def result_of(obj):
    if obj.isDerivedFrom("Mesh::Feature"):
        return obj.Mesh
    if obj.isDerivedFrom("Points::Feature"):
        return obj.Points
    return obj.Shape


def measure(obj):
    """A fingerprint of a feature's result, to see whether it changes when it must not."""
    r = result_of(obj)
    if obj.isDerivedFrom("Part::Feature"):
        return None if r.isNull() else (round(r.Volume, 6), round(r.Area, 6), len(r.Vertexes))
    return (r.CountPoints, round(float(np.abs(np.array([tuple(getattr(q, "Vector", q))
                                                        for q in r.Points])).sum()), 6)
            if r.CountPoints else 0)


def outputs_finite(obj):
    bad = []
    for p in obj.Proxy.PROPERTIES:
        if not p.output:
            continue
        v = getattr(obj, p.name)
        vals = v if isinstance(v, (list, tuple)) else [v]
        # NaN is never a value; an infinite Reachable says the dimension has no limit
        if any(isinstance(x, float) and (math.isnan(x) or math.isinf(x) and p.name not in
                                         UNBOUNDED) for x in vals):
            bad.append(p.name)
    return bad


def oracle(obj, case):
    """Problems of an accepted result ([] when it passes)."""
    problems = []
    base = obj.Base
    r = result_of(obj)
    if obj.isDerivedFrom("Part::Feature"):
        if r.isNull():
            return ["result shape is null"]
        if not r.isValid():
            problems.append("result fails isValid()")
        pts = np.array([tuple(v.Point) for v in r.Vertexes]).reshape(-1, 3)
        if not np.isfinite(pts).all() or not math.isfinite(r.Area):
            problems.append("result has non-finite vertices or area")
        for s in r.Solids:
            if s.Volume < 0:
                problems.append("a result solid is reversed (negative volume)")
                break
    else:
        pts = np.array([tuple(getattr(q, "Vector", q)) for q in r.Points]).reshape(-1, 3)
        if not np.isfinite(pts).all():
            problems.append("result has non-finite points")
        if obj.isDerivedFrom("Mesh::Feature") and base is not None and \
                base.isDerivedFrom("Mesh::Feature") and closed_mesh(base.Mesh) and \
                not closed_mesh(r):
            problems.append("mesh base was closed, result is not")
    bad = outputs_finite(obj)
    if bad:
        problems.append(f"outputs not finite: {bad}")
    if problems or base is None or not base.isDerivedFrom("Part::Feature"):
        return problems + _mesh_invariants(obj, case, pts)
    return problems + _invariants(obj, case, base.Shape.copy(), r.copy())  # OCCT may retouch


def _rel(a, b, scale, tol):
    return abs(a - b) <= tol * max(scale, 1e-9)


def _invariants(obj, case, before, after):
    """The feature's invariant, where cheap: Stretch A*d, Bend Pappus, Twist volume,
    DirectPush targets reached, AreaConstrain area met; no self-intersection (OCCT's BOP
    check) where a turn, scale or push can cause one."""
    f = FEATURE[obj.Proxy.TYPE]
    plain = not len(getattr(obj, "KeyPlacements", []))
    if f in ("stretch", "bend") and plain and not obj.UsePlane2 and before.Solids and \
            (f == "bend" or not len(obj.Polyline)):
        origin = tuple(obj.Plane.Base)
        normal = tuple(obj.Plane.Rotation.multVec(V(0, 0, 1)))
        area, centroid = section_area_centroid(before, origin, normal)
        v0, v1 = solid_volume(before), sum(s.Volume for s in after.Solids)
        if f == "stretch":
            d = obj.Distance.Value
            if d > 1e-7 and area > 0:
                want = v0 + area * d
                if not _rel(v1, want, v0 + area * d, 1e-6) and abs(v1 - want) > 1e-6 * (
                        v0 + area * d) + 2 * (volume_noise(before, origin, normal)
                                              + volume_noise(after, origin, normal)):
                    return [f"stretch volume {v1!r} != V + A*d = {want!r} (A {area})"]
        elif centroid is not None and abs(obj.Angle.Value) > 1e-7:
            a = obj.Axis
            p, u = np.array(tuple(a.Base)), np.array(tuple(a.Rotation.multVec(V(0, 0, 1))))
            w = centroid - p
            radius = np.linalg.norm(w - (w @ u) * u)
            want = v0 + area * math.radians(abs(obj.Angle.Value)) * radius
            if not _rel(v1, want, want, 1e-6) and abs(v1 - want) > 1e-6 * want + 2 * (
                    volume_noise(before, origin, normal)):
                return [f"bend volume {v1!r} != V + Pappus = {want!r}"]
    if f == "twist" and before.Solids:
        v0, v1 = solid_volume(before), sum(s.Volume for s in after.Solids)
        # the refitted faces may deviate by Tolerance: that much times the area
        slack = 1e-6 * v0 + max(obj.MaxDeviation, obj.Tolerance.Value) * after.Area
        if abs(v1 - v0) > slack:
            return [f"twist volume {v1!r} != base volume {v0!r} (slack {slack:.3g})"]
    if f in ("bend", "twist", "taper", "direct_push"):
        for k, solid in enumerate(after.Solids):
            try:  # a turn, a scale or a push can fold a solid into itself
                solid.check(True)
            except (ValueError, Part.OCCError) as e:
                return [f"BOP check of solid {k + 1}: {' '.join(str(e).split())[:120]}"]
    if f == "direct_push":
        problems = []
        for t in obj.Targets:
            d = after.distToShape(Part.Vertex(t))[0]
            if d > 1e-6:
                problems.append(f"target {tuple(t)} missed by {d:.3g}")
        return problems
    if f == "area_constrain":
        target = obj.TargetRatio * obj.OriginalArea if obj.TargetRatio else obj.TargetArea.Value
        index = int(obj.Face[4:]) - 1
        face = after.Faces[index] if obj.Replaced else after.Faces[0]
        got = surface_area(face)
        if not _rel(got, target, target, 1e-6):
            where = f"Face{index + 1}" if obj.Replaced else "the face"
            return [f"area {got!r} (quadrature of {where}) != target {target!r}"]
    return []


def _mesh_invariants(obj, case, pts):
    """DimensionDrive on the box (Distance along an axis) and cylinder (Radius): the
    mesh's own extent after the drive."""
    if FEATURE[obj.Proxy.TYPE] != "dimension_drive" or "Invalid" in obj.State or not len(pts):
        return []
    p = case["params"]
    shape = case["base"]["shape"]
    target = obj.Target.Value
    if p["kind"] == "Distance" and shape == "box" and obj.Base.isDerivedFrom("Mesh::Feature"):
        a, b = np.array(p["regions"][0]), np.array(p["regions"][1])
        axis = int(np.argmax(np.abs(a - b)))
        got = pts[:, axis].max() - pts[:, axis].min()
        if abs(got - abs(target)) > 1e-4 * max(1.0, abs(target)):
            return [f"distance {got!r} != Target {target!r}"]
    if p["kind"] == "Radius" and shape == "cylinder":
        got = np.hypot(pts[:, 1], pts[:, 2]).max()
        if abs(got - target) > 1e-4 * max(1.0, target):
            return [f"radius {got!r} != Target {target!r}"]
    return []


def _nonfinite(value):
    if isinstance(value, (list, tuple)):
        return any(_nonfinite(v) for v in value)
    if hasattr(value, "Rotation"):
        return _nonfinite(tuple(value.Base)) or _nonfinite(tuple(value.Rotation.Q))
    if hasattr(value, "x") and hasattr(value, "z"):
        return _nonfinite((value.x, value.y, value.z))
    value = getattr(value, "Value", value)  # PropertyLength clamps inf to the largest float
    return isinstance(value, float) and not (math.isfinite(value) and abs(value) < 1.7e308)


def expected(obj):
    """The properties a refusal of `obj` must name, when it has a sure cause: those holding
    NaN or infinity, and Base when it is the object itself or depends on it."""
    out = [p.name for p in obj.Proxy.PROPERTIES if not p.output and p.name != "Base"
           and not isinstance(getattr(obj, p.name), str) and _nonfinite(getattr(obj, p.name))]
    base = obj.Base
    try:
        cyclic = base is not None and (base == obj or obj in base.OutListRecursive)
    except IndexError:  # FreeCAD: cyclic dependency detected
        cyclic = True
    return out + (["Base"] if cyclic else [])


def refusal_problem(obj, case):
    """None for a clean refusal: our DeformError, naming a property of the object that the
    message contains (one of expected(obj) when the object has a sure cause)."""
    message = obj.getStatusString()
    exc = fc.RAISED.get(obj.Name)
    kind, prop = (None, None) if exc is None else (type(exc).__name__, getattr(exc, "prop", None))
    names = set(obj.PropertiesList)
    base = getattr(obj, "Base", None)
    if (exc is None or str(exc) != message) and base is not None and base != obj and \
            "Invalid" in base.State:
        return None  # FreeCAD's own verdict ("Error") on an object whose Base failed
    if not message.strip():
        return "empty status message"
    if kind != "DeformError":
        return f"{kind or 'not our'} error: {message[:160]}"
    if prop not in names or prop not in message:
        return f"message does not name its property {prop!r}: {message[:160]}"
    if any(r in message for r in RAW):
        return f"raw text in message: {message[:160]}"
    own, text = obj.Proxy.TYPE.lower(), message
    for o in obj.Document.Objects:  # labels ("Stretch001") are names, not words
        text = text.replace(o.Label, "")
    # pointing to the feature that does what was asked ("use Twist to turn about the
    # normal") is advice, not another feature's words
    text = re.sub(r"\buse (Stretch|Bend|Twist|Taper)\b", "", text)
    foreign = [w for w in ("stretch", "bend", "twist", "taper") if w != own
               and re.search(rf"\b{w}\b", text.lower())]
    if foreign:  # e.g. "a stretch needs parallel planes" from a Bend
        return f"speaks of a {foreign[0]}: {message[:160]}"
    lists = [n for n in names if n != prop and n not in EMPTY_MEANS_ALL
             and re.search(rf"\b{n}\b", message) and isinstance(getattr(obj, n), list)]
    empty = [n for n in lists if not getattr(obj, n)]
    if empty and len(empty) == len(lists):  # it blames only what the object does not have
        return f"blames {empty}, which the object does not have: {message[:160]}"
    expect = expected(obj)
    if expect and prop not in expect:
        return f"names {prop}, expected one of {expect}: {message[:160]}"
    return None


# ---------------------------------------------------------------- steps

def leftovers(doc, names, base_obj, shown):
    problems = []
    now = [o.Name for o in doc.Objects]
    if now != names:
        problems.append(f"objects left behind: {sorted(set(now) - set(names))}")
    if doc.HasPendingTransaction or App.getActiveTransaction():
        problems.append("transaction left open")
    if base_obj.Visibility != shown:
        problems.append("Base left hidden")
    return problems


def run(case):
    out = {"problems": [], "objects": []}
    problem = out["problems"].append
    doc = App.newDocument("Reliability")
    doc.UndoMode = case.get("undo", 1)
    base = make_base(doc, case["base"])
    bases = {base.Name: (base, snapshot(base))}
    names = [o.Name for o in doc.Objects]
    try:
        obj = make(doc, base, case)
    except Exception as e:  # the make_* refused: the document must be as it was
        out["raised"] = f"{type(e).__name__}: {e}"[:200]
        for p in leftovers(doc, names, base, True):
            problem(("leftover", p))
        if isinstance(e, DeformError) and (not e.prop or e.prop not in str(e)):
            problem(("bad_refusal", f"make_* raised without naming its property: {e}"))
        elif not isinstance(e, (DeformError, TypeError, ValueError)):
            problem(("bad_refusal", f"make_* raised {type(e).__name__}: {e}"))
        _check_bases(bases, problem)
        return out, "raised"
    case["_main"] = obj.Name
    if App.getActiveTransaction() or doc.HasPendingTransaction:
        problem(("leftover", "make_* left a transaction open"))
    for step in case.get("steps", []):
        doc, obj = _step(doc, obj, step, case, bases, names, problem)
        if obj is None:
            break
    _check_bases(bases, problem)
    features = [o for o in doc.Objects if is_feature(o)]
    for o in features:
        out["objects"].append(judge(o, case, problem))
    refused = any(e.get("refused") for e in out["objects"])
    return out, "refused" if refused else "accepted"


def judge(o, case, problem):
    """The entry of feature `o` as it stands: a refusal must name its property, an
    Up-to-date result must pass the oracle."""
    state = list(o.State)
    entry = {"name": o.Name, "state": state, "message": o.getStatusString()[:200]}
    if "Invalid" in state or "Error" in state:
        why = refusal_problem(o, case)
        entry["refused"] = True
        if why:
            problem(("bad_refusal", f"{o.Name}: {why}"))
    elif o.Base is not None and "Touched" not in state:
        for p in oracle(o, case):
            problem(("silent_wrong", f"{o.Name}: {p}"))
    return entry


def same(a, b, rel):
    """Equal up to `rel` (relative, with 1 as the smallest scale): a saved document
    rounds coordinates to 15 digits."""
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same(x, y, rel) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float):
        return abs(a - b) <= rel * max(1.0, abs(a)) if abs(a) >= 1 else \
            abs(a - b) <= rel * max(abs(a), 1e-3)
    return a == b


def _check_bases(bases, problem):
    for name, (b, snap) in bases.items():
        try:
            now = snapshot(b)
        except ReferenceError:  # removed by undo: nothing to compare
            continue
        what = [k for k in snap if not same(now.get(k), snap.get(k), 1e-12 if k != "volume"
                                            else 1e-9)]
        if what:
            problem(("base_changed", f"{name}: {what} changed"))


def _step(doc, obj, step, case, bases, names, problem):
    """Apply one step; returns the (possibly reopened) document and main object (None to
    stop)."""
    kind = step["do"]
    if kind == "set":
        for name, value in step["values"].items():
            try:
                assign(obj, name, value)
            except Exception as e:  # a property that refuses the value itself (enumerations)
                step.setdefault("refused_by_property", []).append(f"{name}: {e}"[:120])
                continue
            held = getattr(obj, name)
            held = getattr(held, "Value", held)
            # FreeCAD's PropertyLength holds no negative value (0 instead), PropertyAngle
            # (Bend's Angle) nothing beyond +-360 deg: not ours
            kind_of = obj.getTypeIdOfProperty(name)
            clamped = ("Length" in kind_of and held == 0 and value < 0) or (
                "Angle" in kind_of and abs(held) == 360.0 and abs(value) > 360.0)
            if isinstance(value, (int, float)) and isinstance(held, (int, float)) and \
                    math.isfinite(value) and held != value and not clamped:
                problem(("silent_wrong", f"{name} set to {value!r} holds {held!r}"))
        doc.recompute()
        judge(obj, case, problem)  # what each step leaves must hold too, not only the last
    elif kind == "self_link":
        before = measure(obj)
        obj.Base = obj
        for _ in range(3):
            obj.touch()
            doc.recompute()
        if measure(obj) != before:
            problem(("silent_wrong", f"self-linked result changed: {before} -> {measure(obj)}"))
    elif kind == "cycle":
        try:  # a second feature on this one, then this one on it
            other = fd.make_stretch(obj, (V(0, 0, 0), V(1, 0, 0)), 5)
        except DeformError as e:  # nothing to stretch (this one holds no result yet)
            if "Base" not in str(e):
                problem(("bad_refusal", f"make_stretch on {obj.Name}: {e}"))
            return doc, obj
        names.append(obj.Name)  # undo now takes back the other feature, not this one
        doc.recompute()
        before = (measure(obj), measure(other))
        obj.Base = other
        for _ in range(2):
            obj.touch()
            doc.recompute()
        after = (measure(obj), measure(other))
        if after != before:
            problem(("silent_wrong", f"cycle grew: {before} -> {after}"))
    elif kind == "rebase":
        new = make_base(doc, step["base"], "Rebase")
        names.append(new.Name)  # the case's own object: undo keeps it
        bases[new.Name] = (new, snapshot(new))
        obj.Base = new
        doc.recompute()
    elif kind == "undo_redo":
        if doc.UndoMode == 0:
            return doc, obj
        name = obj.Name
        doc.undo()
        now = [o.Name for o in doc.Objects]
        if now != names:
            problem(("leftover", f"after undo the document holds {now}, not {names}"))
        doc.redo()
        obj = doc.getObject(name)
        if obj is None:
            problem(("leftover", "redo did not bring the feature back"))
            return doc, None
        doc.recompute()
    elif kind == "save_reopen":
        doc.recompute()
        before = {o.Name: (measure(o), list(o.State)) for o in doc.Objects if is_feature(o)}
        path = os.path.join(tempfile.mkdtemp(), "case.FCStd")
        name = obj.Name
        try:
            doc.saveAs(path)
            App.closeDocument(doc.Name)
            doc = App.openDocument(path)
            doc.recompute()
        except Exception as e:
            problem(("broken_save", f"{type(e).__name__}: {e}"[:200]))
            return doc, None
        for n, (m, state) in before.items():
            o = doc.getObject(n)
            if o is None:
                problem(("broken_save", f"{n} missing after reopen"))
            elif "Invalid" not in state and "Invalid" not in o.State and measure(o) != m:
                problem(("silent_wrong", f"{n} reopened as {measure(o)}, saved {m}"))
        for n, (b, snap) in list(bases.items()):
            bases[n] = (doc.getObject(n), snap)
        obj = doc.getObject(name)
    return doc, obj


def main():
    case = json.loads(sys.argv[1])
    try:
        with fc.recorded_errors():
            out, default = run(case)
    except Exception:
        out, default = {"problems": [("runner_error", traceback.format_exc()[-600:])]}, None
    classes = [c for c, _ in out["problems"]] + ([default] if default else [])
    out["cls"] = min(classes, key=SEVERITY.index)
    out["problems"] = [f"{c}: {p}" for c, p in out["problems"]]
    sys.stdout.write("\n" + json.dumps(out) + "\n")
    sys.stdout.flush()
    os._exit(0)  # skip FreeCAD's teardown: a crash there is not the case's


if __name__ == "__main__":
    main()
