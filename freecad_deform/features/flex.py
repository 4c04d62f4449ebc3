"""What Twist, Bend and Taper share where the region between the planes goes through a
space map (geometry.sweep.space_map): the Profile, Tolerance and MaxDeviation properties."""
from ..geometry.sweep.space_map import PROFILES
from .base import Prop

PROFILE = Prop("App::PropertyEnumeration", "Profile", "Motion",
               "How the deformation grows from Plane to Plane2: Linear, or Smooth (zero slope "
               "at both planes, so the joints with the rigid parts are smooth).",
               list(PROFILES))
TOLERANCE = Prop("App::PropertyLength", "Tolerance", "Sweep",
                 "Largest distance allowed between a refitted face and the exact deformation "
                 "(faces the deformation keeps in their kind stay exact).", 1e-3)
MAX_DEVIATION = Prop("App::PropertyFloat", "MaxDeviation", "Result",
                     "Largest distance, in mm, between the result and the exact deformation, "
                     "measured at points the fits did not use (0 where every face is exact).",
                     output=True)
PROPERTIES = (PROFILE, TOLERANCE)


def tolerance(obj):
    """The Tolerance property as a float, which must be positive."""
    from ..geometry.errors import DeformError
    value = float(obj.Tolerance.Value)
    if not value > 0:
        raise DeformError("Tolerance must be positive; raise Tolerance.", "Tolerance")
    return value

