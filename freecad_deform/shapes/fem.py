"""FreeCAD FEM meshes <-> arrays, for DimensionDrive on tetrahedral meshes."""
import numpy as np

from ..geometry.errors import DeformError


VOLUME_NAMES = {4: "linear tetrahedra", 5: "pyramids", 6: "pentahedra (wedges)",
                8: "hexahedra", 10: "quadratic tetrahedra", 13: "quadratic pyramids",
                15: "quadratic pentahedra", 20: "quadratic hexahedra"}


def is_fem_mesh(obj):
    """True when `obj` is a FEM mesh object (Fem::FemMeshObject or derived)."""
    return obj is not None and obj.isDerivedFrom("Fem::FemMeshObject")


def fem_arrays(femmesh):
    """(node ids (N,), nodes (N,3) in global coordinates, volume ids (E,), elements (E,4|10)
    as row indices into nodes) of a FemMesh whose volumes are all linear or all quadratic
    tetrahedra."""
    ids = np.array(sorted(femmesh.Nodes), np.int64)
    if len(ids) == 0:
        raise DeformError("Base holds no nodes; link a tetrahedral FEM mesh.", "Base")
    points = femmesh.Nodes
    nodes = np.array([tuple(points[i]) for i in ids.tolist()], float)
    volumes = np.array(femmesh.Volumes, np.int64)
    if len(volumes) == 0:
        raise DeformError("Base has no volume elements; link a tetrahedral FEM mesh.", "Base")
    connectivity = [femmesh.getElementNodes(v) for v in volumes.tolist()]
    sizes = {len(c) for c in connectivity}
    if not (sizes <= {4} or sizes <= {10}):
        found = ", ".join(VOLUME_NAMES.get(k, f"{k}-node elements") for k in sorted(sizes))
        raise DeformError(f"Base holds {found}, but only linear or only quadratic tetrahedra "
                          f"are supported; link a tetrahedral FEM mesh.", "Base")
    elements = np.searchsorted(ids, np.array(connectivity, np.int64))
    return ids, nodes, volumes, elements


def fem_with_nodes(femmesh, ids, nodes):
    """A new FemMesh with every node of `femmesh` (ids (N,)) at `nodes` (N,3): the same
    node and element numbers, the same elements (volumes, faces, edges) and groups."""
    import Fem
    out = Fem.FemMesh()
    for i, p in zip(ids.tolist(), np.asarray(nodes, float).tolist()):
        out.addNode(p[0], p[1], p[2], i)
    for e in femmesh.Edges:
        out.addEdge(list(femmesh.getElementNodes(e)), e)
    for f in femmesh.Faces:
        out.addFace(list(femmesh.getElementNodes(f)), f)
    for v in femmesh.Volumes:
        out.addVolume(list(femmesh.getElementNodes(v)), v)
    for g in femmesh.Groups:
        new = out.addGroup(femmesh.getGroupName(g), femmesh.getGroupElementType(g))
        elements = list(femmesh.getGroupElements(g))
        if elements:
            out.addGroupElements(new, elements)
    return out
