"""DimensionDrive on tetrahedral meshes (issue 17; the volume meshes Date & Onosato leave
to future work). The boundary triangles drive segmentation, fits and handle exactly as a
surface mesh does; every interior node follows by the harmonic extension of the boundary
motion (volume_mesh.Extension), so each node still moves by s * field and a new Target
costs one product. The reach adds the interval in which no tetrahedron inverts.
"""
import numpy as np

from . import dimension_drive as dd
from . import volume as vm
from ..errors import DeformError


class VolumeModel:
    """The surface DimensionModel of a tetrahedral mesh's boundary plus its extension."""

    STEPS = dd.DimensionModel.STEPS + 1

    def __init__(self, nodes, elements, feature_angle, handle_tolerance=None,
                 progress=lambda: None):
        self.nodes = np.asarray(nodes, float)
        self.elements = np.asarray(elements, np.int64)
        self.tets, self.parent = vm.linear_tets(self.elements)
        if len(self.tets) == 0:
            raise DeformError("Base has no tetrahedra; link a tetrahedral FEM mesh.", "Base")
        self.tets = vm.oriented(self.nodes, self.tets)
        triangles = vm.boundary_triangles(self.nodes, self.tets)
        self.boundary = np.unique(triangles)
        index = np.full(len(self.nodes), -1)
        index[self.boundary] = np.arange(len(self.boundary))
        self.surface = dd.DimensionModel(self.nodes[self.boundary], index[triangles],
                                         feature_angle, handle_tolerance, progress)
        self.extension = vm.Extension(self.nodes, self.elements, self.boundary)
        progress()

    def rebuilt(self, nodes):
        """The model of the same elements at new node positions (a new handle)."""
        return VolumeModel(nodes, self.elements, *self.surface.settings)

    def relaxed(self, nodes, base=None, cache=None):
        """`nodes` with the boundary relaxed in its planes (DimensionModel.relaxed, from the
        boundary of `base`, with `cache`) and the interior following by the harmonic
        extension; unchanged where an element would invert."""
        nodes = np.asarray(nodes, float)
        boundary = nodes[self.boundary]
        shift = self.surface.relaxed(
            boundary, None if base is None else np.asarray(base)[self.boundary], cache) \
            - boundary
        if not shift.any():
            return nodes
        out = nodes + self.extension.field(shift)
        if np.any(vm.signed_volumes(out, self.tets) <= 0):
            return nodes
        return out

    def quality(self, nodes=None):
        """The worst scaled Jacobian of the elements (of their linear sub-tetrahedra)."""
        return float(vm.scaled_jacobian(self.nodes if nodes is None else nodes, self.tets).min())

    def drive(self, kind, regions, target, origin=None, axis_point=None):
        """dd.drive on the boundary, its field extended to every node and its reach cut to
        where no tetrahedron inverts."""
        surface = dd.drive(self.surface, kind, regions, target, origin, axis_point)
        field = self.extension.field(surface.field)
        lo, hi = vm.inversion_reach(self.nodes, self.tets, field)
        reach = (max(lo, surface.reach[0]), min(hi, surface.reach[1]))
        boundary = self.boundary

        def measure(nodes):
            return surface.measure(nodes[boundary])
        return surface._replace(field=field, reach=reach, measure=measure)

    def deformed(self, drive):
        """The moved nodes, or DeformError naming Target when an element would invert."""
        lo, hi = drive.reach
        if not lo < drive.step < hi:
            raise DeformError(f"Target is beyond the deformable range: {dd.range_text(drive)}; "
                              "beyond it tetrahedra invert or boundary triangles flip. "
                              "Change Target.", "Target")
        surface = self.surface
        dd.clear_of_self(surface.vertices, surface.triangles,
                         drive._replace(field=drive.field[self.boundary]))
        return self.nodes + drive.step * drive.field
