"""What the Stretch, Bend, Twist and Taper features share: their plane, axis, motion and
result properties, and reading them (planes, Samples, the key motion); the pipelines
themselves are in ops/ (ops.planes holds what they share)."""
import numpy as np

from ..geometry.sweep import motion as mo
from ..geometry.errors import DeformError
from ..geometry.sweep.planes import parallel_gap
from ..ops import keyed as ops_keyed
from ..shapes import brep
from ..shapes.convert import matrix_array, plane_arrays
from .base import Prop

BASE = Prop("App::PropertyLink", "Base", "Base",
            "The solid, mesh or point cloud to deform; it is never modified.")
PLANE = Prop("App::PropertyPlacement", "Plane", "Planes",
             "Separating plane: its local XY plane splits the part, its local Z (the normal) "
             "points toward the part that moves.")
USE_PLANE2 = Prop("App::PropertyBool", "UsePlane2", "Planes",
                  "Deform only the region between Plane and Plane2, keeping its cross-sections "
                  "(Case 2); the part beyond Plane2 moves rigidly.", False)
PLANE2 = Prop("App::PropertyPlacement", "Plane2", "Planes",
              "Second separating plane, parallel to Plane and beyond it along the normal; used "
              "when UsePlane2 is true.")
def region_plane2(what):
    """Plane2 of a feature that always deforms the region between the planes (Twist,
    Taper): `what` the region does."""
    return Prop("App::PropertyPlacement", "Plane2", "Planes",
                f"Second separating plane, parallel to Plane and beyond it along the normal: "
                f"the region between the planes {what}.")


AXIS = Prop("App::PropertyPlacement", "Axis", "Motion",
            "Axis of rotation: its position is a point on the axis, its local Z the direction "
            "(right-hand rule for Angle).")
ANGLE = Prop("App::PropertyAngle", "Angle", "Motion", "How far the far part turns about Axis.")
SAMPLES = Prop("App::PropertyInteger", "Samples", "Sweep",
               "Number of intermediate profiles where the sweep is not exact (lofts, meshes).",
               16)
KEYS = Prop("App::PropertyPlacementList", "KeyPlacements", "Motion",
            "Key placements of the far part (the paper's key frames), passed in order before "
            "its final place; the gap is then a loft through Samples profiles normal to the "
            "path. Empty: the exact sweep (extrusion or revolve).")
INTERPOLATION = Prop("App::PropertyEnumeration", "Interpolation", "Motion",
                     "How the motion passes through KeyPlacements: Rational, a C2 dual-quaternion "
                     "spline whose point paths are NURBS; Screw, a screw motion from key to key.",
                     list(mo.INTERPOLATIONS))
USE_END = Prop("App::PropertyBool", "UseEndPlacement", "Motion",
               "Move the far part to EndPlacement (any rigid motion: a screw, a slide across "
               "the normal) instead of by the feature's own motion; the gap is lofted along the "
               "key-frame motion through KeyPlacements to it.", False)
END = Prop("App::PropertyPlacement", "EndPlacement", "Motion",
           "Final placement of the far part (the paper's last key frame), used when "
           "UseEndPlacement is true.")
RESULTS = (
    Prop("App::PropertyFloat", "VolumeChange", "Result",
         "Volume of the result minus the volume of the Base, in mm^3 (negative when it "
         "shrinks).", output=True),
    Prop("App::PropertyString", "Continuity", "Result",
         "Continuity at each joint (Lemma 1): G1 where a split face's normal is "
         "perpendicular to the trajectory, else C0.", output=True),
    Prop("App::PropertyStringList", "SplitFaces", "Result",
         "Faces of the Base that a separating plane cut.", output=True),
    Prop("App::PropertyInteger", "IgnoredPoints", "Result",
         "Points of a point-cloud Base left out because a coordinate is NaN or infinite "
         "(a scanner's missing returns); they are not in the result.", output=True),
)


def planes(obj, require_plane2=False):
    """(origin, normal, gap) from the Plane properties; gap is None for one plane."""
    origin, normal = plane_arrays(obj.Plane)
    if not (require_plane2 or obj.UsePlane2):
        return origin, normal, None
    origin2, normal2 = plane_arrays(obj.Plane2)
    gap = parallel_gap(origin, normal, origin2, normal2)
    if gap <= 10 * brep.TOL:
        raise DeformError(f"Plane2 is only {gap:.3g} beyond Plane, within ten times the "
                          f"modelling tolerance: no region lies between them; move Plane2.",
                          "Plane2")
    return origin, normal, gap


MAX_SAMPLES = 4096  # profiles of a sweep; a mesh band's size and time grow linearly with it


def check_samples(obj, least):
    """Samples within [least, MAX_SAMPLES]: fewer cannot sweep, more would never finish."""
    if not least <= obj.Samples <= MAX_SAMPLES:
        raise DeformError(f"Samples {obj.Samples} is outside {least} to {MAX_SAMPLES}; set "
                          f"Samples within that range.", "Samples")


def key_motion(obj, final):
    """The motion through the object's KeyPlacements ending at `final` (at EndPlacement
    with UseEndPlacement), or None."""
    free_end = getattr(obj, "UseEndPlacement", False)
    if free_end:
        final = matrix_array(obj.EndPlacement)
        if (np.abs(final[:3, :3] - np.eye(3)).max() <= 1e-12
                and np.linalg.norm(final[:3, 3]) <= brep.TOL):
            raise DeformError("EndPlacement leaves the far part where it is; give the far "
                              "part's final placement, or clear UseEndPlacement.",
                              "EndPlacement")
    if not (len(obj.KeyPlacements) or free_end):
        return None
    keys = [np.eye(4)] + [matrix_array(p) for p in obj.KeyPlacements] + [final]
    return mo.key_motion(keys, obj.Interpolation)


def keyed(obj, base_kind, origin, normal, gap, motion):
    """Result and outputs of a Case 1 deformation by a key motion (ops.keyed), for every
    kind of Base."""
    if gap is not None:
        raise DeformError("KeyPlacements move the part beyond one Plane; clear KeyPlacements "
                          "or UsePlane2.", "KeyPlacements")
    check_samples(obj, 2)
    if base_kind == "Points":
        return ops_keyed.points(obj.Base.Points, origin, normal, motion)
    if base_kind == "Mesh":
        return ops_keyed.mesh(obj.Base.Mesh, origin, normal, motion, obj.Samples)
    return ops_keyed.solid(obj.Base.Shape, origin, normal, motion, obj.Samples)
