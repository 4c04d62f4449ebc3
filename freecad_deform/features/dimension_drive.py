"""DimensionDrive (Date & Onosato 2008): change a plane distance, a cylinder radius or a
feature position of a triangle mesh; the mesh follows through a prism handle, same
topology, no remeshing. A Part base is tessellated first; the result is always a mesh.

The handle (segmentation, fits, simplification, Warren coordinates) depends only on the
Base mesh, FeatureAngle and HandleTolerance; it is kept on the proxy (not saved) so a
new Target costs one sparse product.
"""
import hashlib

import FreeCAD as App
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.mesh.regions import region_colours
from ..ops import dimension_drive as op
from ..shapes.convert import mesh_arrays, tessellated
from ..shapes.fem import fem_arrays, is_fem_mesh
from .base import DeformFeature, Prop

DEFAULT_FEATURE_ANGLE = op.DEFAULT_FEATURE_ANGLE


# the finest Tolerance, of the solid's diagonal (and 1e-6 mm at least): a torus 54 mm across
# is 172 k triangles at 0.001 mm, and OCCT's mesher throws (uncatchably) at 1e-9 mm
FINEST_TESSELLATION = 1e-4


class DimensionDrive(DeformFeature):
    TYPE = "DimensionDrive"
    RESULT = "Mesh::FeaturePython"
    PROPERTIES = (
        Prop("App::PropertyLink", "Base", "Base",
             "The mesh (or solid, tessellated with Tolerance) to deform; it is never modified."),
        Prop("App::PropertyEnumeration", "Kind", "Dimension",
             "Distance: between two parallel planes (the first picked moves). Radius: of a "
             "cylinder. Position: of a feature on a base plane, in the (Origin, AxisPoint) "
             "frame. Angle: between two planes (the first turns about the line where they "
             "meet), in TargetAngle.", list(op.KINDS)),
        Prop("App::PropertyVectorList", "Regions", "Dimension",
             "Points on the mesh, each picking the region nearest it. Distance: moving plane, "
             "reference plane. Radius: the cylinder. Position: base plane, feature (then "
             "more feature regions if wanted)."),
        Prop("App::PropertyDistance", "Target", "Dimension",
             "The new dimension: the distance or the radius; for Position the u coordinate."),
        Prop("App::PropertyAngle", "TargetAngle", "Dimension",
             "Angle only: the new angle between the two planes (the wedge from their line "
             "of intersection into each region)."),
        Prop("App::PropertyDistance", "TargetV", "Dimension",
             "Position only: the new v coordinate of the feature."),
        Prop("App::PropertyVectorDistance", "Origin", "Dimension",
             "Position only: the origin of the (u, v) frame (projected on the base plane)."),
        Prop("App::PropertyVectorDistance", "AxisPoint", "Dimension",
             "Position only: a point on the u axis of the frame; equal to Origin: u runs "
             "along the global x axis (y if x is normal to the base plane)."),
        Prop("App::PropertyAngle", "FeatureAngle", "Handle",
             "Triangles whose normals turn by more than this are in different regions.",
             DEFAULT_FEATURE_ANGLE),
        Prop("App::PropertyLength", "HandleTolerance", "Handle",
             "How far the simplified mesh that shapes the handle may deviate from the mesh "
             "(its outlines and flat regions within this, its curved regions within 3 times "
             "it, 1.5 times in the mean square); coarser spreads the change wider. 0: 0.5 % "
             "of the mesh size.", 0.0),
        Prop("App::PropertyLength", "Tolerance", "Handle",
             "Tessellation tolerance when Base is a solid.", 0.1),
        Prop("App::PropertyBool", "Rehandle", "Handle",
             "Beyond Reachable, go on in steps: after each, rebuild the handle around the "
             "shape reached (same vertices and triangles, the vertices inside planes "
             "evened out) until Target is met or no step gains (the paper's dynamic handle).",
             False),
        Prop("App::PropertyFloat", "Current", "Result",
             "The dimension measured on the Base, in mm (Position: its u).", output=True),
        Prop("App::PropertyFloat", "CurrentV", "Result",
             "Position only: the v coordinate measured on the Base, in mm.", output=True),
        Prop("App::PropertyFloat", "Achieved", "Result",
             "The dimension measured on the result, in mm (Position: its u).", output=True),
        Prop("App::PropertyFloat", "AchievedV", "Result",
             "Position only: the v coordinate measured on the result, in mm.", output=True),
        Prop("App::PropertyFloatList", "Reachable", "Result",
             "How far the dimension can go before a triangle flips: [lowest, highest] value; "
             "for Position, [back, forward] travel in mm along the move.", output=True),
        Prop("App::PropertyInteger", "Handles", "Result",
             "How many handles the drive used: 1, or more when Rehandle went beyond "
             "Reachable.", output=True),
        Prop("App::PropertyInteger", "RegionCount", "Result",
             "Number of regions the mesh was segmented into.", output=True),
        Prop("App::PropertyColorList", "RegionColors", "Result",
             "One colour per triangle, by region (shown with the view's Coloring).",
             output=True),
    )

    def base_mesh(self, obj):
        """(vertices, triangles, Mesh) of the Base: a mesh, or a solid tessellated."""
        base = obj.Base
        if base is None:
            raise DeformError("Base is empty; link a mesh or a solid.", "Base")
        if base.isDerivedFrom("Mesh::Feature"):
            return (*mesh_arrays(base.Mesh), base.Mesh)
        if hasattr(base, "Shape") and not base.Shape.isNull():
            finest = max(FINEST_TESSELLATION * base.Shape.BoundBox.DiagonalLength, 1e-6)
            if not obj.Tolerance.Value >= finest:
                raise DeformError(
                    f"Tolerance {obj.Tolerance.Value:.3g} mm is finer than "
                    f"{FINEST_TESSELLATION:g} of {base.Label}'s size: tessellating it takes "
                    f"minutes and millions of triangles (OCCT fails at 1e-9 mm); "
                    f"raise Tolerance to {finest:.3g} mm or more.", "Tolerance")
            return tessellated(base.Shape, obj.Tolerance.Value)
        raise DeformError(f"Base {base.Label} is not a mesh or a solid; link one.", "Base")

    def model(self, obj):
        """The handle of the Base (ops.dimension_drive.handle), reused while the Base and
        the handle settings hold."""
        V, T, mesh = self.base_mesh(obj)
        return self.cached_model(obj, V.tobytes() + T.tobytes(), op.handle, op.HANDLE_STEPS, V, T), mesh

    def cached_model(self, obj, data, build, steps, *arrays):
        """build(*arrays, FeatureAngle, HandleTolerance, progress) (progress called `steps`
        times), built once for `data` (the Base's arrays as bytes) and the handle settings."""
        key = hashlib.blake2b(data + np.array(
            [obj.FeatureAngle.Value, obj.HandleTolerance.Value]).tobytes()).hexdigest()
        cached = getattr(self, "_cache", None)
        if cached is None or cached[0] != key:
            bar = App.Base.ProgressIndicator()
            bar.start(f"{obj.Label}: building the deformation handle", steps)
            try:
                model = build(*arrays, obj.FeatureAngle.Value, obj.HandleTolerance.Value,
                              bar.next)
            finally:
                bar.stop()
            self._cache = cached = (key, model)
        return cached[1]

    def execute(self, obj):
        model, mesh = self.model(obj)
        surface = getattr(model, "surface", model)
        if getattr(self, "_coloured", None) is not model:
            obj.RegionCount = surface.count
            obj.RegionColors = region_colours(surface.labels)
            self._coloured = model
        if len(obj.Regions) == 0:
            self.show_base(obj, mesh)
            raise DeformError("Regions is empty; pick the regions of the dimension.", "Regions")
        target = op.target_of(obj.Kind, obj.Target.Value, obj.TargetV.Value,
                              obj.TargetAngle.Value)
        try:
            result, outputs = self.drive(model, mesh, obj.Kind, obj.Regions, target,
                                         obj.Origin, obj.AxisPoint, obj.Rehandle)
        except DeformError as e:
            for name, value in getattr(e, "outputs", {}).items():
                setattr(obj, name, value)
            raise
        strained = outputs.pop("Strained")
        if strained:
            App.Console.PrintWarning(
                f"{obj.Label}: {strained} corner(s) of the moving plane meet faces that "
                "cannot all stay planes or cylinders; they were kept as nearly as possible.\n")
        self.store(obj, result)
        for name, value in outputs.items():
            setattr(obj, name, value)

    @staticmethod
    def drive(model, mesh, *args):
        return op.mesh(model, mesh, *args)

    @staticmethod
    def show_base(obj, mesh):
        if obj.Mesh.CountFacets == 0:
            obj.Mesh = mesh.copy()   # nothing to keep yet: show the Base to pick on

    @staticmethod
    def store(obj, result):
        obj.Mesh = result


class DimensionDriveFem(DimensionDrive):
    """DimensionDrive on a FEM mesh of linear or quadratic tetrahedra: the boundary drives
    the handle, the interior nodes follow by a harmonic extension (geometry.mesh.volume_drive);
    the result is a FEM mesh with the same nodes, elements, numbers and groups."""

    RESULT = "Fem::FemMeshObjectPython"
    PROPERTIES = DimensionDrive.PROPERTIES + (
        Prop("App::PropertyFloat", "QualityBefore", "Result",
             "The worst element quality of the Base: scaled Jacobian (1 regular, 0 flat), of "
             "the linear sub-tetrahedra of quadratic elements.", output=True),
        Prop("App::PropertyFloat", "QualityAfter", "Result",
             "The worst element quality of the result (scaled Jacobian, as QualityBefore).",
             output=True),
    )

    @staticmethod
    def check_base(base):
        if not is_fem_mesh(base):
            raise DeformError(f"Base {base.Label} is not a FEM mesh; link one.", "Base")

    def model(self, obj):
        base = obj.Base
        if not is_fem_mesh(base):
            raise DeformError("Base must be a FEM mesh (the object was made for one); link "
                              "one.", "Base")
        femmesh = base.FemMesh
        ids, nodes, _, elements = fem_arrays(femmesh)
        model = self.cached_model(obj, ids.tobytes() + nodes.tobytes() + elements.tobytes(),
                                  op.fem_handle, op.FEM_HANDLE_STEPS,
                                  nodes, elements)
        obj.QualityBefore = model.quality()
        return model, (femmesh, ids)

    @staticmethod
    def drive(model, mesh, *args):
        return op.fem(model, *mesh, *args)

    @staticmethod
    def show_base(obj, mesh):
        if obj.FemMesh.NodeCount == 0:
            obj.FemMesh = mesh[0].copy()

    @staticmethod
    def store(obj, result):
        obj.FemMesh = result


def proxy_for(base):
    """The DimensionDrive proxy class for `base`: DimensionDriveFem for a FEM mesh."""
    return DimensionDriveFem if is_fem_mesh(base) else DimensionDrive
