"""Dimension-driven mesh deformation (Date & Onosato 2008, sections 4.3-4.4).

DimensionModel holds what depends on the mesh only (regions, fits, simplified mesh,
handle and its coordinates); drive() turns a dimension type, the picked regions and a
target into new vertex positions. Every manipulation here moves the handle linearly in
one parameter s (the change of the dimension), so the vertices are x + s * field with
field = B @ (handle motion per unit s): one sparse product, and the range of s in which
no triangle turns over is the root of one quadratic per triangle.
"""
from typing import Callable, NamedTuple

import numpy as np
from scipy.sparse import csr_matrix, diags
from scipy.sparse.linalg import spsolve
from scipy.spatial import ConvexHull

from .dimension_handle import build_handle, triangle_fit
from ..errors import DeformError
from .fits import fit_cylinder, fit_plane
from .intersect import new_intersections
from .regions import (edge_triangles, region_adjacency, segment, triangle_normals,
                      vertex_regions)
from .simplify import simplify
from ..vectors import unit

KINDS = ("Distance", "Radius", "Position", "Angle")
FIT_TOLERANCE = 1e-4   # a region is a plane / cylinder when its fit deviates less (x size)
HANDLE_TOLERANCE = 5e-3  # handle simplification error (x size)
PARALLEL = 1e-3        # radians: two planes closer than this are parallel
SOFT = 1e3             # weight of leaving a free-form region, against 1 for rounding a cylinder
NO_FLIP = 1e6          # mesh sizes of motion beyond which a triangle's flip is no limit


class Drive(NamedTuple):
    current: tuple        # the dimension before: (value,) or (u, v)
    step: float           # s: how far the target is along the drive
    field: np.ndarray     # (N,3) vertex motion per unit of s
    reach: tuple          # (lo, hi): the interval of s in which no triangle turns over
    measure: Callable     # deformed vertices -> the dimension, like `current`
    strained: int = 0     # control vertices that could not keep all planes/cylinders around
    value: Callable = None  # s -> the dimension (Angle: not current + s); None: current + s


def reach_values(drive):
    """(lowest, highest) value the dimension reaches within drive.reach (one-value kinds)."""
    if drive.value is None:
        return drive.current[0] + drive.reach[0], drive.current[0] + drive.reach[1]
    ends = sorted(drive.value(s) for s in drive.reach)
    return ends[0], ends[1]


def _worst_shape(X, triangles):
    """The smallest 4 sqrt(3) area / (sum of squared edges) of the triangles (1: equilateral)."""
    x = X[triangles]
    e = x[:, [1, 2, 0]] - x
    area = 0.5 * np.linalg.norm(np.cross(e[:, 0], e[:, 1]), axis=1)
    return float((4 * np.sqrt(3) * area / np.maximum((e * e).sum(axis=(1, 2)), 1e-300)).min(
        initial=1.0))


def cotangent_laplacian(vertices, triangles):
    """The (N, N) cotangent Laplacian of a mesh, weights kept above 1e-3 (positive)."""
    x = vertices[triangles]
    cot = []                                  # at each corner, of the edge across it
    for k in range(3):
        a, b = x[:, (k + 1) % 3] - x[:, k], x[:, (k + 2) % 3] - x[:, k]
        cot.append(np.einsum("ij,ij->i", a, b)
                   / np.maximum(np.linalg.norm(np.cross(a, b), axis=1), 1e-300))
    w = np.maximum(np.stack(cot, 1), 1e-3)
    i = triangles[:, [1, 2, 0, 2, 0, 1]].ravel()
    j = triangles[:, [2, 0, 1, 1, 2, 0]].ravel()
    n = len(vertices)
    A = csr_matrix((np.concatenate([w, w], axis=1).ravel(), (i, j)), (n, n))
    return diags(np.asarray(A.sum(axis=1)).ravel()) - A


def flipped(before, after, triangles):
    """Which triangles turn by 90 degrees or more from `before` to `after`."""
    x, y = before[triangles], after[triangles]
    n0 = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    n1 = np.cross(y[:, 1] - y[:, 0], y[:, 2] - y[:, 0])
    return np.einsum("ij,ij->i", n0, n1) <= 0


def _surface_distance(points, normals, tolerance):
    """A function giving distances to the region's plane or cylinder, or None when the
    region (points, triangle normals) is neither within `tolerance`."""
    plane = fit_plane(points, normals)
    if plane.rms <= tolerance:
        return lambda q: np.abs(q @ plane.normal - plane.offset)
    if len(points) >= 6:
        cyl = fit_cylinder(points, normals)
        if cyl.rms <= tolerance:
            def distance(q):
                d = q - cyl.point
                return np.abs(np.linalg.norm(d - np.outer(d @ cyl.axis, cyl.axis), axis=1)
                              - cyl.radius)
            return distance
    return None


def absorb(vertices, triangles, normals, labels, tolerance):
    """Labels with every region whose vertices all lie on a neighbouring region's plane or
    cylinder merged into that neighbour. Dihedral angles alone split a surface where a
    mesher left a few badly shaped triangles (a chord of a hole wall reaching far round
    the circle); fitting, as in the paper's reference [1], puts them back."""
    labels = np.unique(labels, return_inverse=True)[1].reshape(-1)
    surfaces = {}
    inner = edge_triangles(triangles)[1]
    inner = inner[inner[:, 1] >= 0]          # the two triangles of every inner edge

    def surface(r):
        if r not in surfaces:
            mask = labels == r
            surfaces[r] = _surface_distance(vertices[np.unique(triangles[mask])],
                                            normals[mask], tolerance)
        return surfaces[r]

    merged = True
    while merged:
        merged = False
        sizes = np.bincount(labels)
        a, b = labels[inner[:, 0]], labels[inner[:, 1]]
        near = {}                            # each region's neighbours (sets, as they were)
        for x, y in {(int(x), int(y)) for x, y in np.unique(
                np.sort(np.stack([a, b], 1)[a != b], axis=1), axis=0)}:
            near.setdefault(x, set()).add(y)
            near.setdefault(y, set()).add(x)
        groups = np.split(np.argsort(labels, kind="stable"), np.cumsum(sizes)[:-1])
        for r in np.argsort(sizes, kind="stable").tolist():
            points = None
            for q in sorted(near.get(r, ()), key=lambda q: -sizes[q]):
                if sizes[q] < sizes[r]:
                    break
                if surface(q) is None:
                    continue
                if points is None:
                    points = vertices[np.unique(triangles[groups[r]])]
                if np.all(surface(q)(points) <= tolerance):
                    labels[groups[r]] = q
                    surfaces.pop(q)
                    merged = True
                    break
            if merged:
                break
    return np.unique(labels, return_inverse=True)[1].reshape(-1)


class DimensionModel:
    """Regions, fits, simplified mesh and handle of one mesh, computed once."""

    STEPS = 4  # progress() is called after segmenting, fitting, simplifying, binding

    def __init__(self, vertices, triangles, feature_angle, handle_tolerance=None,
                 progress=lambda: None):
        self.vertices = np.asarray(vertices, float)
        self.triangles = np.asarray(triangles, np.int64)
        self.settings = (feature_angle, handle_tolerance)     # for rebuilt()
        V, T = self.vertices, self.triangles
        self.size = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0))) if len(V) else 0.0
        if len(T) == 0 or self.size == 0:
            raise DeformError("Base has no triangles; link a mesh or a solid.", "Base")
        self.normals, self.areas = triangle_normals(V, T)
        self.tolerance = FIT_TOLERANCE * self.size
        labels = segment(V, T, feature_angle)
        progress()
        self.labels = absorb(V, T, self.normals, labels, self.tolerance)
        self.count = int(self.labels.max()) + 1
        self.regions = vertex_regions(len(V), T, self.labels)     # (N, K) incidence
        self.planes = [self._plane(r) for r in range(self.count)]
        self.planar = np.array([p.rms <= self.tolerance for p in self.planes])
        self._cylinders = {}
        progress()
        tol = (handle_tolerance if handle_tolerance else HANDLE_TOLERANCE * self.size)
        self.simplified = simplify(V, T, self.labels, tol)
        progress()
        self.handle = build_handle(V, T, self.labels, self.planar, self.simplified)
        progress()

    def rebuilt(self, vertices):
        """The model of the same triangles at new vertex positions (a new handle)."""
        return DimensionModel(vertices, self.triangles, *self.settings)

    def relaxed(self, vertices, base=None, cache=None):
        """`vertices` (this model's moved) with those inside a planar region (all their
        triangles on it) moved within its plane toward the mean of their neighbours
        (weights: cotangents of the `base` mesh, the same mesh before any drive; default
        this model), the region's boundary fixed: a plane a drive stretched on one side
        (round a grown hole) gets its vertices evened out for the next handle, every plane
        stays where it is. Of the whole move and its halves, the one whose worst triangle
        is best shaped, flipping none (none: `vertices`). `cache`: a dict kept by a caller
        that relaxes several models of the same `base` (rehandled), which holds its
        Laplacian."""
        T = self.triangles
        one = np.diff(self.regions.indptr) == 1                # on one region only
        inside = one.copy()
        inside[one] = self.planar[self.regions.indices[self.regions.indptr[:-1][one]]]
        if not inside.any():
            return vertices
        cache = {} if cache is None else cache
        if "laplacian" not in cache:
            cache["laplacian"] = cotangent_laplacian(
                self.vertices if base is None else np.asarray(base, float), T)
        L = cache["laplacian"]
        free = np.flatnonzero(inside)
        fixed = np.flatnonzero(~inside)
        given = np.asarray(vertices, float)
        Y = given.copy()
        Y[free] = spsolve(L[free][:, free].tocsc(), -(L[free][:, fixed] @ Y[fixed]))\
            .reshape(-1, 3)
        near = np.isin(T, free).any(axis=1)
        # only the triangles near a free vertex change; the others are those of `given`
        if flipped(self.vertices, given, T[~near]).any():
            return given
        T = T[near]
        best, score = given, _worst_shape(given, T)
        for t in 0.5 ** np.arange(RELAX_HALVINGS):
            X = given + t * (Y - given)
            q = _worst_shape(X, T)
            if q > score and not flipped(self.vertices, X, T).any():
                best, score = X, q
        return best

    # --- regions ----------------------------------------------------------------------------
    def region_vertices(self, label):
        return np.unique(self.triangles[self.labels == label])

    def _plane(self, label):
        mask = self.labels == label
        return fit_plane(self.vertices[np.unique(self.triangles[mask])], self.normals[mask])

    def cylinder(self, label):
        """The cylinder fit of a region, or None when the region is no cylinder."""
        if label not in self._cylinders:
            fit = None
            if not self.planar[label]:
                mask = self.labels == label
                fit = fit_cylinder(self.vertices[self.region_vertices(label)], self.normals[mask])
                if not (fit.rms <= self.tolerance and fit.radius < 1e3 * self.size):
                    fit = None
            self._cylinders[label] = fit
        return self._cylinders[label]

    def triangle_at(self, point):
        """The triangle nearest `point` (exact point-triangle distances)."""
        p = np.asarray(point, float).reshape(3)
        tri = self.vertices[self.triangles]
        distance, _ = triangle_fit(p, tri[:, 0], tri[:, 1], tri[:, 2], self.normals)
        return int(np.argmin(distance))

    def region_at(self, point):
        """The region of the triangle nearest `point`."""
        return int(self.labels[self.triangle_at(point)])

    def regions_of(self, vertex):
        row = self.regions.indices[self.regions.indptr[vertex]:self.regions.indptr[vertex + 1]]
        return [int(r) for r in row]

    def colours(self):
        """Region label per triangle (for display)."""
        return self.labels

    # --- motion -----------------------------------------------------------------------------
    def control(self, labels):
        """The simplified vertices on the given regions: the control space."""
        owners = np.unique(self.handle.owner)
        on = np.asarray(self.regions[owners][:, list(labels)].sum(axis=1)).reshape(-1) > 0
        return owners[on]

    def field(self, motion_of_owner, affine=None):
        """Vertex motion per unit s: handle points move by their owner's translation
        `motion_of_owner` (N,3) plus, for owners flagged in affine[0] (N,), the linear map
        affine[1] (3,3) about the point affine[2]."""
        H = self.handle
        moves = motion_of_owner[H.owner]
        if affine is not None:
            flagged, L, centre = affine
            sel = flagged[H.owner]
            moves[sel] += (H.points[sel] - centre) @ L.T
        return np.asarray(H.displace(moves))

    def reach(self, field):
        """(lo, hi): the interval of s around 0 in which no triangle's normal turns by 90
        degrees or more when the vertices move by s * field; infinite on a side where none
        turns before the vertices moved NO_FLIP mesh sizes (a triangle stretched along its
        plane has a root from rounding alone there, e.g. 5.7e15 on a 20 mm cube)."""
        T = self.triangles
        x, f = self.vertices[T], field[T]
        e1, e2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        f1, f2 = f[:, 1] - f[:, 0], f[:, 2] - f[:, 0]
        n0 = np.cross(e1, e2)
        a = np.einsum("ij,ij->i", n0, n0)
        b = np.einsum("ij,ij->i", n0, np.cross(e1, f2) + np.cross(f1, e2))
        c = np.einsum("ij,ij->i", n0, np.cross(f1, f2))
        live = (a > 0) & ((b != 0) | (c != 0))
        a, b, c = a[live], b[live], c[live]
        with np.errstate(divide="ignore", invalid="ignore"):
            disc = b * b - 4 * a * c
            sq = np.sqrt(np.maximum(disc, 0))
            q = -0.5 * (b + np.copysign(sq, b))          # stable roots: q / c and a / q
            r1 = np.where(c != 0, q / c, np.inf)
            r2 = np.where(q != 0, a / q, np.inf)
            real = (disc >= 0)[:, None]
            roots = np.where(real, np.stack([r1, r2], 1), np.inf)
        far = NO_FLIP * self.size / max(float(np.abs(field).max(initial=0.0)), 1e-300)
        roots = np.where(np.abs(roots) > far, np.inf, roots)
        pos = np.where(roots > 0, roots, np.inf).min(initial=np.inf)
        neg = np.where(roots < 0, roots, -np.inf).max(initial=-np.inf)
        return float(neg), float(pos)

    # --- constraints ------------------------------------------------------------------------
    def _forbidden(self, vertex, label):
        """(hard, soft): the directions a vertex on region `label` may not move along to
        keep that region a plane (its normal) or a cylinder (its normal there), and those
        it should rather not: round a cylinder (sliding along the axis keeps the rim a
        circle; round it only when the axis leaves no other way, e.g. a side plane moving
        across a cylinder whose axis is parallel to it); off a free-form region."""
        if self.planar[label]:
            return [self.planes[label].normal], []
        cyl = self.cylinder(label)
        if cyl is not None:
            d = self.vertices[vertex] - cyl.point
            radial = d - (d @ cyl.axis) * cyl.axis
            if np.linalg.norm(radial) < 1e-12 * self.size:
                return [], []
            radial = unit(radial)
            return [radial], [np.cross(cyl.axis, radial)]
        at = np.any(self.triangles == vertex, axis=1) & (self.labels == label)
        return [], [SOFT * unit((self.normals[at] * self.areas[at, None]).sum(axis=0))]

    def constraint(self, vertex, direction, moving):
        """(c, exact): the paper's constraint vector at `vertex`, scaled so c . direction
        = 1. Exact: c keeps every plane and cylinder at the vertex (outside the `moving`
        regions) what it is, and moves as little as it can across free-form ones. Where
        those planes and cylinders leave no such direction (four faces meeting), c is the
        least-squares compromise and exact is False."""
        hard, soft = [], []
        for r in self.regions_of(vertex):
            if r not in moving:
                strict, rows = self._forbidden(vertex, r)
                hard.extend(strict)
                soft.extend(rows)
        hard, soft = np.array(hard).reshape(-1, 3), np.array(soft).reshape(-1, 3)
        N = np.eye(3)
        if len(hard):
            _, s, vt = np.linalg.svd(hard)
            N = vt[int(np.sum(s > 1e-6 * s[0])):].T               # the directions left free
        exact = N.shape[1] > 0 and np.linalg.norm(N.T @ direction) > 1e-3
        if not exact:
            N, soft = np.eye(3), np.concatenate([SOFT * hard, soft / SOFT])
        # the least |c|^2 + |soft c|^2 with c . direction = 1, c in the free directions:
        # a long slide (a rim along an axis almost across the motion) costs its length
        M = soft @ N
        y = np.linalg.solve(np.eye(N.shape[1]) + M.T @ M, N.T @ direction)
        c = N @ y
        return c / (c @ direction), exact


def _two_regions(model, regions, what):
    labels = [model.region_at(p) for p in regions]
    if len(set(labels)) < len(labels):
        raise DeformError(f"Regions: two of the points pick the same region; {what}.", "Regions")
    return labels


def _two_planes(model, regions, kind, moving, planes, advice):
    """The region labels of the two points in `regions`, which must pick two different
    planar regions: `moving` first, then the reference."""
    if len(regions) != 2:
        raise DeformError(f"Regions: {kind} needs two points, on {moving} and on the "
                          f"reference plane.", "Regions")
    a, b = _two_regions(model, regions, advice)
    for label, which in ((a, "first"), (b, "second")):
        if not model.planar[label]:
            raise DeformError(f"Regions: the {which} point picks a region that is not a plane; "
                              f"{kind} needs two {planes}.", "Regions")
    return a, b


def distance_drive(model, regions, target):
    """DP: move the first picked plane along its normal so its distance to the second
    (the reference) is `target`; the planes around it slide along their constraint vectors."""
    a, b = _two_planes(model, regions, "Distance", "the moving plane", "parallel planes",
                       "pick two different parallel planes")
    pa, pb = model.planes[a], model.planes[b]
    angle = np.arcsin(min(1.0, np.linalg.norm(np.cross(pa.normal, pb.normal))))
    if angle > PARALLEL:
        raise DeformError(f"Regions: the two planes are not parallel (they meet at "
                          f"{np.degrees(angle):.3g} degrees); pick two parallel planes.", "Regions")
    n = pa.normal
    ca = model.vertices[model.region_vertices(a)].mean(axis=0)
    cb = model.vertices[model.region_vertices(b)].mean(axis=0)
    if (ca - cb) @ n < 0:
        n = -n
    current = float((ca - cb) @ n)
    motion = np.zeros_like(model.vertices)
    strained = 0
    for v in model.control([a]):
        if b in model.regions_of(v):
            raise DeformError("Regions: the two planes touch; pick two planes apart.", "Regions")
        c, exact = model.constraint(v, n, {a})
        if np.linalg.norm(c) > 1e3:
            raise DeformError("Regions: a corner of the moving plane cannot slide along the "
                              "faces around it (they are parallel to the plane); pick "
                              "another plane.", "Regions")
        motion[v] = c
        strained += not exact

    def measure(vertices):
        qa = vertices[model.region_vertices(a)]
        qb = vertices[model.region_vertices(b)]
        return (float(abs((qa.mean(axis=0) - qb.mean(axis=0)) @ fit_plane(qa).normal)),)

    field = model.field(motion)
    return Drive((current,), float(target) - current, field, model.reach(field), measure,
                 strained)


def radius_drive(model, regions, target):
    """RC: scale the picked cylinder about its axis to radius `target`; where it meets a
    plane that its scaling would leave, its rim slides along the axis to stay on it."""
    if len(regions) != 1:
        raise DeformError("Regions: Radius needs one point, on the cylinder.", "Regions")
    label = model.region_at(regions[0])
    cyl = model.cylinder(label)
    if cyl is None:
        kind = "a plane" if model.planar[label] else "not a cylinder"
        raise DeformError(f"Regions: the picked region is {kind}; Radius needs a point on a "
                          "cylindrical face.", "Regions")
    a = cyl.axis
    across = (np.eye(3) - np.outer(a, a)) / cyl.radius     # radial motion per unit radius
    motion = np.zeros_like(model.vertices)
    owners = model.control([label])
    for v in owners:
        radial = across @ (model.vertices[v] - cyl.point)
        for r in model.regions_of(v):
            if r != label and model.planar[r]:
                m = model.planes[r].normal
                if abs(a @ m) > 0.1 and abs(radial @ m) > 1e-12:
                    motion[v] -= (radial @ m) / (a @ m) * a
    flagged = np.zeros(len(model.vertices), bool)
    flagged[owners] = True

    def measure(vertices):
        mask = model.labels == label
        q = vertices[model.region_vertices(label)]
        return (fit_cylinder(q, triangle_normals(vertices, model.triangles[mask])[0]).radius,)

    field = model.field(motion, (flagged, across, cyl.point))
    return Drive((cyl.radius,), float(target) - cyl.radius, field, model.reach(field), measure)


def _feature(model, base, picked, extra):
    """The regions of the object on the base plane: the picked ones, and the regions
    reached from them (not through the base) that lie over the picked region's footprint."""
    n = model.planes[base].normal
    u = np.cross(n, np.eye(3)[np.argmin(np.abs(n))])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)

    def flat(label):
        q = model.vertices[model.region_vertices(label)]
        return np.column_stack([q @ u, q @ w])

    hull = ConvexHull(flat(picked), qhull_options="QJ")
    slack = 1e-6 * model.size
    adjacency = region_adjacency(model.triangles, model.labels)
    objects, todo = {picked, *extra}, [picked, *extra]
    while todo:
        r = todo.pop()
        for x, y in adjacency:
            other = y if x == r else x if y == r else None
            if other is None or other in objects or other == base:
                continue
            xy = flat(other)
            if np.all(hull.equations[:, :2] @ xy.T + hull.equations[:, 2:] <= slack):
                objects.add(other)
                todo.append(other)
    return objects


def position_drive(model, regions, target, origin, axis_point):
    """PO: translate the object on the base plane so its reference point is at `target`
    (u, v) in the frame (origin, axis_point, base normal), both points projected on the
    plane; with origin = axis_point, u runs along the global x (y if x is normal to it)."""
    if len(regions) < 2:
        raise DeformError("Regions: Position needs a point on the base plane and a point on "
                          "the feature.", "Regions")
    labels = _two_regions(model, regions, "pick the base plane and the feature")
    base, picked, extra = labels[0], labels[1], labels[2:]
    if not model.planar[base]:
        raise DeformError("Regions: the first point must pick a plane (the base of the "
                          "feature).", "Regions")
    n = model.planes[base].normal
    o = np.asarray(origin, float)
    o = o - ((o @ n) - model.planes[base].offset) * n
    du = np.asarray(axis_point, float) - np.asarray(origin, float)
    if np.linalg.norm(du) < 1e-12 * model.size:      # no frame given: the global x (or y)
        du = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
    du -= (du @ n) * n
    if np.linalg.norm(du) < 1e-9 * model.size:
        raise DeformError("AxisPoint - Origin is perpendicular to the base plane; pick a "
                          "point along the plane.", "AxisPoint")
    eu = unit(du)
    ev = np.cross(n, eu)
    objects = _feature(model, base, picked, extra)
    cyl = model.cylinder(picked)
    axis = cyl.axis if cyl is not None and abs(cyl.axis @ n) > 0.1 else n

    def reference(vertices, plane_offset):
        if cyl is not None and axis is cyl.axis:
            mask = model.labels == picked
            fit = fit_cylinder(vertices[model.region_vertices(picked)],
                               triangle_normals(vertices, model.triangles[mask])[0])
            p = fit.point + (plane_offset - fit.point @ n) / (fit.axis @ n) * fit.axis
        else:
            idx = np.unique(model.triangles[np.isin(model.labels, list(objects))])
            p = vertices[idx].mean(axis=0)
        return float((p - o) @ eu), float((p - o) @ ev)

    current = reference(model.vertices, model.planes[base].offset)
    goal = np.asarray(target, float).reshape(2) - current
    step = float(np.linalg.norm(goal))
    direction = (goal[0] * eu + goal[1] * ev) / step if step > 0 else eu
    motion = np.zeros_like(model.vertices)
    for v in model.control(objects):
        t = direction.copy()
        for r in model.regions_of(v):
            if r not in objects and model.planar[r]:
                m = model.planes[r].normal
                if abs(t @ m) > 1e-12:
                    if abs(axis @ m) < 0.1:
                        raise DeformError("Regions: the feature meets a plane it cannot slide "
                                          "along; pick another feature.", "Regions")
                    t -= (t @ m) / (axis @ m) * axis
        motion[v] = t

    def measure(vertices):
        return reference(vertices, fit_plane(vertices[model.region_vertices(base)]).offset)

    field = model.field(motion)
    return Drive(current, step, field, model.reach(field), measure)


def angle_drive(model, regions, target):
    """Angle: turn the first picked plane about its line of intersection with the second
    (the hinge) so the wedge between them (from the hinge into each region) is `target`
    degrees. The plane's vertices move along its normal by s times their distance from the
    hinge (the paper's constraint vectors, scaled): an affine map of the plane, which turns
    it by atan(s) exactly and keeps it a plane; the faces around it slide as for Distance."""
    a, b = _two_planes(model, regions, "Angle", "the plane that turns", "planes",
                       "pick two planes that meet")

    def wedge(vertices, planes):
        (na, da), (nb, db) = planes
        hinge = np.cross(na, nb)
        if np.linalg.norm(hinge) < np.sin(PARALLEL):
            raise DeformError("Regions: the two planes are parallel; Angle needs two planes "
                              "that meet (use Distance for parallel ones).", "Regions")
        hinge = unit(hinge)
        ca = vertices[model.region_vertices(a)].mean(axis=0)
        cb = vertices[model.region_vertices(b)].mean(axis=0)
        c = np.linalg.solve(np.array([na, nb, hinge]), [da, db, hinge @ ca])
        u, v = ca - c, cb - c
        u, v = unit(u - (u @ hinge) * hinge), unit(v - (v @ hinge) * hinge)
        return c, hinge, u, v, float(np.degrees(np.arccos(np.clip(u @ v, -1, 1))))

    pa, pb = model.planes[a], model.planes[b]
    c, hinge, u, v, current = wedge(model.vertices, ((pa.normal, pa.offset),
                                                      (pb.normal, pb.offset)))
    w = pa.normal
    sigma = 1.0 if w @ v > 0 else -1.0       # turning u toward w closes the wedge
    motion = np.zeros_like(model.vertices)
    strained = 0
    for vertex in model.control([a]):
        beta = (model.vertices[vertex] - c) @ u
        if abs(beta) < 1e-12 * model.size:
            continue                          # on the hinge
        cv, exact = model.constraint(vertex, w, {a})
        if np.linalg.norm(cv) > 1e3:
            raise DeformError("Regions: an edge of the turning plane cannot slide along the "
                              "faces around it; pick another plane.", "Regions")
        motion[vertex] = beta * cv
        strained += not exact
    if not 0 < target < 180:
        raise DeformError("Target must be an angle between 0 and 180 degrees.", "Target")
    turn = sigma * np.radians(current - target)
    if abs(turn) >= np.pi / 2:
        raise DeformError("Target turns the plane by 90 degrees or more; change Target in "
                          "steps below 90 degrees.", "Target")

    def measure(vertices):
        planes = [fit_plane(vertices[model.region_vertices(r)]) for r in (a, b)]
        return (wedge(vertices, [(p.normal, p.offset) for p in planes])[4],)

    field = model.field(motion)
    return Drive((current,), float(np.tan(turn)), field, model.reach(field), measure, strained,
                 lambda s: current - sigma * float(np.degrees(np.arctan(s))))


def matching_regions(model, regions, other):
    """Points on the mesh of DimensionModel `other`, one per picked region of `model`, on
    the region of `other` that lies on the same plane or cylinder (the mating surface of
    an assembly: a shaft in a bore, a face against a face; Date & Onosato, Fig. 8)."""
    tol = FIT_TOLERANCE * max(model.size, other.size)
    centres = other.vertices[other.triangles].mean(axis=1)
    out = []
    for p in regions:
        label = model.region_at(p)
        best, score = None, np.inf
        if model.planar[label]:
            plane = model.planes[label]
            for r in np.nonzero(other.planar)[0]:
                q = other.planes[r]
                cos = q.normal @ plane.normal
                gap = abs(q.offset - np.sign(cos) * plane.offset)
                if abs(abs(cos) - 1) < 1e-9 and gap <= tol and gap < score:
                    best, score = r, gap
        elif model.cylinder(label) is not None:
            cyl = model.cylinder(label)
            for r in range(other.count):
                q = other.cylinder(r)
                if q is None or np.linalg.norm(np.cross(q.axis, cyl.axis)) > 1e-6:
                    continue
                d = q.point - cyl.point
                gap = max(abs(q.radius - cyl.radius),
                          np.linalg.norm(d - (d @ cyl.axis) * cyl.axis))
                if gap <= tol and gap < score:
                    best, score = r, gap
        if best is None:
            raise DeformError("Regions: the other mesh has no plane or cylinder where the "
                              f"region picked at {tuple(np.round(p, 6))} lies; pick regions "
                              "the two meshes share.", "Regions")
        mine = np.nonzero(other.labels == best)[0]
        middle = centres[mine].mean(axis=0)
        out.append(tuple(float(c) for c in
                         centres[mine[np.argmin(np.linalg.norm(centres[mine] - middle, axis=1))]]))
    return out


def drive(model, kind, regions, target, origin=None, axis_point=None):
    """The Drive of one dimension change (see the module docstring). The regions are
    checked before the target, so the first error names what to fix first."""
    if kind == "Distance":
        result = distance_drive(model, regions, target)
    elif kind == "Radius":
        result = radius_drive(model, regions, target)
    elif kind == "Angle":
        return angle_drive(model, regions, target)
    elif kind == "Position":
        if origin is None or axis_point is None:
            raise DeformError("Origin and AxisPoint are needed for Position.", "Origin")
        return position_drive(model, regions, target, origin, axis_point)
    else:
        raise DeformError(f"Kind must be one of {', '.join(KINDS)}.", "Kind")
    if not target > 0:
        raise DeformError(f"Target must be a positive {kind.lower()}.", "Target")
    return result


def deformed(model, result):
    """The moved vertices of a Drive, or DeformError naming Target when the target is
    beyond the deformable range (a triangle would turn over) or makes the mesh cut
    through itself."""
    lo, hi = result.reach
    if not lo < result.step < hi:
        raise DeformError(f"Target is beyond the deformable range: {range_text(result)}; "
                          "beyond it triangles flip. Change Target.", "Target")
    clear_of_self(model.vertices, model.triangles, result)
    return model.vertices + result.step * result.field


CLEAR_STEPS = 7   # the clear range is found to 1/128 of the step


def clear_of_self(vertices, triangles, result):
    """DeformError naming Target, with the range that stays clear, when the mesh moved by
    the Drive crosses itself (a hole grown through an outer wall)."""
    moving = np.abs(result.field).max(axis=1) > 0
    moved = moving[triangles].any(axis=1)
    if not moved.any():
        return

    def crosses(s):
        return new_intersections(vertices, vertices + s * result.field, triangles, moved) > 0
    if not crosses(result.step):
        return
    good, bad = 0.0, result.step
    for _ in range(CLEAR_STEPS):
        mid = 0.5 * (good + bad)
        good, bad = (good, mid) if crosses(mid) else (mid, bad)
    if len(result.current) == 1:
        value = (result.value(good) if result.value is not None
                 else result.current[0] + good)
        text = f"it stays clear from {result.current[0]:.6g} to {value:.6g}"
    else:
        text = f"the feature can move {good:.6g} toward the target (asked {result.step:.6g})"
    raise DeformError(f"Target makes the mesh cut through itself: {text}; change Target.",
                      "Target")


def range_text(result):
    """The reachable range of a Drive, in words for a refusal."""
    lo, hi = result.reach
    if len(result.current) == 1:
        low, high = reach_values(result)
        now = f"(now {result.current[0]:.6g})"
        if np.isfinite(low) and np.isfinite(high):
            return f"reachable {low:.6g} to {high:.6g} {now}"
        if np.isfinite(low):
            return f"reachable from {low:.6g} up {now}"
        if np.isfinite(high):
            return f"reachable up to {high:.6g} {now}"
        return f"reachable at any value {now}"
    return f"the feature can move {hi:.6g} toward the target (asked {result.step:.6g})"


REHANDLE_FRACTION = 0.5  # each step goes this part of the way to where a triangle would flip
MAX_HANDLES = 20         # handles built before a drive that keeps on stalling is refused
RELAX_HALVINGS = 4       # the relaxation tried whole and halved this often
STALL = 1e-3             # a handle reaching less than this part of the way makes no progress


def rehandled(model, drive_of, moved, regions, first=None, limit=MAX_HANDLES,
               fraction=REHANDLE_FRACTION):
    """(positions, first Drive, last Drive, handles) of a drive beyond the reach of one
    handle: Date & Onosato's dynamic handle. The mesh goes part of the way within the
    reach of its handle, a new handle (segments, fits, prisms) is built on the shape
    reached, the same vertices and triangles, and so on until the target is within reach.

    model has .vertices or .nodes, .rebuilt(positions) and (or its .surface) triangle_at;
    drive_of(model, regions) gives the Drive to the target (`first`: already known for
    `model`), moved(model, drive) the moved positions or a DeformError. Between handles
    the vertices inside planes are relaxed (model.relaxed); the regions follow the
    triangles they picked first.
    Refused (DeformError naming Target, with the range reached) when a step would make the
    mesh cut through itself, when it makes no progress, or after `limit` handles."""
    surface = getattr(model, "surface", model)
    picked = [surface.triangle_at(p) for p in regions]
    base = getattr(model, "nodes", surface.vertices)
    first = drive = first if first is not None else drive_of(model, regions)
    handles, start = 1, abs(first.step)
    cache = {}                  # the Laplacian of `base`, the same for every handle
    while True:
        lo, hi = drive.reach
        if lo < drive.step < hi:
            try:
                return moved(model, drive), first, drive, handles
            except DeformError as e:   # cuts through itself before the target: say how far
                raise _stalled(first, drive, handles, str(e)) from None
        end = hi if drive.step > 0 else lo
        s = fraction * end
        if not np.isfinite(s) or abs(end) <= STALL * start or handles >= limit:
            raise _stalled(first, drive, handles, "beyond it triangles flip and a new "
                           "handle gains nothing more")
        try:
            positions = moved(model, drive._replace(step=s))
        except DeformError as e:
            raise _stalled(first, drive, handles, str(e)) from None
        model = model.rebuilt(model.relaxed(positions, base, cache))
        handles += 1
        surface = getattr(model, "surface", model)
        corners = surface.vertices[surface.triangles[picked]]
        drive = drive_of(model, [tuple(c) for c in corners.mean(axis=1)])


def _stalled(first, drive, handles, why):
    """The refusal of a rehandled drive: how far the dimension got with how many handles."""
    if len(first.current) == 1:
        now = drive.current[0]
        text = (f"it went from {first.current[0]:.6g} to {now:.6g} with {handles} handle(s) "
                f"(this handle: {range_text(drive)})")
    else:
        text = (f"the feature got to ({drive.current[0]:.6g}, {drive.current[1]:.6g}) with "
                f"{handles} handle(s), {drive.step:.6g} short")
    why = why.rstrip(".").replace("; change Target", "")
    error = DeformError(f"Target is beyond what rebuilt handles reach: {text}; {why}. "
                        "Change Target.", "Target")
    error.handles = handles
    return error
