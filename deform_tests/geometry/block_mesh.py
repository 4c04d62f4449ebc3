"""A block with a vertical through hole as an FE-like surface mesh (interior vertices on
every face), built with numpy and scipy only, for the DimensionDrive kernel tests."""
import numpy as np
from scipy.spatial import Delaunay


def _ring(n):
    a = 2 * np.pi * np.arange(n) / n
    return np.column_stack([np.cos(a), np.sin(a)])


def block_with_hole(size=(100.0, 60.0, 30.0), centre=(50.0, 30.0), radius=8.0, step=5.0,
                    hole_segments=32):
    """(vertices, triangles) of the closed, outward-oriented mesh of the box
    [0,L]x[0,W]x[0,H] minus the cylinder of `radius` about the vertical line at `centre`."""
    L, W, H = size
    c = np.asarray(centre, float)
    nx, ny, nz = (max(2, int(round(d / step))) for d in (L, W, H))
    # outline of the top face: rectangle corners and edge points, counter-clockwise
    xs, ys = np.linspace(0, L, nx + 1), np.linspace(0, W, ny + 1)
    rect = np.concatenate([np.column_stack([xs[:-1], np.zeros(nx)]),
                           np.column_stack([np.full(ny, L), ys[:-1]]),
                           np.column_stack([xs[:0:-1], np.full(nx, W)]),
                           np.column_stack([np.zeros(ny), ys[:0:-1]])])
    circle = c + radius * _ring(hole_segments)
    gx, gy = np.meshgrid(xs[1:-1], ys[1:-1])
    inner = np.column_stack([gx.ravel(), gy.ravel()])
    inner = inner[np.linalg.norm(inner - c, axis=1) > radius + 0.5 * step]
    flat = np.concatenate([rect, circle, inner])
    tri = Delaunay(flat).simplices
    cent = flat[tri].mean(axis=1)
    tri = tri[np.linalg.norm(cent - c, axis=1) > radius]
    e1, e2 = flat[tri[:, 1]] - flat[tri[:, 0]], flat[tri[:, 2]] - flat[tri[:, 0]]
    ccw = (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) > 0
    tri = np.where(ccw[:, None], tri, tri[:, ::-1])
    nf = len(flat)
    heights = np.linspace(0, H, nz + 1)
    # vertices: one copy of the face outline per height (rings), interior points top and bottom
    outline = np.concatenate([rect, circle])
    no = len(outline)
    rings = np.concatenate([np.column_stack([outline, np.full(no, z)]) for z in heights])
    top_inner = np.column_stack([inner, np.full(len(inner), H)])
    bottom_inner = np.column_stack([inner, np.zeros(len(inner))])
    V = np.concatenate([rings, top_inner, bottom_inner])
    base_top, base_bottom = len(rings), len(rings) + len(inner)

    def face_index(level, inner_base):
        idx = np.empty(nf, np.int64)
        idx[:no] = level * no + np.arange(no)
        idx[no:] = inner_base + np.arange(len(inner))
        return idx

    top = face_index(nz, base_top)[tri]
    bottom = face_index(0, base_bottom)[tri][:, ::-1]
    walls = []
    for loop, outward in ((np.arange(len(rect)), True), (len(rect) + np.arange(len(circle)), False)):
        a, b = loop, np.roll(loop, -1)
        for k in range(nz):
            lo, hi = k * no, (k + 1) * no
            q = np.stack([lo + a, lo + b, hi + b, hi + a], 1)
            quads = q if outward else q[:, ::-1]
            walls += [quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]
    T = np.concatenate([top, bottom, *walls])
    return V, T
