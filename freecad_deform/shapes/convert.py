"""Conversions between FreeCAD values (Placement, Mesh, Points) and numpy arrays."""
import FreeCAD as App
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.planes import unit_normal

Z = App.Vector(0, 0, 1)


def plane_placement(plane, prop="Plane"):
    """A Placement whose local XY is the plane, from a Placement or an (origin, normal) tuple."""
    if isinstance(plane, App.Placement):
        return App.Placement(plane)
    try:
        origin, normal = plane
        origin, normal = App.Vector(*origin), App.Vector(*normal)
    except (TypeError, ValueError):
        raise DeformError(f"{prop} must be a Placement or a (point, direction) pair of vectors.", prop)
    n = unit_normal(tuple(normal), prop)
    return App.Placement(origin, App.Rotation(Z, App.Vector(*n)))


def plane_arrays(placement):
    """(origin, unit normal) as numpy arrays from a plane Placement.

    Rounding noise of the rotation (a 1e-16 component) is cleared, so points on an
    axis-aligned plane are exactly on it.
    """
    normal = np.array(tuple(placement.Rotation.multVec(Z)))
    normal[np.abs(normal) < 1e-12] = 0.0
    return np.array(tuple(placement.Base)), normal / np.linalg.norm(normal)


def vector(array):
    return App.Vector(*(float(x) for x in array))


def mesh_arrays(mesh):
    """(vertices (N,3) float, triangles (M,3) int) of a Mesh.Mesh, in global coordinates."""
    points, facets = mesh.Topology
    return (np.array([tuple(p) for p in points], float).reshape(-1, 3),
            np.array(facets, dtype=np.int64).reshape(-1, 3))


def mesh_from_arrays(vertices, triangles):
    """A Mesh.Mesh from vertex and triangle arrays (points must be Vectors: tuples crash Mesh)."""
    import Mesh
    return Mesh.Mesh(([App.Vector(*p) for p in np.asarray(vertices, float).tolist()],
                      [tuple(t) for t in np.asarray(triangles, int).tolist()]))


def points_array(points):
    """(N,3) array of a Points.Points kernel, in global coordinates."""
    return np.array([tuple(p) for p in points.Points], float).reshape(-1, 3)


def points_from_array(array):
    import Points
    return Points.Points([App.Vector(*p) for p in np.asarray(array, float).tolist()])
