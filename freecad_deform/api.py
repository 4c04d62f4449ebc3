"""Macro API: make_stretch(), ... Each creates one feature in one transaction and recomputes."""
import FreeCAD as App

from .features.base import RESULT_TYPES, base_kind
from .features.stretch import Stretch
from .shapes.convert import plane_placement


def _create(proxy_class, base, name):
    """A new feature object on `base` in base's document, the base hidden."""
    doc = base.Document
    obj = doc.addObject(RESULT_TYPES[base_kind(base)], name)
    proxy_class(obj)
    obj.Base = base
    base.Visibility = False
    if App.GuiUp:
        from .gui.view_providers import attach
        attach(obj)
    return obj


def _transaction(doc, title, build):
    """Run `build()` inside one undo step (or inside the caller's, if one is open)."""
    own = not (doc.HasPendingTransaction or App.getActiveTransaction())
    if own:
        doc.openTransaction(title)
    try:
        obj = build()
        doc.recompute()
    except Exception:
        if own:
            doc.abortTransaction()
        raise
    if own:
        doc.commitTransaction()
    return obj


def make_stretch(base, plane, distance, plane2=None):
    """Stretch `base` at `plane` by `distance`; with `plane2`, only the region between them."""
    def build():
        obj = _create(Stretch, base, "Stretch")
        obj.Plane = plane_placement(plane)
        obj.Distance = distance
        if plane2 is not None:
            obj.Plane2 = plane_placement(plane2, "Plane2")
            obj.UsePlane2 = True
        return obj
    return _transaction(base.Document, "Stretch", build)
