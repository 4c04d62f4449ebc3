"""Deform workbench: stretch, bend, twist and drive existing FreeCAD models without history.

`freecad_deform.geometry` imports without FreeCAD; the `make_*` functions (from `api`)
need FreeCAD and are loaded on first use.
"""
__version__ = "0.1.0"

from .registry import API as _API  # the make_* of every feature and tool (registry.py)

__all__ = list(_API)


def __getattr__(name):
    if name in _API:
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'freecad_deform' has no attribute {name!r}")
