"""Pure numpy/scipy kernels of the Deform workbench: arrays in, arrays out, no FreeCAD."""
from .errors import DeformError

__all__ = ["DeformError"]
