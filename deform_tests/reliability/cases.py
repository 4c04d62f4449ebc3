"""The reliability campaign's cases (issue 11): hypothesis strategies over every feature's
properties and Bases, and the issue's own cases as fixed examples.

A case is JSON (runner.py runs it in its own process): {"feature", "base": {"shape",
"as"}, "params": {...}, "steps": [...], "undo": 0|1, "expect": [...]}. `expect` lists the
properties the case put a NaN or infinite value in (for reading; the runner finds what a
refusal must name from the object itself at the end).
"""
import math

from hypothesis import strategies as st

NAN, INF = float("nan"), float("inf")
SPECIAL = (0.0, -0.0, 1e-12, -1e-12, 1e-7, 1e-3, 1e6, 1e12, -1e6, NAN, INF, -INF)
SOLIDS = ("box", "cylinder", "cone", "sphere", "torus", "compound", "reversed", "void")
SHAPES = SOLIDS + ("face", "bspline_face", "wire", "vertex", "empty")


def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def all_finite(value):
    """False if a number anywhere in `value` (nested lists and dicts) is NaN or infinite."""
    if isinstance(value, dict):
        return all(all_finite(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(all_finite(v) for v in value)
    return not isinstance(value, float) or math.isfinite(value)


def number(lo, hi, extra=()):
    """Ordinary values in [lo, hi] (three draws in four) and the hostile ones: zero, tiny,
    huge, NaN, infinite."""
    ordinary = st.floats(lo, hi, allow_nan=False)
    return st.one_of(ordinary, ordinary, ordinary, st.sampled_from(SPECIAL + extra))


def bases(kinds=("shape", "mesh", "points")):
    """A primitive as a shape, or tessellated into a small mesh or point cloud."""
    solids = st.sampled_from([{"shape": s} for s in SOLIDS])
    return st.one_of(solids, solids, st.builds(lambda s, a: {"shape": s, "as": a},
                                               st.sampled_from(SHAPES), st.sampled_from(kinds)),
                     st.just({"shape": "box", "as": "degenerate_mesh"}))


NORMALS = ((1, 0, 0), (1, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 0.2, 0.1),
           (-1, 0, 0), (0, 0, 0), (NAN, 0, 0))


@st.composite
def plane(draw, offset=None):
    """(origin, normal): the origin `offset` along the normal from the centre; offsets near
    the parts' ends (20), a cone's apex (20 - 1e-6), beyond, or not finite."""
    n = draw(st.sampled_from(NORMALS))
    if offset is None:
        offset = draw(st.one_of(st.floats(-25, 25), st.sampled_from(
            (0.0, 20.0, -20.0, 20 - 1e-6, 20 - 1e-8, 5.0, NAN, INF))))
    length = math.sqrt(sum(c * c for c in n)) if all(map(finite, n)) else 0.0
    unit = [c / length for c in n] if length else [1.0, 0.0, 0.0]
    return {"o": [offset * c for c in unit], "n": list(n)}


def _plane_expect(p, name):
    return [] if all(map(finite, p["o"] + p["n"])) else [name]


SAMPLES = (-5, 0, 1, 2, 16, 64, 200, 201, 10 ** 6)
# Case 3 separating polylines (in the xz plane, extruded along y): a fold, a point, NaN
POLYLINES = ([[-5, 0, -10], [0, 0, 0], [5, 0, 10]], [[0, 0, 0]], [[0, 0, 0], [0, 0, 0]],
             [[0, 0, -10], [NAN, 0, 10]], [])


def keys():
    """KeyPlacements: a few placements on the way (one far off, one turned, NaN)."""
    key = st.builds(lambda x, t: {"o": [x, 0.0, 0.0], "n": [1, 0, 0], "turn": t},
                    number(-10, 30), number(-90, 90))
    return st.lists(key, max_size=3)


@st.composite
def set_step(draw, props):
    """After creation, a property set to a hostile value."""
    name, values = draw(st.sampled_from(props))
    value = draw(values)
    step = {"do": "set", "values": {name: value}}
    if not all_finite(value):
        step["expect"] = [name]
    return step


def steps(props):
    """0 to 2 of: a property set, a self-link, a cycle, a Base of another kind, undo/redo,
    save and reopen."""
    one = st.one_of(set_step(props), st.just({"do": "self_link"}), st.just({"do": "cycle"}),
                    bases().map(lambda b: {"do": "rebase", "base": b}),
                    st.just({"do": "undo_redo"}), st.just({"do": "save_reopen"}))
    return st.lists(one, max_size=2)


def _finish(feature, base, params, expect, step_list, undo):
    for s in step_list:
        expect = expect + s.pop("expect", [])
    return {"feature": feature, "base": base, "params": params, "steps": step_list,
            "undo": undo, "expect": sorted(set(expect))}


ANGLES = (360.0, 720.0, -720.0, 1e6, 90.0, -90.0)
# the distance between Plane and Plane2: ordinary first (hypothesis's simplest draws come
# from the first branch), then the hostile ones
GAP = st.one_of(st.floats(2, 30), number(-5, 30))


@st.composite
def stretch(draw):
    p = draw(plane())
    params = {"plane": p, "distance": draw(number(-60, 60))}
    expect = _plane_expect(p, "Plane") + ([] if finite(params["distance"]) else ["Distance"])
    if draw(st.booleans()) and draw(st.booleans()):
        gap = draw(number(-5, 30))
        params["plane2"] = p2 = {"o": [o + gap * c for o, c in zip(p["o"], [1, 0, 0])],
                                 "n": p["n"]}
        expect += _plane_expect(p2, "Plane2")
    props = [("Distance", number(-60, 60)), ("Samples", st.sampled_from(SAMPLES)),
             ("Plane", plane()), ("KeyPlacements", keys()),
             ("Interpolation", st.sampled_from(("Screw", "Rational", "Bogus"))),
             ("Polyline", st.sampled_from(POLYLINES))]
    return _finish("stretch", draw(bases()), params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


@st.composite
def bend(draw):
    p = draw(plane())
    r = draw(st.one_of(st.floats(-40, 40), st.sampled_from((0.0, 5.0, 30.0, NAN, 1e9))))
    direction = draw(st.sampled_from(((0, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 0, 0))))
    axis = {"o": [p["o"][0], 0.0, r], "n": list(direction)}
    params = {"plane": p, "angle": draw(number(-400, 400, ANGLES)), "axis": axis}
    expect = _plane_expect(p, "Plane") + _plane_expect(axis, "Axis") + (
        [] if finite(params["angle"]) else ["Angle"])
    props = [("Angle", number(-400, 400, ANGLES)), ("Samples", st.sampled_from(SAMPLES)),
             ("KeyPlacements", keys()), ("Tolerance", number(0, 1)),
             ("Profile", st.sampled_from(("Linear", "Smooth", "Bogus")))]
    return _finish("bend", draw(bases()), params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


@st.composite
def twist(draw):
    p = draw(plane(offset=draw(st.floats(-15, 5))))
    gap = draw(GAP)
    p2 = {"o": [p["o"][0] + gap, p["o"][1], p["o"][2]], "n": p["n"]}
    params = {"plane": p, "plane2": p2,
              "angle": draw(st.one_of(st.floats(5, 170), number(-400, 400, ANGLES)))}
    expect = _plane_expect(p, "Plane") + _plane_expect(p2, "Plane2") + (
        [] if finite(params["angle"]) else ["Angle"])
    if draw(st.booleans()):
        direction = draw(st.sampled_from(((1, 0, 0), (1, 0, 1), (0, 1, 0), (1, 1e-9, 0))))
        params["axis"] = {"o": [0.0, draw(st.floats(-5, 5)), 0.0], "n": list(direction)}
    props = [("Angle", number(-400, 400, ANGLES)),
             ("Turns", st.sampled_from((-3, 0, 2, 10 ** 6))),
             ("Samples", st.sampled_from(SAMPLES)), ("Tolerance", number(0, 1)),
             ("Profile", st.sampled_from(("Linear", "Smooth", "Bogus"))),
             ("UseAxis", st.booleans())]
    return _finish("twist", draw(bases()), params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


@st.composite
def taper(draw):
    p = draw(plane(offset=draw(st.floats(-15, 5))))
    gap = draw(GAP)
    p2 = {"o": [p["o"][0] + gap, p["o"][1], p["o"][2]], "n": p["n"]}
    params = {"plane": p, "plane2": p2,
              "scale": draw(st.one_of(st.floats(0.3, 3), number(-2, 3)))}
    expect = _plane_expect(p, "Plane") + _plane_expect(p2, "Plane2") + (
        [] if finite(params["scale"]) else ["Scale"])
    return _finish("taper", draw(bases()), params, expect, draw(steps([
        ("Scale", number(-2, 3))])), draw(st.sampled_from((0, 1))))


DD_BASES = ({"shape": "box", "as": "mesh"}, {"shape": "box", "as": "mesh"},
            {"shape": "cylinder", "as": "mesh"}, {"shape": "box"},
            {"shape": "box", "as": "degenerate_mesh"}, {"shape": "box", "as": "points"},
            {"shape": "face"}, {"shape": "empty"}, {"shape": "torus", "as": "mesh"})


@st.composite
def dimension_drive(draw):
    kind = draw(st.sampled_from(("Distance", "Distance", "Radius", "Position")))
    base = draw(st.sampled_from(DD_BASES))
    if kind == "Distance":
        regions = draw(st.sampled_from(([[0, 0, 5], [0, 0, -5]], [[20, 0, 0], [-20, 0, 0]],
                                        [[0, 0, 5], [20, 0, 0]], [[0, 0, 5], [0, 0, 5]])))
        target = draw(number(-20, 80))
    elif kind == "Radius":
        regions = [[0, 8, 0]]
        target = draw(number(-5, 30))
        base = draw(st.sampled_from(({"shape": "cylinder", "as": "mesh"}, base)))
    else:
        regions = [[0, 0, -5], [5, 0, 5]]
        target = [draw(number(-20, 20)), draw(number(-20, 20))]
    params = {"kind": kind, "regions": regions, "target": target}
    values = target if isinstance(target, list) else [target]
    expect = [] if all(map(finite, values)) else ["Target", "TargetV"]
    options = {}
    if draw(st.booleans()):
        options["feature_angle"] = draw(st.sampled_from((0.0, 30.0, 180.0, NAN)))
        expect += [] if finite(options["feature_angle"]) else ["FeatureAngle"]
    if draw(st.booleans()):
        options["handle_tolerance"] = draw(st.sampled_from((0.0, 1e-9, 1e6, INF)))
        expect += [] if finite(options["handle_tolerance"]) else ["HandleTolerance"]
    params["options"] = options
    props = [("Target", number(-20, 80)), ("FeatureAngle", number(-10, 200)),
             ("Tolerance", number(0, 5))]
    return _finish("dimension_drive", base, params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


AC_BASES = ({"shape": "bspline_face"}, {"shape": "bspline_face"}, {"shape": "box"},
            {"shape": "sphere"}, {"shape": "cylinder"}, {"shape": "torus"},
            {"shape": "face"}, {"shape": "box", "as": "mesh"}, {"shape": "wire"},
            {"shape": "empty"}, {"shape": "void"})


@st.composite
def area_constrain(draw):
    base = draw(st.sampled_from(AC_BASES))
    face = draw(st.sampled_from(("Face1", "Face1", "Face1", "Face3", "Face99", "Edge1", "")))
    target = draw(st.one_of(st.sampled_from(("105%", "95%", "100%", "0%", "-5%", "1e9%")),
                            number(0, 3000)))
    poles = draw(st.sampled_from((None, None, [[2, 2]], [[3, 3], [3, 4]], [[0, 0]],
                                  [[99, 99]], [[1, 1]])))
    dof = draw(st.sampled_from(("Normal", "Normal", "Z", "Free", "Sideways")))
    params = {"face": face, "target": target, "poles": poles, "dof": dof}
    if draw(st.booleans()):
        params["options"] = {"method": draw(st.sampled_from(("Penalty", "Lagrange-Newton",
                                                              "Bogus")))}
    expect = [] if isinstance(target, str) or finite(target) else ["TargetArea"]
    props = [("TargetArea", number(0, 3000)), ("TargetRatio", number(-1, 3))]
    return _finish("area_constrain", base, params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


DP_BASES = (({"shape": "circle"}, "Edge1"), ({"shape": "bspline_edge"}, "Edge1"),
            ({"shape": "wire"}, "Edge2"), ({"shape": "bspline_face"}, "Face1"),
            ({"shape": "box"}, "Face6"), ({"shape": "box"}, "Face1"),
            ({"shape": "cylinder"}, "Face1"), ({"shape": "sphere"}, "Face1"),
            ({"shape": "box", "as": "mesh"}, "Face1"), ({"shape": "empty"}, "Edge1"),
            ({"shape": "compound"}, "Face7"), ({"shape": "box"}, "Face99"))


@st.composite
def direct_push(draw):
    base, element = draw(st.sampled_from(DP_BASES))
    uv = [draw(st.floats(0, 1)), draw(st.floats(0, 1))]
    offset = [draw(number(-5, 5)) if draw(st.booleans()) else 0.0 for _ in range(2)] + [
        draw(number(-15, 15))]
    params = {"element": element, "point": {"uv": uv}, "offset": offset}
    options = {}
    if draw(st.booleans()):
        options["range"] = draw(st.sampled_from((-1, 0, 1, 2, 3, 4, 8, 20, 49)))
    if draw(st.booleans()) and draw(st.booleans()):
        options["fixed"] = {"uv": [draw(st.floats(0, 1)), draw(st.floats(0, 1))]}
    params["options"] = options
    expect = [] if all(map(finite, offset)) else ["Targets"]
    props = [("Range", st.sampled_from((-1, 0, 2, 8, 49)))]
    return _finish("direct_push", base, params, expect, draw(steps(props)),
                   draw(st.sampled_from((0, 1))))


STRATEGIES = {"stretch": stretch, "bend": bend, "twist": twist, "taper": taper,
              "dimension_drive": dimension_drive, "area_constrain": area_constrain,
              "direct_push": direct_push}


def _p(o, n=(1, 0, 0)):
    return {"o": list(o), "n": list(n)}


def fixed(feature, base, params, steps=(), expect=(), undo=1, name=None):
    return {"feature": feature, "base": base, "params": params, "steps": list(steps),
            "undo": undo, "expect": list(expect), "name": name}


BOX, X0 = {"shape": "box"}, _p((0, 0, 0))
# the issue's cases, each one fixed example of the campaign
ISSUE = [
    fixed("stretch", BOX, {"plane": X0, "distance": 5}, [{"do": "self_link"}],
          name="self-link"),
    fixed("stretch", BOX, {"plane": X0, "distance": 5}, [{"do": "cycle"},
                                                         {"do": "save_reopen"}],
          name="cycle, saved and reopened"),
    fixed("area_constrain", {"shape": "bspline_face"}, {"face": "Face1", "target": "105%"},
          [{"do": "self_link"}], name="AreaConstrain self-link"),
    fixed("twist", BOX, {"plane": _p((-10, 0, 0)), "plane2": _p((10, 0, 0)), "angle": 720},
          name="Twist 720 deg"),
    fixed("twist", BOX, {"plane": _p((-10, 0, 0)), "plane2": _p((10, 0, 0)), "angle": 10},
          [{"do": "set", "values": {"Angle": 0, "Turns": 2}}], name="Twist two Turns set"),
    fixed("direct_push", {"shape": "circle"}, {"element": "Edge1", "point": {"uv": [0.25, 0]},
                                              "offset": [NAN, 0, 0]}, expect=["Targets"],
          name="DirectPush NaN target"),
    fixed("direct_push", {"shape": "bspline_edge"}, {"element": "Edge1",
                                                    "point": {"uv": [0.5, 0]},
                                                    "offset": [0, INF, 0]}, expect=["Targets"],
          name="DirectPush infinite target"),
    fixed("stretch", {"shape": "cone"}, {"plane": _p((20 - 1e-6, 0, 0)), "distance": 5},
          name="Stretch 1e-6 below a cone's apex"),
    fixed("stretch", {"shape": "cone"}, {"plane": _p((20 - 1e-8, 0, 0)), "distance": 5},
          name="Stretch within tolerance of a cone's apex"),
    fixed("direct_push", BOX, {"element": "Face6", "point": {"uv": [0.5, 0.5]},
                               "offset": [0, 0, -15]},
          name="DirectPush through the opposite face"),
    fixed("direct_push", {"shape": "bspline_edge"},
          {"element": "Edge1", "point": {"uv": [0.5, 0]}, "offset": [0, 0, 3],
           "options": {"fixed": {"uv": [0.5, 0]}}}, name="DirectPush on a Fixed point"),
    fixed("direct_push", {"shape": "circle"}, {"element": "Edge1", "point": {"uv": [0, 0]},
                                              "offset": [0, 0, 3]},
          name="DirectPush on a circle's seam"),
    fixed("stretch", {"shape": "reversed"}, {"plane": X0, "distance": 5},
          name="Stretch of a reversed solid"),
    fixed("twist", BOX, {"plane": _p((-10, 0, 0)), "plane2": _p((10, 0, 0)), "angle": 40,
                         "axis": _p((0, 0, 0), (0, 0, 1))}, name="Twist axis off the normal"),
    fixed("stretch", {"shape": "compound"}, {"plane": X0, "distance": 5},
          name="Stretch of a free face in a compound"),
    fixed("bend", {"shape": "compound"}, {"plane": X0, "angle": -30,
                                          "axis": _p((0, 0, 40), (0, 1, 0))},
          name="Bend of a free face in a compound"),
    fixed("direct_push", {"shape": "bspline_edge"},
          {"element": "Edge1", "point": {"uv": [0.5, 0]}, "offset": [0, 0, 3],
           "options": {"range": 50}}, name="DirectPush Range 50"),
    fixed("stretch", BOX, {"plane": X0, "distance": INF}, expect=["Distance"],
          name="Stretch Distance inf"),
    fixed("twist", {"shape": "box", "as": "mesh"}, {"plane": _p((-10, 0, 0)),
                                                    "plane2": _p((10, 0, 0)), "angle": 30},
          [{"do": "set", "values": {"Samples": 10 ** 6}}], expect=["Samples"],
          name="mesh Twist Samples 10^6"),
    fixed("twist", {"shape": "box", "as": "mesh"}, {"plane": _p((-10, 0, 0)),
                                                    "plane2": _p((10, 0, 0)), "angle": 30},
          [{"do": "set", "values": {"Samples": 200}}], name="mesh Twist Samples 200"),
    fixed("stretch", BOX, {"plane": _p((0, 0, 0), (1, 2, 0)), "distance": 5},
          name="Stretch plane through Base vertices and edges"),
    fixed("stretch", {"shape": "void"}, {"plane": X0, "distance": 5},
          name="Stretch plane through a void's poles"),
    fixed("area_constrain", BOX, {"face": "Face1", "target": 900.0, "dof": "Sideways"},
          undo=0, name="make_* with a bad enumeration, UndoMode 0"),
    fixed("area_constrain", BOX, {"face": "Face1", "target": 900.0, "dof": "Sideways"},
          name="make_* with a bad enumeration"),
    fixed("stretch", BOX, {"plane": X0, "distance": 1e-12},
          name="Stretch Distance 1e-12"),
    fixed("bend", BOX, {"plane": X0, "angle": 1e-12, "axis": _p((0, 0, 40), (0, 1, 0))},
          name="Bend Angle 1e-12"),
    fixed("dimension_drive", {"shape": "box", "as": "degenerate_mesh"},
          {"kind": "Distance", "regions": [[0, 0, 5], [0, 0, -5]], "target": 12},
          name="DimensionDrive zero-area triangle"),
    fixed("area_constrain", {"shape": "bspline_face"},
          {"face": "Face1", "target": "105%", "poles": [[0, 0]]},
          name="AreaConstrain pole (0, 0)"),
    fixed("bend", BOX, {"plane": X0, "angle": -30, "axis": _p((0, 0, 40), (0, 1, 0)),
                        "plane2": _p((5, 0, 0), (0, 1, 0))}, name="Bend Plane2 not parallel"),
    fixed("twist", BOX, {"plane": X0, "plane2": _p((5, 0, 0), (0, 1, 0)), "angle": 30},
          name="Twist Plane2 not parallel"),
    fixed("stretch", BOX, {"plane": X0, "distance": -20 + 1e-9},
          name="Stretch shrink to just short of the end"),
    fixed("stretch", BOX, {"plane": X0, "distance": 5},
          [{"do": "rebase", "base": {"shape": "box", "as": "mesh"}}],
          name="Stretch Base changed to a mesh"),
    fixed("dimension_drive", {"shape": "box", "as": "mesh"},
          {"kind": "Distance", "regions": [[0, 0, 5], [0, 0, -5]], "target": 12},
          [{"do": "rebase", "base": {"shape": "box", "as": "points"}}],
          name="DimensionDrive Base changed to a point cloud"),
    fixed("stretch", BOX, {"plane": X0, "distance": 5},
          [{"do": "rebase", "base": {"shape": "empty"}}], name="Stretch empty Base"),
    fixed("stretch", BOX, {"plane": X0, "distance": 5}, [{"do": "undo_redo"},
                                                         {"do": "save_reopen"}],
          undo=1, name="Stretch undo, redo, save, reopen"),
]
