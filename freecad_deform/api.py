"""Macro API: make_stretch(), make_bend(), make_twist(), make_taper(), make_dimension_drive(),
make_area_constrain(), make_direct_push(). Each creates one feature in one
transaction and recomputes; the keyword arguments are the object's properties.
solve() is the goal seek of the batch command line."""
import FreeCAD as App
import numpy as np

from .features.base import RESULT_TYPES, base_kind
from .features.area_constrain import AreaConstrain
from .features.bend import Bend
from .features.dimension_drive import DimensionDrive, proxy_for
from .features.direct_push import DirectPush
from .features.stretch import Stretch
from .features.taper import Taper
from .features.twist import Twist
from .geometry.errors import DeformError
from .ops import dimension_drive as dimension_drive_op
from .shapes.convert import plane_placement


def _create(proxy_class, base, name):
    """A new feature object on `base` in base's document, the base hidden."""
    doc = base.Document
    obj = doc.addObject(getattr(proxy_class, "RESULT", None) or RESULT_TYPES[base_kind(base)],
                        name)
    proxy_class(obj)
    obj.Base = base
    base.Visibility = False
    if App.GuiUp:
        from .gui.view_providers import attach
        attach(obj)
    return obj


def _make(proxy_class, base, values):
    """Create, set `values` (property name -> value), recompute: one undo step (or the
    caller's, if one is open). A call that raises leaves the document as it was: the new
    object removed, the Base shown again, no transaction left open."""
    doc = base.Document
    # an empty or unknown Base is refused before anything is opened
    getattr(proxy_class, "check_base", base_kind)(base)
    own = doc.UndoMode > 0 and not (doc.HasPendingTransaction or App.getActiveTransaction())
    if own:
        doc.openTransaction(proxy_class.TYPE)
    shown, name, done = base.Visibility, None, False
    try:
        obj = _create(proxy_class, base, proxy_class.TYPE)
        name = obj.Name
        for prop, value in values.items():
            _set(obj, prop, value)
        doc.recompute()
        done = True
    finally:
        if own:
            doc.commitTransaction() if done else doc.abortTransaction()
            if App.getActiveTransaction():  # opened, nothing recorded: still active
                App.closeActiveTransaction(not done)
        if not done:  # abortTransaction already removed it where undo is on
            if name is not None and doc.getObject(name) is not None:
                doc.removeObject(name)
            base.Visibility = shown
    return obj


def _set(obj, prop, value):
    """obj.prop = value; FreeCAD's refusal (an angle of 1e300 overflows its property with a
    SystemError) as a DeformError naming prop."""
    try:
        setattr(obj, prop, value)
    except (OverflowError, SystemError, ValueError, TypeError, App.Base.FreeCADError) as e:
        cause = e.__cause__ or e.__context__ or e
        why = cause.args[0] if cause.args else type(cause).__name__
        why = why.get("sErrMsg", why) if isinstance(why, dict) else why  # FreeCAD's errors
        shown = repr(value)
        shown = shown if len(shown) <= 60 else shown[:57] + "..."
        raise DeformError(f"{prop} cannot hold {shown} ({why}); give {prop} a value its "
                          f"property can hold.", prop) from e


def _second_plane(plane2):
    return {} if plane2 is None else {"Plane2": plane_placement(plane2, "Plane2"),
                                       "UsePlane2": True}


def make_stretch(base, plane, distance, plane2=None):
    """Stretch `base` at `plane` by `distance`; with `plane2`, only the region between them."""
    return _make(Stretch, base, {"Plane": plane_placement(plane), "Distance": distance,
                                 **_second_plane(plane2)})


def make_bend(base, plane, angle, axis, plane2=None):
    """Bend `base` at `plane` by `angle` (degrees) about `axis` (point, direction)."""
    return _make(Bend, base, {"Plane": plane_placement(plane), "Angle": angle,
                              "Axis": plane_placement(axis, "Axis"), **_second_plane(plane2)})


def make_twist(base, plane, plane2, angle, axis=None):
    """Twist the region of `base` between `plane` and `plane2` by `angle` (degrees, or a
    quantity; beyond 360 deg the whole turns go to Turns)."""
    degrees = App.Units.Quantity(angle).Value if isinstance(angle, str) else float(
        getattr(angle, "Value", angle))
    finite = bool(np.isfinite(degrees))  # not finite: NaN, which Angle keeps and refuses
    turns = int(degrees / 360.0) if finite else 0
    if abs(turns) >= 2 ** 31:
        raise DeformError(f"Angle {degrees:.4g} deg is more whole turns than the Turns "
                          f"property can count (2^31); give Angle a smaller value.", "Angle")
    values = {"Plane": plane_placement(plane), "Plane2": plane_placement(plane2, "Plane2"),
              "Angle": degrees - 360.0 * turns if finite else float("nan"), "Turns": turns}
    if axis is not None:
        values.update(Axis=plane_placement(axis, "Axis"), UseAxis=True)
    return _make(Twist, base, values)


def make_taper(base, plane, plane2, scale, axis=None):
    """Taper the region of `base` between `plane` and `plane2`: scaled across the axis from 1
    at `plane` to `scale` at `plane2` (a number, or (scale_x, scale_y) along the X and Y of
    the axis frame); axis: (point, direction) or a Placement, default the plane normal
    through the section's centroid."""
    values = {"Plane": plane_placement(plane), "Plane2": plane_placement(plane2, "Plane2")}
    if np.ndim(scale) == 0:
        values["Scale"] = float(scale)
    else:
        values.update(UseScaleXY=True, ScaleX=float(scale[0]), ScaleY=float(scale[1]))
    if axis is not None:
        values.update(Axis=plane_placement(axis, "Axis"), UseAxis=True)
    return _make(Taper, base, values)


def _camel(name):
    return "".join(part[:1].upper() + part[1:] for part in name.split("_"))


def _options(proxy_class, caller, options):
    """Keyword options in snake_case as {Property: value}; an unknown one is a TypeError."""
    known = {p.name for p in proxy_class.PROPERTIES}
    values = {}
    for name, value in options.items():
        if _camel(name) not in known:
            raise TypeError(f"{caller}() got an unknown option {name!r}")
        values[_camel(name)] = value
    return values


def make_matching_drive(drive, other):
    """The DimensionDrive `drive` applied to the matching plane or cylinder of the mesh (or
    solid, or FEM mesh) `other`, its Target bound to drive's by an expression: one value
    changes both parts, a bore and its shaft (Date & Onosato, Fig. 8)."""
    model, _ = drive.Proxy.model(drive)
    shown = other.Visibility
    probe = make_dimension_drive(other, drive.Kind, [], 1.0,
                                 feature_angle=drive.FeatureAngle.Value,
                                 handle_tolerance=drive.HandleTolerance.Value)
    try:
        picks = dimension_drive_op.matching_regions(model, drive.Regions,
                                                    probe.Proxy.model(probe)[0])
    except DeformError:
        probe.Document.removeObject(probe.Name)     # nothing left behind
        other.Visibility = shown
        raise
    probe.Regions = [App.Vector(*p) for p in picks]
    for name in ("Target", "TargetV", "TargetAngle"):
        probe.setExpression(name, f"{drive.Name}.{name}")
    probe.Origin, probe.AxisPoint = drive.Origin, drive.AxisPoint
    probe.Document.recompute()
    return probe


def make_dimension_drive(mesh_obj, kind, regions, target, **options):
    """Drive a dimension of `mesh_obj` (a mesh, or a solid tessellated with `tolerance`) to
    `target`. kind: "Distance" (regions: a point on the moving plane, one on the reference
    plane), "Radius" (a point on the cylinder) or "Position" (a point on the base plane,
    one on the feature; target (u, v) in the frame of the options origin and axis_point).
    Other options are properties in snake_case: feature_angle, handle_tolerance, tolerance.
    """
    kind = str(kind).capitalize()
    values = {"Kind": kind, "Regions": [App.Vector(*p) for p in regions]}
    if kind == "Position":
        try:
            u, v = target
        except (TypeError, ValueError):
            raise ValueError("target of a Position is a (u, v) pair") from None
        values.update(Target=u, TargetV=v)
    else:
        values["TargetAngle" if kind == "Angle" else "Target"] = target
    for prop, value in _options(DimensionDrive, "make_dimension_drive", options).items():
        values[prop] = App.Vector(*value) if prop in ("Origin", "AxisPoint") else value
    return _make(proxy_for(mesh_obj), mesh_obj, values)


def make_area_constrain(base, face, target_area, poles=None, dof="Normal", **options):
    """Move poles of `face` ("FaceN" of base) as little as possible so its area is
    `target_area`: a number (mm^2), a quantity, or a ratio of the original as "105%".
    poles: 1-based (i, j) pairs as in getPole, None for every interior pole; dof: "Normal",
    "Z" or "Free". Other options are properties in snake_case: method, target_ratio."""
    values = {"Face": str(face), "Dof": dof,
              "Poles": [f"{i},{j}" for i, j in (poles or [])]}
    if isinstance(target_area, str) and target_area.strip().endswith("%"):
        values["TargetRatio"] = float(target_area.strip()[:-1]) / 100.0
    else:
        values["TargetArea"] = target_area
    values.update(_options(AreaConstrain, "make_area_constrain", options))
    return _make(AreaConstrain, base, values)


def _vectors(points):
    return [App.Vector(*p) for p in points]


def make_direct_push(base, element, point, target, **options):
    """Push `point` of `element` ("EdgeN" or "FaceN" of base) to `target`; the poles and
    knots follow (point and target None: no push yet). Options: range (the paper's m), fixed=[points], straight=[(point_a,
    point_b)], angles=[(corner, degrees, leg_before, leg_after)], blend=["EdgeN", ...] (faces
    of a solid: Pratt's C1 rounding of those edges); other options are properties in
    snake_case."""
    pushes = [] if point is None and target is None else [(point, target)]
    values = {"Element": str(element), "Points": _vectors([p for p, _ in pushes]),
              "Targets": _vectors([t for _, t in pushes])}
    packed = {"range": int, "fixed": _vectors, "blend": lambda edges: [str(e) for e in edges],
              "straight": lambda spans: _vectors([p for pair in spans for p in pair]),
              "angles": lambda angles: [App.Vector(*v) for corner, degrees, before, after
                                        in angles for v in (tuple(corner),
                                                            (degrees, before, after))]}
    options = {name: packed[name](value) if name in packed else value
               for name, value in options.items()}
    values.update(_options(DirectPush, "make_direct_push", options))
    return _make(DirectPush, base, values)


def solve(doc, vary, target=None, minimize=None, maximize=None, **options):
    """Goal seek: the values of `vary` ({"Stretch.Distance": (lo, hi)}) that make
    `target` ({"Stretch.VolumeChange": value}) hold, or that minimise or maximise one
    output. Returns {"Stretch.Distance": value, "residual": r, "iterations": n}; the
    document is left recomputed at the solution."""
    from .batch.solve import solve as goal_seek
    return goal_seek(doc, vary, target, minimize, maximize, **options)
