"""Segmentation by dihedral angle on the block-with-hole mesh, whose faces we know."""
import numpy as np

from freecad_deform.geometry.mesh.regions import edge_triangles, region_adjacency, segment

from .block_mesh import block_with_hole


def test_every_face_is_one_region_and_the_hole_one_more():
    V, T = block_with_hole(hole_segments=32)              # the hole turns 11.25 deg per facet
    labels = segment(V, T, np.radians(40))
    assert labels.max() + 1 == 7
    assert np.all(np.diff(np.bincount(labels)) <= 0)      # the largest region first
    # a region is one face: its triangles share a normal (six planes) or the hole
    normals = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    flat = [r for r in range(7) if np.ptp(normals[labels == r], axis=0).max() < 1e-12]
    assert len(flat) == 6
    hole = ({*range(7)} - set(flat)).pop()
    touching = {a if b == hole else b for a, b in region_adjacency(T, labels) if hole in (a, b)}
    assert len(touching) == 2 and all(abs(normals[labels == r][0, 2]) == 1 for r in touching)


def test_the_threshold_splits_the_hole_into_its_facets():
    V, T = block_with_hole(hole_segments=32)
    assert segment(V, T, np.radians(10)).max() + 1 == 6 + 32


def test_a_vanishing_threshold_keeps_coplanar_triangles_together():
    """FeatureAngle 1e-66 deg: coplanar triangles whose normals differ by float32 rounding
    stay one region (each face, and each hole facet, one region: 6 + 32), instead of one
    region per triangle (which took two minutes to build a handle)."""
    V, T = block_with_hole(hole_segments=32)
    V = V.astype(np.float32).astype(float)   # FreeCAD's mesh points
    assert segment(V, T, np.radians(1e-66)).max() + 1 == 6 + 32


def test_edges_know_their_two_triangles():
    V, T = block_with_hole()
    edges, faces = edge_triangles(T)
    assert len(edges) == 3 * len(T) // 2 and np.all(faces >= 0)     # closed: no border
    for e, (f, g) in zip(edges[:50], faces[:50]):
        assert set(e) <= set(T[f]) and set(e) <= set(T[g]) and f != g
