"""Conversions between FreeCAD values (Placement, Mesh, Points) and numpy arrays."""
import FreeCAD as App
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.sweep.planes import unit_normal

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


def matrix_array(placement):
    """The 4x4 homogeneous matrix of a Placement, as a numpy array."""
    return np.array(placement.toMatrix().A, float).reshape(4, 4)


def vector(array):
    return App.Vector(*(float(x) for x in array))


PLY_FROM = 20000   # facets: below this FreeCAD's Topology lists are as fast as a file
PLY_HEADER = ("property float32 x\nproperty float32 y\nproperty float32 z\nelement face {}\n"
              "property list uchar int vertex_index\nend_header\n")


def mesh_arrays(mesh):
    """(vertices (N,3) float, triangles (M,3) int) of a Mesh.Mesh, in global coordinates.

    Read from the binary PLY FreeCAD writes (its float32 points and facets in order, about
    ten times faster than its Topology lists); the placement applied in double afterwards,
    as Topology does. Topology is the fallback for a PLY of another layout."""
    import os
    import tempfile
    if mesh.CountFacets < PLY_FROM:
        return _topology_arrays(mesh)
    raw = mesh
    if not mesh.Placement.isIdentity():
        raw = mesh.copy()
        raw.Placement = App.Placement()
    handle, path = tempfile.mkstemp(suffix=".ply")
    os.close(handle)
    try:
        raw.write(path)
        with open(path, "rb") as f:
            data = f.read()
    finally:
        os.remove(path)
    end = data.find(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii", "replace")
    try:
        nv = int(header.split("element vertex ")[1].split()[0])
        nf = int(header.split("element face ")[1].split()[0])
    except (IndexError, ValueError):
        nv = nf = -1
    if nv < 0 or not header.endswith(PLY_HEADER.format(nf)) or \
            len(data) != end + 12 * nv + 13 * nf:
        return _topology_arrays(mesh)
    vertices = np.frombuffer(data, "<f4", 3 * nv, end).reshape(-1, 3).astype(float)
    faces = np.frombuffer(data, np.dtype([("n", "u1"), ("i", "<i4", 3)]), nf, end + 12 * nv)
    if raw is not mesh:
        m = matrix_array(mesh.Placement)
        vertices = vertices @ m[:3, :3].T + m[:3, 3]
    return vertices, faces["i"].astype(np.int64)


def _topology_arrays(mesh):
    points, facets = mesh.Topology
    flat = np.fromiter((c for p in points for c in p), float, count=3 * len(points))
    return flat.reshape(-1, 3), np.array(facets, dtype=np.int64).reshape(-1, 3)


def mesh_eps(vertices):
    """The mesh kernels' snapping distance for a mesh FreeCAD will store: four float32
    steps of its largest stored coordinate (about `storage_origin`; at least 1e-9). Points
    a cut makes closer than one float32 step to a vertex would be merged with it when
    stored, leaving a degenerate, non-manifold facet; within this distance the vertex is
    snapped onto the plane instead."""
    V = np.asarray(vertices, float).reshape(-1, 3)
    if not len(V):
        return 1e-9
    lo, hi = _bounds(V)
    origin = _origin(lo, hi)                  # |v - origin| is largest at a bound (monotonic)
    top = float(max((hi - origin).max(), (origin - lo).max()))
    return max(1e-9, 4 * float(np.finfo(np.float32).eps) * top)


FAR = 16.0   # a part farther than this many times its size from the origin is stored about it


def storage_origin(vertices):
    """(3,) the translation a mesh or cloud of these global coordinates is stored about.

    FreeCAD keeps the points as float32, whose step grows with the coordinate (0.5 at a
    UTM northing of 5.6e6), and the Placement in double: a part far from the origin
    compared with its size (a georeferenced scan, a Base with a Placement) is stored
    about the centre of its bounding box, with that Placement, so it keeps float32 steps
    of its size (stored whole, a 30 mm box at (665000, 5648000) mm came back 0.12 mm
    off). Zero for a part near the origin: its result has no Placement, as before."""
    V = np.asarray(vertices, float).reshape(-1, 3)
    return _origin(*_bounds(V)) if len(V) else np.zeros(3)


def _bounds(V):
    """(lowest, highest) of each column of V (N, 3): a reduction per column, 17x faster
    than V.min(axis=0) on a million rows (11 ms), which mesh_eps had in every recompute."""
    return (np.array([V[:, k].min() for k in range(3)]),
            np.array([V[:, k].max() for k in range(3)]))


def _origin(lo, hi):
    """storage_origin from the bounds: the largest |coordinate| is at one of them."""
    if max(np.abs(lo).max(), np.abs(hi).max()) <= FAR * max(float((hi - lo).max()),
                                                              np.finfo(float).tiny):
        return np.zeros(3)
    return (lo + hi) / 2


def mesh_from_arrays(vertices, triangles):
    """A Mesh.Mesh from vertex and triangle arrays (unused vertices left out), placed
    at `storage_origin` when the part lies far from the origin.

    Written in FreeCAD's own binary mesh format (.bms: float32 points, facets with their
    neighbours) and read by FreeCAD, which then has no points to merge and no neighbours
    to rebuild: 4x faster than a binary STL, 10x faster than Python lists. The neighbours
    come from one sparse matrix of the directed edges (`_neighbours`); a mesh where an
    edge is not shared by exactly two facets of opposite directions (open, non-manifold,
    flipped), or a FreeCAD that reads the file otherwise, goes through a binary STL
    instead, whose reader merges the points and rebuilds the neighbours.
    """
    V = np.asarray(vertices, float).reshape(-1, 3)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    used = np.bincount(T.ravel(), minlength=len(V)) > 0
    if not used.all():
        T = (np.cumsum(used) - 1)[T]
        V = V[used]
    origin = storage_origin(V)
    if origin.any():
        mesh = mesh_from_arrays(V - origin, T)
        mesh.Placement = App.Placement(vector(origin), App.Rotation())
        return mesh
    neighbours = _neighbours(T, len(V))
    if neighbours is None or not len(T):
        return _stl_mesh(V, T)
    P = V.astype("<f4")
    facets = np.empty((len(T), 6), "<u4")
    facets[:, :3] = T
    facets[:, 3:] = neighbours
    box = np.array([[c.min(), c.max()] for c in P.T], "<f4")   # columns: 20x faster
    try:
        mesh = _read_mesh(".bms", (np.array([0xA0B0C0D0, 0x010000], "<u4"), BMS_INFO,
                                   np.array([len(P), len(T)], "<u4"), P, facets, box))
    except Exception:   # noqa: BLE001  (a FreeCAD that reads another form: the STL)
        mesh = None
    if mesh is None or (mesh.CountPoints, mesh.CountFacets) != (len(P), len(T)):
        return _stl_mesh(V, T)
    return mesh


BMS_INFO = np.frombuffer(b"MESH-" * 51 + b"M", np.uint8)   # the format's 256-byte info


def _neighbours(T, N):
    """(M, 3) the facet across edge T[:, j] -> T[:, j+1] of each facet, or None unless every
    directed edge occurs once and its reverse once (a closed, consistently oriented
    2-manifold). The edges' sparse matrix then has a symmetric pattern, and its k-th entry
    in row order (a -> b) is the reverse of its k-th entry in column order (b -> a)."""
    from scipy.sparse import csr_matrix
    if N >= 2 ** 31 or 3 * len(T) >= 2 ** 31:
        return None
    T32 = T.astype(np.int32)
    a, b = T32.ravel(), T32[:, [1, 2, 0]].ravel()
    ids = np.arange(1, len(a) + 1, dtype=np.int32)
    rows = csr_matrix((ids, (a, b)), shape=(N, N))
    rows.sum_duplicates()                                   # sorted indices (a no-op if so)
    cols = rows.tocsc()
    if rows.nnz != len(a) or not (np.array_equal(rows.indptr, cols.indptr)
                                  and np.array_equal(rows.indices, cols.indices)):
        return None
    across = np.empty(len(a), np.int32)
    across[rows.data - 1] = (cols.data - 1) // 3
    return across.reshape(-1, 3)


def _stl_mesh(V, T):
    tri = V[T]
    record = np.zeros(len(tri), dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)),
                                       ("attribute", "<u2")])
    record["normal"] = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    record["corners"] = tri
    return _read_mesh(".stl", (np.zeros(80, np.uint8), np.array([len(tri)], "<u4"), record))


def _read_mesh(suffix, parts):
    """Mesh.Mesh read from a temporary file made of the arrays `parts`, in order."""
    import os
    import tempfile

    import Mesh
    handle, path = tempfile.mkstemp(suffix=suffix)
    try:
        with os.fdopen(handle, "wb") as out:
            for part in parts:
                out.write(np.ascontiguousarray(part).tobytes())
        return Mesh.Mesh(path)
    finally:
        os.remove(path)


def points_array(points):
    """(N,3) array of the finite points of a Points.Points kernel, in global coordinates.

    Scans carry points with NaN (or infinite) coordinates where the sensor got no return
    (an organized cloud keeps its grid that way); they are left out, so no distance,
    spacing or plane test sees them. The count left out is CountPoints - len(result).
    """
    pts = _saved_points(points)
    if pts is None:
        pts = np.array([tuple(p) for p in points.Points], float).reshape(-1, 3)
    elif not points.Placement.isIdentity():   # as points.Points gives them: placed in double
        m = matrix_array(points.Placement)
        pts = pts @ m[:3, :3].T + m[:3, 3]
    finite = np.isfinite(pts).all(axis=1)
    return pts if finite.all() else pts[finite]


def _saved_points(points):
    """The (N,3) float array of the kernel's own float32 points, unplaced, read from the
    binary form FreeCAD saves them in (uncompressed: 20x faster than its Vector list for a
    million points), or None when that form is not the one expected."""
    import io
    import zipfile
    try:
        archive = zipfile.ZipFile(io.BytesIO(bytes(points.dumpContent(Compression=0))))
        name = next(n for n in archive.namelist() if n != "Persistence.xml")
        data = archive.read(name)
    except Exception:   # noqa: BLE001  (another FreeCAD, another form)
        return None
    count = int(np.frombuffer(data[:4], "<u4")[0]) if len(data) >= 4 else -1
    if count != points.CountPoints or len(data) != 4 + 12 * count:
        return None
    return np.frombuffer(data, "<f4", 3 * count, 4).reshape(-1, 3).astype(float)


def points_from_array(array):
    """A Points.Points of the (N,3) array, restored from the binary form FreeCAD saves it in
    (a count, then float32 x y z; it stores float32 either way): seven times faster than a
    list of Vectors for a million points. Placed at `storage_origin` of its finite points
    when they lie far from the origin."""
    import io
    import zipfile

    import Points
    array = np.asarray(array, float).reshape(-1, 3)
    bounds = _bounds(array) if len(array) else None
    if bounds is not None and np.isfinite(bounds).all():    # (no point to leave out: no copy)
        origin = _origin(*bounds)
    else:
        origin = storage_origin(array[np.isfinite(array).all(axis=1)])
    pts = np.ascontiguousarray(array - origin if origin.any() else array, dtype="<f4")
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        archive.writestr("Persistence.xml", '<Content>\n<Points file="points" mtrx="1 0 0 0 '
                         '0 1 0 0 0 0 1 0 0 0 0 1 "/>\n</Content>')
        archive.writestr("points", np.uint32(len(pts)).tobytes() + pts.tobytes())
    result = Points.Points()
    try:
        result.restoreContent(buffer.getvalue())
    except Exception:   # noqa: BLE001  (a FreeCAD that reads another form: the slow way)
        pass
    if result.CountPoints != len(pts):
        result = Points.Points([App.Vector(*p) for p in pts.astype(float).tolist()])
    if origin.any():
        result.Placement = App.Placement(vector(origin), App.Rotation())
    return result


def tessellated(shape, tolerance):
    """(vertices, triangles, Mesh) of a shape meshed with the linear deflection `tolerance`."""
    import MeshPart
    mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=float(tolerance),
                                  AngularDeflection=0.5, Relative=False)
    return (*mesh_arrays(mesh), mesh)


def moved_mesh(mesh, vertices):
    """A copy of `mesh` with its points moved to `vertices` (N,3): same facets, same order.

    setPoint leaves the kernel's bounding box as the copy had it; FreeCAD's grids are
    built on that box, and its self-intersection test ended the whole process on a mesh
    with points beyond it (a DimensionDrive lengthening a part). The identity transform
    recomputes the box (its points stay bit for bit)."""
    result = mesh.copy()
    for i, p in enumerate(np.asarray(vertices, float).tolist()):
        result.setPoint(i, App.Vector(*p))
    result.transform(App.Matrix())
    return result


def box_arrays(bound_box):
    """(lo, hi): the min and max corners of a FreeCAD BoundBox as numpy arrays."""
    return (np.array([bound_box.XMin, bound_box.YMin, bound_box.ZMin]),
            np.array([bound_box.XMax, bound_box.YMax, bound_box.ZMax]))
