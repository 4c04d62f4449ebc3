"""View providers of the Deform features: icon, Base in the tree, double-click to edit.

FreeCAD saves the class path (freecad_deform.gui.view_providers.ViewProviderDeform) in
the document and re-creates it when the document is reopened with the GUI up; its state
is None, so nothing is pickled.
"""
import FreeCAD as App
import FreeCADGui as Gui

from .. import registry
from ..features.base import Stateless
from . import icon_path

# Base view properties a new result takes over, so it looks like what it replaces.
_INHERITED_VIEW = ("ShapeColor", "LineColor", "PointColor", "LineWidth", "PointSize",
                   "Transparency", "DisplayMode")


def attach(obj):
    """Give a new Deform feature its view provider (called by api.make_* when the GUI is up)."""
    vobj = obj.ViewObject
    if vobj is None:
        return None
    ViewProviderDeform(vobj)
    base = getattr(obj, "Base", None)
    if base is not None and base.ViewObject is not None:
        for name in _INHERITED_VIEW:
            if name in base.ViewObject.PropertiesList and name in vobj.PropertiesList:
                try:
                    setattr(vobj, name, getattr(base.ViewObject, name))
                except ValueError:
                    pass  # a display mode the result does not have
    return vobj.Proxy


def feature_type(obj):
    """The proxy's TYPE ("Stretch", ...), or "Deform" when it is not known (yet)."""
    return getattr(getattr(obj, "Proxy", None), "TYPE", None) or "Deform"


def panel_class(obj):
    """The task panel class of `obj` (registry.py: <Type>Panel in gui/<type>_panel.py), or
    None when its feature has no panel. An error inside the panel's module is raised."""
    feature = registry.feature(feature_type(obj))
    if feature is None or feature.panel_class is None:
        return None
    return registry.load(feature.panel_class)


class ViewProviderDeform(Stateless):
    """One view provider for every Deform feature; what differs comes from the proxy's TYPE."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.ViewObject = vobj

    def attach(self, vobj):
        self.ViewObject = vobj

    # --- look -------------------------------------------------------------------------------
    def getIcon(self):
        vobj = getattr(self, "ViewObject", None)
        obj = getattr(vobj, "Object", None) if vobj is not None else None
        return icon_path(feature_type(obj))

    def claimChildren(self):
        base = getattr(self.ViewObject.Object, "Base", None)
        return [base] if base is not None else []

    # --- editing ----------------------------------------------------------------------------
    def doubleClicked(self, vobj):
        gdoc = Gui.getDocument(vobj.Object.Document.Name)
        if gdoc.getInEdit() is None:
            gdoc.setEdit(vobj.Object.Name, 0)
        return True

    def setupContextMenu(self, vobj, menu):
        from PySide import QtGui
        action = QtGui.QAction(QtGui.QIcon(self.getIcon()), "Edit " + feature_type(vobj.Object), menu)
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None  # FreeCAD's own modes (Transform, ...) stay available
        if Gui.Control.activeDialog():
            App.Console.PrintWarning("Close the open task panel before editing "
                                     f"{vobj.Object.Label}.\n")
            return False
        cls = panel_class(vobj.Object)
        if cls is None:
            return False
        Gui.Control.showDialog(cls(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        Gui.Control.closeDialog()
        return True

    # --- deleting ---------------------------------------------------------------------------
    def onDelete(self, vobj, subelements):
        base = getattr(vobj.Object, "Base", None)
        if base is not None and base.ViewObject is not None:
            base.ViewObject.show()
        return True

