# Deform workbench: GUI entry point.
#
# FreeCAD exec()s this file while it starts, without __file__ (0.20) and with the
# top-level names of this file invisible inside the class (they land in exec's locals).
# So everything the class needs is imported inside it, and the heavy imports wait for
# Initialize(), which runs when the workbench is first activated. The repository root
# is on sys.path (FreeCAD adds each Mod/<dir>), so freecad_deform imports; its gui
# package __init__ is only os.path work. The toolbar and menu are freecad_deform/registry.py's.


class DeformWorkbench(Workbench):  # noqa: F821  (Workbench comes from FreeCAD's start-up)
    """Stretch, bend and twist existing solids, meshes and point clouds, drive the
    dimensions of meshes, without history."""

    from freecad_deform.gui import icon_path as _icon_path

    MenuText = "Deform"
    ToolTip = ("Edit existing models without their history: stretch, bend or twist a solid, "
               "mesh or point cloud at a plane, or drive a mesh's dimensions, keeping the "
               "result parametric")
    Icon = _icon_path("Deform")
    del _icon_path

    def Initialize(self):
        from freecad_deform import registry
        from freecad_deform.gui import commands  # noqa: F401  (adds the registry's commands)
        names = [tool.command for tool in registry.TOOLBAR]
        self.appendToolbar("Deform", names)
        self.appendMenu("Deform", names)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(DeformWorkbench())  # noqa: F821
