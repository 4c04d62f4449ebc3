"""DimensionDrive (Date & Onosato 2008): change a plane distance, a cylinder radius, an
angle between planes or a feature position of a triangle mesh (or of the boundary of a
tetrahedral FEM mesh, its interior following); the mesh follows through a prism handle,
same topology, no remeshing.

handle() / fem_handle() build the handle of a mesh once (segmentation, fits,
simplification, Warren coordinates: it depends only on the mesh, feature_angle and
handle_tolerance); mesh() / fem() then drive one dimension to a target for one sparse
product, giving (result, outputs). A refusal raised after the dimension was measured
carries the outputs known by then in its `outputs` attribute.
"""
import re

import numpy as np

from ..geometry.errors import DeformError
from ..geometry.mesh import dimension_drive as dd
from ..geometry.mesh import volume_drive as vd
from ..geometry.mesh.regions import weld
from ..shapes.convert import moved_mesh
from ..shapes.fem import fem_with_nodes

DEFAULT_FEATURE_ANGLE = 40.0   # degrees; FreeCAD tessellates cylinders at <= 28.6 degrees
KINDS = dd.KINDS               # the kinds of dimension: the values of the Kind property
HANDLE_STEPS = dd.DimensionModel.STEPS   # progress() calls while handle() builds
FEM_HANDLE_STEPS = vd.VolumeModel.STEPS  # and while fem_handle() builds


def _radians(feature_angle):
    if not 0 < feature_angle < 180:
        raise DeformError("FeatureAngle must be between 0 and 180 degrees.", "FeatureAngle")
    return np.radians(feature_angle)


def handle(vertices, triangles, feature_angle=DEFAULT_FEATURE_ANGLE, handle_tolerance=0.0,
           progress=lambda: None):
    """The handle of a triangle mesh (a geometry.mesh.dimension_drive.DimensionModel):
    feature_angle in degrees, handle_tolerance in mm (0: 0.5 % of the mesh size);
    progress() is called after each of its STEPS. Vertices at the same place are welded
    first (loose faces of a PLY drive as one surface); `unwelded` maps the model's
    vertices back to the mesh's."""
    V, T, unwelded = weld(vertices, triangles)
    model = dd.DimensionModel(V, T, _radians(feature_angle), handle_tolerance or None,
                              progress)
    model.unwelded = unwelded
    return model


def fem_handle(nodes, elements, feature_angle=DEFAULT_FEATURE_ANGLE, handle_tolerance=0.0,
               progress=lambda: None):
    """The handle of a tetrahedral mesh (a geometry.mesh.volume_drive.VolumeModel): its
    boundary's handle and the harmonic extension to the interior nodes."""
    return vd.VolumeModel(nodes, elements, _radians(feature_angle), handle_tolerance or None,
                          progress)


def target_of(kind, target=0.0, target_v=0.0, target_angle=0.0):
    """The kernel's target for a kind: the angle for Angle, (u, v) for Position, else Target."""
    if kind == "Angle":
        return target_angle
    if kind == "Position":
        return (target, target_v)
    return target


def measure(model, kind, regions, origin=None, axis_point=None):
    """The dimension the regions have on the mesh: (value,) or (u, v)."""
    probe = (0.0, 0.0) if kind == "Position" else 1.0  # any valid target
    surface = getattr(model, "surface", model)
    return dd.drive(surface, kind, [tuple(p) for p in regions], probe, origin,
                    axis_point).current


def _values(name, value):
    return {name: float(value[0]), name + "V": float(value[1]) if len(value) > 1 else 0.0}


def _moved(model, drive, deformed, kind, regions, target, origin, axis_point,
           rehandle=False):
    """(moved vertices, outputs) of one drive: Current(V), Reachable, Achieved(V), Handles
    and Strained (the corners that could not keep all their planes and cylinders). With
    `rehandle`, a target beyond Reachable is reached in steps, each with a handle rebuilt
    on the shape reached (dd.rehandled)."""
    outputs = {}
    regions = [tuple(p) for p in regions]
    origin = None if origin is None else tuple(origin)
    axis_point = None if axis_point is None else tuple(axis_point)
    try:
        result = drive(model, kind, regions, target, origin, axis_point)
        outputs.update(_values("Current", result.current))
        lo, hi = result.reach
        outputs["Reachable"] = (list(dd.reach_values(result)) if len(result.current) == 1
                                else [lo, hi])
        outputs["Handles"] = 1
        if rehandle and not lo < result.step < hi:
            vertices, _, last, outputs["Handles"] = dd.rehandled(
                model, lambda m, r: drive(m, kind, r, target, origin, axis_point), deformed,
                regions, result)
            result = result._replace(measure=last.measure)
        else:
            vertices = deformed(model, result)
    except DeformError as e:
        if "Handles" in outputs:
            outputs["Handles"] = getattr(e, "handles", outputs["Handles"])
        if kind == "Angle" and e.prop == "Target":   # the angle lives in TargetAngle
            e = DeformError(re.sub(r"\bTarget\b", "TargetAngle", str(e)), "TargetAngle")
        e.outputs = outputs
        raise e from None
    outputs.update(_values("Achieved", result.measure(vertices)), Strained=result.strained)
    return vertices, outputs


def mesh(model, base_mesh, kind, regions, target, origin=None, axis_point=None,
         rehandle=False):
    """(the Mesh moved, outputs): the dimension `kind` of the regions (points on the mesh,
    each picking the region nearest it) driven to `target` (target_of); `model` is
    handle() of base_mesh's vertices and triangles. `rehandle`: beyond Reachable, go on
    with new handles (the paper's dynamic handle)."""
    vertices, outputs = _moved(model, dd.drive, dd.deformed, kind, regions, target, origin,
                               axis_point, rehandle)
    unwelded = getattr(model, "unwelded", None)
    return moved_mesh(base_mesh, vertices if unwelded is None else vertices[unwelded]), outputs


def fem(model, femmesh, ids, kind, regions, target, origin=None, axis_point=None,
        rehandle=False):
    """(the FemMesh with its nodes moved, outputs) as mesh(), `model` fem_handle() of its
    nodes (numbered by ids) and elements; outputs add QualityAfter."""
    nodes, outputs = _moved(model, lambda m, *a: m.drive(*a), lambda m, d: m.deformed(d),
                            kind, regions, target, origin, axis_point, rehandle)
    outputs["QualityAfter"] = model.quality(nodes)
    return fem_with_nodes(femmesh, ids, nodes), outputs


def matching_regions(model, regions, other):
    """Points on the mesh of handle `other` picking its regions on the same planes and
    cylinders as `regions` of handle `model` (a shaft in a bore, a face against a face)."""
    return dd.matching_regions(getattr(model, "surface", model), [tuple(p) for p in regions],
                               getattr(other, "surface", other))
