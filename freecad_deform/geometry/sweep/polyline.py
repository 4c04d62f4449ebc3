"""Case 3 of Wu & Ilies: a piecewise-planar separating surface, given as a polyline that is
extruded perpendicular to its own plane (Fig. 4 and 13)."""
import numpy as np

from ..errors import DeformError
from .planes import unit_normal


class PolylineSurface:
    """The polyline `points` extruded along the normal of its plane.

    `normal` (the motion direction, toward the moving part) must lie in the polyline's
    plane; along the lateral direction u = e x normal the polyline must advance at every
    segment, so that the surface is the graph s = height(u) over u and splits space into a
    near side and a far side.
    """

    def __init__(self, points, normal, tol=1e-9):
        pts = np.asarray(points, float).reshape(-1, 3)
        n = unit_normal(normal)
        if len(pts) < 2:
            raise DeformError("Polyline needs at least two points.", "Polyline")
        spread = pts - pts[0]
        e = np.cross(n, spread[np.argmax(np.linalg.norm(np.cross(n, spread), axis=1))])
        if np.linalg.norm(e) < tol:
            raise DeformError("Polyline runs along the Plane normal; its points must spread "
                              "across the part.", "Polyline")
        e /= np.linalg.norm(e)
        scale = max(np.ptp(pts, axis=0).max(), 1.0)
        if np.abs(spread @ e).max() > tol * scale:
            raise DeformError("Polyline must lie in one plane that contains the Plane normal; "
                              "move its points into such a plane.", "Polyline")
        u = np.cross(e, n)
        lateral, height = pts @ u, pts @ n
        if np.any(np.diff(lateral) <= tol * scale):
            if np.all(np.diff(lateral) < -tol * scale):
                lateral, height, pts = lateral[::-1], height[::-1], pts[::-1]
            else:
                raise DeformError("Polyline folds back or has a segment along the Plane normal; "
                                  "give its points in order across the part.", "Polyline")
        self.points, self.normal, self.extrusion, self.lateral_axis = pts, n, e, u
        self.lateral, self.height = lateral, height

    def height_at(self, points):
        """The surface's coordinate along the normal above each point (ends extended)."""
        lat = np.asarray(points, float).reshape(-1, 3) @ self.lateral_axis
        slopes = np.diff(self.height) / np.diff(self.lateral)
        seg = np.clip(np.searchsorted(self.lateral, lat) - 1, 0, len(slopes) - 1)
        return self.height[seg] + slopes[seg] * (lat - self.lateral[seg])

    def offset(self, points):
        """Signed distance along the normal from the surface (positive on the far side)."""
        pts = np.asarray(points, float).reshape(-1, 3)
        return pts @ self.normal - self.height_at(pts)

    def segment_planes(self):
        """(point, unit normal) of each planar segment, the normal on the far side."""
        out = []
        for a, b in zip(self.points[:-1], self.points[1:]):
            m = np.cross(self.extrusion, b - a)
            m /= np.linalg.norm(m)
            out.append((a, m if m @ self.normal > 0 else -m))
        return out
