"""Measures of closed triangle meshes in float64 (FreeCAD's Mesh sums in float32)."""
import numpy as np


def mesh_volume(vertices, triangles):
    """Enclosed volume by the divergence theorem: the sum of det(v0, v1, v2) / 6, coordinate
    by coordinate on contiguous columns (10x faster than stacking the corners), BLOCK
    triangles at a time (the temporaries stay in the CPU cache: 1.5x faster)."""
    from ..blocks import BLOCK
    x, y, z = np.ascontiguousarray(np.asarray(vertices, float).reshape(-1, 3).T)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    total = 0.0
    for i in range(0, len(T), BLOCK):
        a, b, c = np.ascontiguousarray(T[i:i + BLOCK].T)
        xb, yb, zb, xc, yc, zc = x.take(b), y.take(b), z.take(b), x.take(c), y.take(c), z.take(c)
        det = yb * zc
        det -= zb * yc
        det *= x.take(a)
        part = zb * xc
        part -= xb * zc
        part *= y.take(a)
        det += part
        part = xb * yc
        part -= yb * xc
        part *= z.take(a)
        det += part
        total += det.sum()
    return float(total / 6.0)
