"""Bend, twist and general rigid motions on closed triangle meshes (Wu & Ilies 2011).

Case 1 (`sweep_mesh`, one plane): the mesh is cut at the plane (cut.cut), the far
part moved by M(1) and the gap filled with the section ring swept through `samples` + 1
configurations M(i/samples). Case 2 (`map_between`, two parallel planes): the region between
the planes is cut into `samples` slabs and each vertex mapped by the motion at its fraction of
the gap, the part beyond Plane2 moved rigidly. Meshes are vertices (N, 3) float and triangles
(M, 3) int, counter-clockwise seen from outside; s is the signed distance to Plane.
"""
from math import isfinite

import numpy as np

from ..errors import DeformError
from ..blocks import BLOCK, compress_rows, in_parallel
from .cut import arrays, placed, seam, split, without_flat
from ..sweep.motion import apply, apply_each, fraction_matrices, rotation, translation
from ..sweep.planes import (check_crossing, frame, signed_distance, unit_as_given,
                           unit_normal)
from ..vectors import skew, unit

PASS_ROWS = 4 * BLOCK   # slab_cut's vertex pass: some 40 numpy calls a block, bound by their
                        # overhead more than by the cache (1.4x faster than BLOCK rows)


def _check_samples(samples):
    if isinstance(samples, bool) or not float(samples).is_integer() or samples < 1:
        raise DeformError(f"Samples must be a whole number of at least 1 (it is {samples}); "
                          f"raise Samples.", "Samples")
    return int(samples)


def sweep_mesh(vertices, triangles, origin, normal, motion, samples=16, eps=1e-9):
    """Case 1 with a rigid motion (e.g. a ScrewMotion for a bend); returns (vertices, triangles).

    The mesh is cut at the plane; triangles with every vertex at s <= 0 (after snapping
    |s| <= eps onto the plane) stay bit-identical; the others are moved by motion.matrix(1),
    on-plane vertices they share with the near part duplicated first. The gap between the
    section ring and its moved copy is filled by the rings M(i/samples) (section ring),
    i = 0..samples, consecutive rings joined by two triangles per seam edge as in the
    stretch band (which this is for a translation and samples = 1). Closed 2-manifold in,
    closed 2-manifold out (self-intersection is not checked beyond the test below). The
    result is written once: triangles near (kept, then the cut's pieces), far (likewise),
    band; a vertex beyond the plane moves even when no triangle uses it.

    The motion must carry every section vertex toward the moving side at t = 0
    (velocity . normal > 0), else the band would fold back through the fixed part: a
    DeformError names Axis (the axis crosses the section) or Angle (it all turns backward).
    """
    V, T = arrays(vertices, triangles, copy=False)       # only new arrays are written
    o, n = np.asarray(origin, float), unit_normal(normal)
    samples = _check_samples(samples)
    s = signed_distance(V, o, n)
    check_crossing(s, "Plane", eps, touching=True)
    sp = split(V, T, o, n, eps, s)
    N = len(V)
    NK = N + len(sp.P)
    side, pieces = sp.side, sp.pieces
    # the pieces' sides: far when a corner is beyond the plane (the new vertices are on it)
    corner = np.where(pieces < N, sp.code.take(np.minimum(pieces, N - 1)), 4)
    piece_far = ((corner[:, 0] | corner[:, 1] | corner[:, 2]) & 1) == 1
    is_near, is_far = (side & 1) == 0, (side & 3) == 1
    near_count, far_rows = int(np.count_nonzero(is_near)), np.flatnonzero(is_far)
    near_pieces, far_pieces = pieces[~piece_far], pieces[piece_far]
    # only the triangles with a corner on the plane can share one with the other side
    near_touch = T[np.flatnonzero((side & 5) == 4)]
    far_touch_rows = np.flatnonzero((side & 7) == 5)
    far_touch = T[far_touch_rows]
    on = np.zeros(NK, bool)
    on[sp.snap] = True
    on[N:] = True
    used = np.zeros((2, NK), bool)
    used[0, near_touch] = used[0, near_pieces] = True
    used[1, far_touch] = used[1, far_pieces] = True
    dup = np.flatnonzero(used[0] & used[1])                # on the plane, used by both sides
    is_dup = np.zeros(NK, bool)
    is_dup[dup] = True

    def copies(tris):                   # the dup corners renumbered to their copies
        hit = is_dup.take(tris)
        tris[hit] = NK + np.searchsorted(dup, tris[hit])
        return tris

    _, a, b = seam(np.concatenate([far_touch, far_pieces]),
                   np.concatenate([near_touch, near_pieces]), on)
    ring = np.unique(np.concatenate([a, b]))
    base = NK + len(dup)
    W = placed(V, sp, n, len(dup) + (samples - 1) * len(ring))
    W[NK:base] = W[dup]
    if len(ring):
        _check_no_fold(motion.velocity(W[ring], 0.0), n)
    # ring level i of the seam vertices: themselves (i = 0), their copies (i = samples),
    # else appended level by level; one quad (two triangles) per seam edge and level
    if samples > 1:
        W[base:] = apply(motion.matrices(np.arange(1, samples) / samples),
                         W[ring]).reshape(-1, 3)
    levels = np.concatenate([ring[None], base + np.arange((samples - 1) * len(ring)).reshape(
        samples - 1, len(ring)), NK + np.searchsorted(dup, ring)[None]])
    A, B = levels[:, np.searchsorted(ring, a)], levels[:, np.searchsorted(ring, b)]
    band = np.stack([np.stack([A[:-1], B[:-1], B[1:]], -1),
                     np.stack([A[:-1], B[1:], A[1:]], -1)], 1).reshape(-1, 3)
    # the result's triangles written once: near (kept, pieces), far (kept, pieces), band
    sizes = np.cumsum([0, near_count, len(near_pieces), len(far_rows), len(far_pieces),
                       len(band)])
    out = np.empty((sizes[-1], 3), np.int64)
    compress_rows(is_near, T, out[:sizes[1]])
    out[sizes[1]:sizes[2]] = near_pieces
    far_kept = out[sizes[2]:sizes[3]]
    compress_rows(is_far, T, far_kept)
    far_kept[np.searchsorted(far_rows, far_touch_rows)] = copies(far_touch)
    out[sizes[3]:sizes[4]] = copies(far_pieces)
    out[sizes[4]:] = band
    # what moves by M(1): the vertices beyond the plane, those on it used by the far side
    # alone, and the copies
    end = motion.matrix(1.0)
    alone = np.flatnonzero(used[1] & ~used[0] & on)
    if np.array_equal(end[:3, :3], np.eye(3)):            # a translation: by columns
        head = W[:N]
        beyond = sp.code == 1
        for k in range(3):
            if end[k, 3] != 0:
                np.add(head[:, k], end[k, 3], out=head[:, k], where=beyond)
        W[alone] += end[:3, 3]
        W[NK:base] += end[:3, 3]
    else:
        moving = np.concatenate([np.flatnonzero(sp.code == 1), alone, np.arange(NK, base)])
        W[moving] = apply(end, W.take(moving, axis=0))
    return W, out


def _check_no_fold(velocity, n):
    vn = velocity @ n
    tol = 1e-9 * max(float(np.linalg.norm(velocity, axis=1).max()), 1e-300)
    if (vn <= tol).all():
        raise DeformError("The motion carries the section back into the fixed part instead of "
                          "away from it; change the sign of Angle (or turn the Plane normal "
                          "toward the part that moves).", "Angle")
    if (vn <= tol).any():
        raise DeformError("The axis crosses or touches the section at Plane, so the swept "
                          "section would fold through the part; move Axis off the section.",
                          "Axis")


def map_between(vertices, triangles, origin, normal, gap, motion_of_s, samples=16, eps=1e-9):
    """Case 2 (twist; bend with two planes); returns (vertices, triangles).

    Plane2 is parallel to Plane at s = gap. The mesh is cut at s = 0, s = gap and the
    samples - 1 planes between (`slab_cut`, so no triangle spans two slabs); vertices with
    s <= 0 stay bit-identical (those within eps of a plane are snapped onto it first), those
    with s >= gap are moved by motion_of_s(1.0), those between by motion_of_s(s / gap)
    (exactly i / samples on the i-th plane). motion_of_s: fraction -> 4x4 (see
    motion.fraction_matrices; `twist_motion`, `bend_motion` or a motion object). Only the
    cuts change the topology; closed stays closed. The mesh between the planes follows the
    map only at its vertices: the triangles are flat, so a curved map is sampled `samples`
    times across the gap. The cost is linear in samples and in the triangles.
    """
    V, T = arrays(vertices, triangles, copy=False)       # slab_cut writes to new arrays
    o, n = np.asarray(origin, float), unit_normal(normal)
    gap = _check_gap(gap)
    samples = _check_samples(samples)
    if gap / samples <= 2 * eps:
        raise DeformError(f"{samples} Samples put the cutting planes closer than the tolerance "
                          f"in a gap of {gap:g}; lower Samples.", "Samples")
    return slab_cut(V, T, o, n, gap, samples, eps, motion_of_s)


FOLLOW = 1e-3        # how far (of the mesh's bounding-box diagonal) a flat piece between
                     # two Samples planes may stray from a twist or bend map (follow_map)
CHECK = 2e-3         # beyond this (of the diagonal) a result is searched for crossing facets
                     # (map_following): the 1.2 M-triangle benchmark part twisted 90 deg at
                     # Samples 16 reaches 1.2e-3, the notched cube that crossed 9e-3 (16) and
                     # 2.2e-3 (64)
FOLLOW_ROUNDS = 12   # rounds of edge splits at most
SLIVER = 1e-3        # a triangle whose height is below this fraction of its longest edge is
                     # not split (its halves would be as thin)
NEEDLE = 1e-5        # a triangle whose height is below this fraction of its longest edge has
                     # its corners in line (to rounding): it fills a crack (_beside_needles)
NEEDLE_CHECK = 1e-4  # beside a needle, pieces are searched when some triangle's bound exceeds
                     # this (of the diagonal): the benchmark part's region has none (its
                     # thinnest triangles 5e-4 of their longest edge), the check costs it one
                     # look-up of the corners of the 51,070 triangles over 1e-4


def slab_deviation(V, T, o, n, gap, samples, angle, axis_point, axis_direction, slope=1.0,
                   curvature=0.0, bend=False, tol=None):
    """Per triangle (M,), a bound on how far its flat pieces between the Samples planes
    (map_between) stray from the map they sample: 0 for the triangles outside the region.

    The map is p -> R(theta(f)) (p - g(f) n), f = s / gap, a turn about the axis by theta =
    angle t(f) (twist: g = 0; bend: g = gap t(f)), t the profile with |t'| <= slope and
    |t''| <= curvature. Along a segment p + tau v of a piece, the second derivative of the
    map is theta_tt R' y + theta_t^2 R'' y + 2 theta_t R' y_t (- R g_tt n for a bend), so
    its size is at most Q = A r v_s^2 + 2 c1 |v_s| d with c1 = |angle| slope / gap, A =
    c1^2 + |angle| curvature / gap^2 (+ curvature / gap for a bend), r the distance from
    the axis, v_s the segment's extent along n and d that of y_t across the axis (twist:
    |v| across the axis; bend: |v| across n + |1 - slope| |v_s|). A piece lies inside its
    triangle and one slab: |v_s| <= h_t = min(gap / samples, the triangle's extent along n
    inside the region), d <= the largest such extent of the triangle's edges, r <= that of
    its corners (the farthest of the region's, for speed: with `tol`, the triangles whose
    bound exceeds it get their own). The flat piece interpolates the map at its corners: for a map of second
    derivative Q it strays by at most (4/3) Q / 8 = Q / 6 (the sum over its edges of their
    bows Q / 8 weighted by 4 l_i l_j)."""
    out = np.zeros(len(T))
    V, T = arrays(V, T, copy=False)
    if 4 * len(T) < len(V):                   # (a few new triangles: their vertices alone)
        used, T = np.unique(T, return_inverse=True)
        V, T = V.take(used, axis=0), T.reshape(-1, 3)
    k = np.asarray(axis_direction, float).reshape(3)
    k = k / np.linalg.norm(k)
    # per vertex: s, the distance from the axis, and two coordinates across the direction
    # the edges' extent d is measured across (the axis for a twist, the normal for a bend)
    s = V @ n
    s -= float(np.asarray(o, float) @ n)
    code = (s > 0).view(np.int8) + (s >= gap).view(np.int8)
    c = code.take(T)
    total = c[:, 0] + c[:, 1]
    total += c[:, 2]
    rows = np.flatnonzero((total != 0) & (total != 6))   # all before Plane or beyond Plane2
    if not len(rows):
        return out
    Tr = T.take(rows, axis=0)
    w = V - np.asarray(axis_point, float).reshape(3)
    along = w @ k
    r2 = np.einsum("ij,ij->i", w, w)
    r2 -= along * along
    u, v, _ = frame(n if bend else k)
    plane = (V @ u, V @ v)
    corner = [Tr[:, j] for j in range(3)]
    S = [s.take(x) for x in corner]
    lo = np.clip(np.minimum(np.minimum(S[0], S[1]), S[2]), 0.0, gap)
    h = np.clip(np.maximum(np.maximum(S[0], S[1]), S[2]), 0.0, gap)
    h -= lo
    np.minimum(h, gap / samples, out=h)
    r = np.sqrt(max(float(r2.take(Tr).max()), 0.0))      # the farthest (each one's below)
    P = [[x.take(y) for y in corner] for x in plane]
    d2 = None
    for j in range(3):
        e = [q[(j + 1) % 3] - q[j] for q in P]
        e2 = e[0] * e[0]
        e2 += e[1] * e[1]
        d2 = e2 if d2 is None else np.maximum(d2, e2, out=d2)
    d = np.sqrt(d2)
    if bend:
        d += abs(1.0 - slope) * h
    c1, A = _rates(angle, gap, slope, curvature, bend)
    out[rows] = bound = (A * r * h * h + 2.0 * c1 * h * d) / 6.0
    if tol is not None:                       # the triangles over tol get their own r
        over = np.flatnonzero(bound > tol)
        t = Tr.take(over, axis=0)
        own = np.sqrt(np.maximum(r2.take(t).max(axis=1), 0.0))
        out[rows.take(over)] = (A * own * h.take(over) ** 2 + 2.0 * c1 * h.take(over)
                                * d.take(over)) / 6.0
    return out


def _rates(angle, gap, slope, curvature, bend):
    """(c1, A) of slab_deviation's bound: the turn's rate along n, |angle| slope / gap, and
    the factor of r v_s^2 in the map's second derivative."""
    c1 = abs(angle) * slope / gap
    return c1, c1 * c1 + abs(angle) * curvature / gap ** 2 + (curvature / gap if bend else 0.0)


def follow_map(V, T, o, n, gap, samples, angle, axis_point, axis_direction, slope=1.0,
               curvature=0.0, bend=False, tol=None):
    """The mesh (V, T) with edges split so that its flat pieces between the Samples planes
    follow the twist or bend map (see slab_deviation) within `tol` (default FOLLOW x the
    bounding-box diagonal): returns (vertices, triangles, risky), risky the number of
    triangles still beyond tol (no split can bring them under: slivers, or a part so far
    from the axis that a slab's own turn strays, which only more Samples mend).

    Each round the triangles beyond tol that a split helps (their deviation not all in the
    term of their extent along n, which a split leaves as it is once it is a slab's width;
    not slivers) have their longest edge split at its midpoint, and so has every triangle
    with a split edge, until it holds (longest-edge bisection closed over the neighbours:
    both triangles of an edge split it at the same new vertex, so a closed 2-manifold
    stays one, orientation kept, and the triangles keep their shape). A triangle with
    one split edge becomes 2, two 3 (its longest edge's midpoint joined to the opposite
    corner first), three 4. The input arrays come back unchanged (the same objects) when
    nothing needs a split: the cost then is slab_deviation's, on the region's triangles.
    On flat triangles, so the enclosed volume is kept exactly."""
    V, T = arrays(V, T, copy=False)
    if not len(T):
        return V, T, 0
    if tol is None:
        tol = FOLLOW * float(np.linalg.norm(np.ptp(V, axis=0)))
    h = gap / samples
    k = np.asarray(axis_direction, float).reshape(3)
    k = k / np.linalg.norm(k)
    A = _rates(angle, gap, slope, curvature, bend)[1]

    def deviation(V, T):
        return slab_deviation(V, T, o, n, gap, samples, angle, axis_point, axis_direction,
                              slope, curvature, bend, tol)

    dev = deviation(V, T)
    for _ in range(FOLLOW_ROUNDS + 1):
        over = np.flatnonzero(dev > tol)
        if not len(over):
            return V, T, 0
        X = V.take(T.take(over, axis=0), axis=0)
        E = X[:, [1, 2, 0]] - X
        L2 = (E * E).sum(axis=2)
        longest = np.sqrt(L2.max(axis=1))
        area2 = np.linalg.norm(np.cross(E[:, 0], -E[:, 2]), axis=1)
        w = X - np.asarray(axis_point, float).reshape(3)
        r = np.sqrt(np.maximum((w * w).sum(axis=2) - (w @ k) ** 2, 0.0)).max(axis=1)
        S = (X - o) @ n
        thick = np.ptp(S, axis=1) < h         # a split shortens its extent along n too
        helps = (thick | (A * r * h * h / 6.0 < 0.75 * tol)) & (area2 >= SLIVER * longest ** 2)
        if not helps.any() or _ == FOLLOW_ROUNDS:
            return V, T, int(len(over))
        V, T, kept = _bisected(V, T, over[helps])
        dev = np.concatenate([dev[kept], deviation(V, T[int(np.count_nonzero(kept)):])])
    return V, T, 0


def map_following(V, T, o, n, gap, motion_of_s, samples, eps, angle, axis_point,
                  axis_direction, slope=1.0, curvature=0.0, bend=False, what="Twist"):
    """map_between, checked where its flat pieces may stray far enough from the map to cross
    (the op's entry for a mesh Twist and a two-plane mesh Bend; map_between alone is the
    kernel). When some triangle's slab_deviation exceeds CHECK x the bounding-box diagonal,
    the pieces of the triangles whose own bound exceeds FOLLOW (half of CHECK: two pieces
    straying less than that each stray less than CHECK together) are searched for facets
    they cross (_edit_crossings), pieces of two triangles that already cross in the Base
    not counting; if some cross, the mesh is refined by follow_map (to FOLLOW) and
    mapped again, and refused, naming Samples, if the refined triangles' pieces still cross.
    Beside a needle facet (_beside_needles) the pieces are searched whenever some bound
    exceeds NEEDLE_CHECK, and split to half their own bound if they cross. A result without
    crossings comes back as map_between gives it (the triangles of the cut alone)."""
    V, T = arrays(V, T, copy=False)
    W, F = map_between(V, T, o, n, gap, motion_of_s, samples, eps)
    diagonal = float(np.linalg.norm(np.ptp(V, axis=0))) if len(V) else 0.0
    bound = (o, n, gap, samples, angle, axis_point, axis_direction, slope, curvature, bend)
    dev = slab_deviation(V, T, *bound)
    if not len(T):
        return W, F
    cut = (o, n, gap, samples, eps, motion_of_s)
    tol = FOLLOW * diagonal
    strays = _beside_needles(V, T, dev, NEEDLE_CHECK * diagonal)
    if dev.max() > CHECK * diagonal:
        strays = np.union1d(strays, np.flatnonzero(slab_deviation(V, T, *bound, tol=tol) > tol))
    elif len(strays):                    # (split them at least once, if they cross)
        own = slab_deviation(V, T.take(strays, axis=0), *bound, tol=0.0)
        tol = min(tol, max(0.5 * float(own.max()), NEEDLE_CHECK * diagonal))
    else:
        return W, F
    if not _edit_crossings(V, T, W, F, strays, cut):
        return W, F
    Vf, Tf, risky = follow_map(V, T, o, n, gap, samples, angle, axis_point, axis_direction,
                               slope, curvature, bend, tol)
    W, F = map_between(Vf, Tf, o, n, gap, motion_of_s, samples, eps)
    # the split triangles (each piece has a new vertex) and those still over tol
    split = Tf.max(axis=1) >= len(V) if len(Tf) else np.zeros(0, bool)
    strays = np.union1d(np.flatnonzero(split | (slab_deviation(Vf, Tf, *bound, tol=tol) > tol)),
                        _beside_needles(Vf, Tf, slab_deviation(Vf, Tf, *bound),
                                        NEEDLE_CHECK * diagonal))
    crossed = _edit_crossings(Vf, Tf, W, F, strays, cut)
    if crossed:
        raise DeformError(
            f"The {what} bends the mesh's flat facets through each other: {crossed} pairs "
            f"of facets cross (between two of the {samples} Samples planes a facet follows "
            f"the map only at its corners, and {risky} facets stray too far even split: "
            f"slivers, or parts far from the axis); raise Samples, lower Angle or move Plane2 "
            f"farther.", "Samples")
    return W, F


def _beside_needles(V, T, dev, low):
    """Rows of the region's triangles (dev > 0) that share a corner with a needle (a
    triangle whose height is under NEEDLE of its longest edge: its corners in line to
    rounding) beside a triangle whose bound `dev` exceeds `low`. A needle fills a crack
    where a corner lies on another triangle's edge; the triangles meeting there lie against
    each other, so a piece straying by any amount can cross them (trimesh's 7_8ths_cube
    twisted at Samples 256: bound 5.6e-4 of the diagonal, 8 crossing pairs). The cost is
    the region's corners looked up once when some triangle exceeds `low`."""
    empty = np.zeros(0, np.int64)
    over = np.flatnonzero(dev > low)
    if not len(over):
        return empty
    region = np.flatnonzero(dev > 0)
    R = T.take(region, axis=0)

    def touching(rows):                   # the region's rows with a corner of `rows`
        flag = np.zeros(len(V), bool)
        flag[T.take(rows, axis=0).reshape(-1)] = True
        f = flag.take(R)
        return region[f[:, 0] | f[:, 1] | f[:, 2]]

    near = touching(over)
    X = V.take(T.take(near, axis=0), axis=0)
    E = X[:, [1, 2, 0]] - X
    L2 = np.einsum("ijk,ijk->ij", E, E).max(axis=1)
    c = np.cross(E[:, 0], E[:, 2])
    needles = near[np.einsum("ij,ij->i", c, c) < NEEDLE * NEEDLE * L2 * L2]
    return touching(needles) if len(needles) else empty


def _edit_crossings(V, T, W, F, rows, cut):
    """How many pairs of facets of (W, F) = map_between(V, T, *cut) cross (intersect:
    an edge of one through the other, the two sharing no vertex) with one of them a piece
    of a triangle in `rows`, not counting pieces of two triangles that already cross in
    (V, T): those the edit did not make. (Touching ones count: trimesh's 7_8ths_cube has a
    corner on another facet's edge, and its twist crossed them there.) The Base is
    searched only when the pieces cross something."""
    from . import intersect
    if not len(rows):
        return 0
    mask = np.zeros(len(T), bool)
    mask[rows] = True
    o, n = cut[0], cut[1]
    axes = frame(n)[[2, 0, 1]].T          # (searched with n along x: the boxes of pieces
                                          # in different slabs then lie apart)
    def search(S):
        X, G, source = _pieces_found(V, T, W, F, S, cut)
        X = (X - o) @ axes
        among = (source >= 0) & mask.take(np.maximum(source, 0))
        pairs = intersect._candidates(X, G, among)
        pairs = pairs[intersect.crossing(X, G, pairs)] if len(pairs) else pairs
        return source.take(pairs[:, 0]), source.take(pairs[:, 1])

    a, b = search(np.asarray(rows, np.int64))
    if not len(a):
        return 0
    X = (V - o) @ axes
    pairs = intersect._candidates(X, T, mask)
    before = pairs[intersect.crossing(X, T, pairs)] if len(pairs) else pairs
    if not len(before):
        return len(a)
    a, b = search(np.union1d(rows, before.reshape(-1)))   # (their partners' pieces known)
    M = len(T)
    old = (a >= 0) & (b >= 0) & np.isin(np.minimum(a, b) * M + np.maximum(a, b),
                                        np.sort(before, axis=1) @ np.array([M, 1]))
    return int(np.count_nonzero(~old))


def _pieces_found(V, T, W, F, S, cut):
    """(X, G, source): the result (W, F) = map_between(V, T, *cut) and, for each of its
    facets, the row of T it is a piece of where that is known (-1 otherwise): the rows
    the cut left as they were, and the pieces of the triangles S.

    slab_cut does not say which input triangle a piece comes from, so S is cut again on
    its own (each triangle with its own copies of its corners, so that its pieces are one
    connected set), and its pieces are found in (W, F) by their vertices' places. Pieces
    of S not found so (where the two cuts differ) are appended to (X, G) as they are."""
    o, n, gap, samples, eps, motion_of_s = cut
    M, k = len(T), len(S)
    # two loose vertices beyond both planes keep slab_cut's plane checks
    Vs = np.concatenate([V.take(T.take(S, axis=0).reshape(-1), axis=0),
                         [o - gap * n, o + 2.0 * gap * n]])
    Ws, Fs = slab_cut(Vs, np.arange(3 * k).reshape(-1, 3), o, n, gap, samples, eps,
                      motion_of_s)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree
    e = np.concatenate([Fs[:, [0, 1]], Fs[:, [1, 2]]])
    _, label = connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])),
                                               shape=(len(Ws), len(Ws))), directed=False)
    owner = np.full(label.max() + 1, -1)
    owner[label[3 * np.arange(k)]] = S
    piece_of = owner.take(label.take(Fs[:, 0]))
    close = 1e-9 * float(np.linalg.norm(np.ptp(W, axis=0)))
    box = np.flatnonzero(((W >= Ws.min(axis=0) - close) & (W <= Ws.max(axis=0) + close))
                         .all(axis=1))
    _, at = cKDTree(W.take(box, axis=0)).query(Ws, distance_upper_bound=close)
    index = np.where(at < len(box), box.take(np.minimum(at, len(box) - 1)), -1)
    G = index.take(Fs)                                   # the pieces in W's numbering
    source = np.full(len(F), -1)
    if len(F) >= M:
        same = np.flatnonzero((F[:M] == T).all(axis=1))
        source[same] = same
    key = np.sort(F, axis=1)
    order = np.lexsort(key.T[::-1])
    key = key[order]
    want = np.sort(G, axis=1)
    at = np.minimum(np.searchsorted(_rowkey(key), _rowkey(want)), len(key) - 1)
    hit = (key.take(at, axis=0) == want).all(axis=1)
    source[order.take(at[hit])] = piece_of[hit]
    lost = ~hit & (piece_of >= 0)
    if not lost.any():
        return W, F, source
    G, L = G[lost], Fs[lost]
    extra = np.unique(L[G < 0])
    G[G < 0] = len(W) + np.searchsorted(extra, L[G < 0])
    return (np.concatenate([W, Ws.take(extra, axis=0)]), np.concatenate([F, G]),
            np.concatenate([source, piece_of[lost]]))


def _rowkey(R):
    """Rows of three non-negative integers as one sortable key each (lexicographic)."""
    R = np.ascontiguousarray(R, np.int64)
    return R.view(np.dtype([("a", np.int64), ("b", np.int64), ("c", np.int64)])).reshape(-1)


def _bisected(V, T, rows):
    """(V, T, kept) with the longest edge of the triangles `rows` split at its midpoint, and
    the longest edge of every triangle that has a split edge, until none has a split edge
    without its longest (see follow_map); the triangles not split (`kept`, a mask of the
    input's rows) come first, in their order."""
    N = len(V)

    def edges(t):                         # (edge keys (k, 3): edge j is corner j -> j + 1,
        X = V.take(t, axis=0)             # the index of the longest)
        nxt = t[:, [1, 2, 0]]
        key = np.minimum(t, nxt) * N + np.maximum(t, nxt)
        return key, ((X[:, [1, 2, 0]] - X) ** 2).sum(axis=2).argmax(axis=1)

    key, longest = edges(T.take(rows, axis=0))
    split = np.unique(key[np.arange(len(rows)), longest])
    while True:                           # the triangles with both ends of a split edge
        end = np.zeros(N, np.int8)
        end[split // N] = end[split % N] = 1
        c = end.take(T)
        at = np.flatnonzero(c[:, 0] + c[:, 1] + c[:, 2] >= 2)
        key, longest = edges(T.take(at, axis=0))
        cut = np.isin(key, split)
        more = np.setdiff1d(key[np.arange(len(at)), longest][cut.any(axis=1)], split)
        if not len(more):
            break
        split = np.union1d(split, more)
    mid = N + np.minimum(np.searchsorted(split, key), len(split) - 1)   # (valid where cut)
    W = np.concatenate([V, 0.5 * (V.take(split // N, axis=0) + V.take(split % N, axis=0))])
    count = cut.sum(axis=1)
    kept = np.ones(len(T), bool)
    kept[at[count > 0]] = False
    out = [T[kept]]
    for c in (1, 2, 3):
        this = np.flatnonzero(count == c)
        if not len(this):
            continue
        t, m, lg = T.take(at[this], axis=0), mid.take(this, axis=0), longest.take(this)
        if c == 3:
            m0, m1, m2 = m[:, 0], m[:, 1], m[:, 2]
            out += [np.stack(x, 1) for x in ((t[:, 0], m0, m2), (m0, t[:, 1], m1),
                                             (m2, m1, t[:, 2]), (m0, m1, m2))]
            continue
        # turned so that edge 0 is split (c = 2: edges 0 and 1, edge 2 whole)
        first = lg if c == 1 else (np.argmin(cut.take(this, axis=0), axis=1) + 1) % 3
        turn = (first[:, None] + np.arange(3)) % 3
        t, m = np.take_along_axis(t, turn, 1), np.take_along_axis(m, turn, 1)
        t0, t1, t2, m0, m1 = t[:, 0], t[:, 1], t[:, 2], m[:, 0], m[:, 1]
        if c == 1:
            out += [np.stack([t0, m0, t2], 1), np.stack([m0, t1, t2], 1)]
            continue
        zero = ((lg - first) % 3 == 0)[:, None]        # the longest is edge 0, else edge 1
        out += [np.where(zero, np.stack([t0, m0, t2], 1), np.stack([t0, m0, m1], 1)),
                np.stack([m0, t1, m1], 1),
                np.where(zero, np.stack([m0, m1, t2], 1), np.stack([t0, m1, t2], 1))]
    return W, np.concatenate(out), kept


def move_by_fraction(points, f, motion_of_s, in_place=False):
    """Point i moved by motion_of_s(f[i]), f in [0, 1]; the points with f = 0 returned
    bit-identical (in_place: the points array itself is written and returned).

    A motion with `shifts` (twist_motion, bend_motion) turns every point by its own angle,
    those at f = 1 included (one rigid transform for them all, to rounding), BLOCK rows at a
    time on columns: every row of a block gets its displacement (no gather or scatter of
    the moving ones), only in the columns the motion changes (a turn about a coordinate
    axis keeps that one), subtracted as its negative with its zeros made +0.0: x - (+0.0)
    is x for every float x, -0.0 included, so the rows with f = 0 (displacement 0) stay
    bit-identical without a mask (a masked subtraction is 3x slower on a cloud, whose rows
    with f = 0 and f > 0 alternate at random); a block with a displacement that is not
    finite (a point at infinity) is masked. Any other motion goes through its (K, 4, 4)
    transforms, one per distinct fraction."""
    P = np.asarray(points, float)
    out = P if in_place else P.copy()
    if not hasattr(motion_of_s, "shifts"):
        move = np.flatnonzero(f > 0)
        fractions, which = np.unique(f.take(move), return_inverse=True)   # one per plane
        out[move] = apply_each(fraction_matrices(motion_of_s, fractions)[which.reshape(-1)],
                               P.take(move, axis=0))
        return out
    for i in range(0, len(P), BLOCK):
        _move_block(P[i:i + BLOCK], f[i:i + BLOCK], out[i:i + BLOCK], motion_of_s)
    return out


def _move_block(P, f, out, motion_of_s, finite=False):
    """move_by_fraction on one block (rows P into out, which may be P) by a motion with
    `shifts`. The block's lowest and highest fraction decide the work: none when all are
    0; one angle for all when all are 1 (no sine per row); no +0.0 when none is 0.
    finite: the caller knows every point is finite (no masked subtraction)."""
    low, high = f.min(), f.max()
    if high <= 0:
        return
    for k, minus in enumerate(motion_of_s.shifts(P, 1.0 if low == 1 else f)):
        if minus is not None:
            column = out[:, k]
            if not low > 0:                   # (some rows stay, or a fraction is NaN)
                minus += 0.0
            if finite or np.isfinite(minus).all():
                np.subtract(column, minus, out=column)
            else:
                np.subtract(column, minus, out=column, where=f > 0)


def slab_cut(V, T, o, n, gap, samples, eps, motion_of_s=None):
    """The mesh cut at the planes s = gap * j / samples, j = 0..samples, all at once, and
    each vertex moved by motion_of_s (None: not moved) at its fraction of the gap (see
    move_by_fraction): s / gap clipped to [0, 1], exactly j / samples on plane j. Returns
    (vertices, triangles).

    A vertex that is not finite is refused naming Base, planes that miss the part naming
    Plane or Plane2. Vertices within eps of a plane are snapped onto it; every edge gets one
    new vertex per plane it crosses (shared by its two triangles, so closed stays closed),
    and the cut points joined by a section segment shorter than eps are merged (pieces a
    merge leaves as one triangle both ways round are dropped, _without_fins; a vertex
    whose every piece went with them stays among the vertices, unused). A triangle
    crossing k planes becomes 2k + 1 triangles (2k when its middle vertex lies on a plane):
    sorted by level, its vertices a <= b <= c, the chain a -> c on one side and a -> b -> c
    on the other are zipped from a to c (a triangle crossing one plane, most of them, gets
    its pieces directly: _one_plane), leaving a quadrilateral between each two planes. One
    the motion takes out of its plane (by more than eps) gets a centre vertex and four
    triangles (2 more: _fanned); the others are split along their shorter diagonal in the
    input. The cost is linear in the output (no triangle is cut twice). Original vertices
    keep their indices, the cut points and then the centres are appended; orientation is
    kept; a triangle crossing no plane keeps its row, the rows of the cut ones hold pieces
    (of any cut triangle) and the other pieces follow the input's rows.
    Each block of vertices is moved while it is in the cache, right after it is classified:
    the cut points are made from the input's vertices (snapped), then moved.
    Large rows are gathered with take: fancy or boolean indexing of rows is 3 to 10x slower.
    """
    V, T = arrays(V, T, copy=False)           # (int64 triangles: edge keys are N^2)
    N = len(V)
    if not N:
        raise DeformError("The Base mesh has no vertices; give Base a mesh with triangles.",
                          "Base")
    ns = unit_as_given(n)
    if not (np.isfinite(o).all() and np.isfinite(ns).all()):
        raise DeformError("Plane's position or normal is not a finite number (NaN or "
                          "infinity); set Plane to finite numbers.", "Plane")
    levels = _Levels(o, ns, gap, samples, eps, min(N, PASS_ROWS))
    # per vertex, PASS_ROWS at a time (in the L3 cache), in one pass: its level u and cell between
    # planes (snapped within eps of a plane), its fraction and its moved place; W gets room
    # for the cut points too (grown below when a cut makes more). A vertex that is not
    # finite makes a level that is not (refused before its cell is cast), unless it is in a
    # coordinate the normal does not see (`blind`: checked then). (No np.errstate here: on
    # numpy 1.24 it adds 4 us to every ufunc call inside it, 2.5x the pass.)
    room = N + N // 8 + 1024
    W = np.empty((room, 3))
    u = np.empty(N)
    small = np.int8 if samples < 120 else np.int16 if samples < 30000 else np.int32
    cell = np.empty(N, small)

    shifts = hasattr(motion_of_s, "shifts")

    def vertex_pass(start, stop):             # -> (lowest, highest s) of its vertices
        lo, hi = np.inf, -np.inf
        fraction = np.empty(min(PASS_ROWS, stop - start))
        for i in range(start, stop, PASS_ROWS):
            v = V[i:min(i + PASS_ROWS, stop)]
            end = i + len(v)
            s, on, d = levels(v, u[i:end])
            low, high = float(s.min()), float(s.max())
            if not (isfinite(low) and isfinite(high)) or levels.blind and not np.isfinite(
                    v).all():
                raise DeformError("The Base mesh has vertices that are not finite numbers "
                                  "(NaN or infinity) or too large to measure; repair or "
                                  "replace the Base mesh.", "Base")
            lo, hi = min(lo, low), max(hi, high)
            np.floor(u[i:end], out=cell[i:end], casting="unsafe")
            w = W[i:end]
            w[...] = v
            if on is not None:
                w[on] -= d[:, None] * ns
            if motion_of_s is not None:
                f = np.divide(s, gap, out=fraction[:len(v)])
                _clip(f, levels.unit)
                if on is not None:
                    f[on] = u[i:end].take(on) / samples
                if shifts:
                    _move_block(w, f, w, motion_of_s, finite=True)
                else:
                    move_by_fraction(w, f, motion_of_s, in_place=True)
        return lo, hi

    # (a motion of the caller's own, not one of ours, is called from this thread alone)
    lo, hi = np.array(in_parallel(vertex_pass, N) if shifts or motion_of_s is None
                      else [vertex_pass(0, N)]).T
    ends = np.array([lo.min(), hi.max()])
    check_crossing(ends, "Plane", eps, touching=True)
    check_crossing(ends - gap, "Plane2", eps, touching=True)
    # which triangles cross a plane: only those whose corners are not all in one cell
    # between planes can, and only those are sorted (most triangles of a fine mesh cross
    # none); then from their lowest and highest level alone
    M = len(T)

    def scan(start, stop):
        maybe = []
        for i in range(start, stop, BLOCK):
            c = cell.take(T[i:min(i + BLOCK, stop)])
            maybe.append(np.flatnonzero((c[:, 0] != c[:, 1]) | (c[:, 1] != c[:, 2])) + i)
        return maybe

    maybe = [m for part in in_parallel(scan, M) for m in part]
    cell = None                               # (freed)
    maybe = np.concatenate(maybe) if maybe else np.empty(0, np.int64)
    W, new, rows = _cut(V, T, W, u, maybe, levels, room, gap, samples, eps, motion_of_s)
    u = maybe = None                          # (freed before the result is allocated)
    if new is None:
        return W, T.copy()
    if len(new) < len(rows):                  # (flat input triangles) rows to drop
        keep = np.ones(M, bool)
        keep[rows] = False
        return W, np.concatenate([T[keep], new])
    out = np.empty((M + len(new) - len(rows), 3), np.int64)

    def copy(start, stop):
        out[start:stop] = T[start:stop]

    in_parallel(copy, M)
    out[rows] = new[:len(rows)]
    out[M:] = new[len(rows):]
    return W, out


def _cut(V, T, W, u, maybe, levels, room, gap, samples, eps, motion_of_s):
    """slab_cut's cut of the triangles `maybe` (those with corners in different cells):
    the cut points, moved, and the quadrilaterals' centres written to W after its N
    vertices (W grown when it has no room for them), and the pieces. Returns (W, pieces or
    None when no triangle crosses a plane, the rows of T that were cut). In steps of their
    own (_crossed, _cut_points, _pieces, _fanned), each step's temporaries freed when it
    ends."""
    N = len(V)
    rows, a, b, c, odd, ub, uc, planes = _crossed(T, u, maybe, samples)
    if not len(rows):
        return W[:N], None, rows
    P, point, e, merged = _cut_points(V, levels, a, b, c, ub, planes, gap, samples, eps,
                                      motion_of_s)
    tris, quads = _pieces(point, a, b, c, ub, uc, odd, planes, e)
    K = len(P)
    if N + K > room:
        W = np.concatenate([W[:N], np.empty((K, 3))])
    W[N:N + K] = P
    del P
    fans, centres, across = _fanned(quads, W[:N + K], motion_of_s, eps)
    if N + K + len(centres) > len(W):         # (grown only for the centres there are)
        W = np.concatenate([W[:N + K], centres])
    else:
        W = W[:N + K + len(centres)]
        W[N + K:] = centres
    del centres
    new = without_flat(np.concatenate([tris, _split(fans, across, quads, N + K)]))
    return W, _without_fins(new, N + merged, len(W)) if len(merged) else new, rows


def _fanned(quads, moved, motion_of_s, eps):
    """Which quadrilaterals (m, 4) get a centre vertex, those centres, and how the others
    are split. Between two planes a quadrilateral's corners turn by different angles, so
    it is no longer flat; split along either diagonal it lies on one side of the turned
    surface, the same side slab after slab (the diagonal shorter in the input lost 2.6 % of
    the slab on a coarse cylinder twisted across its length at Samples 16, first order in
    the turn per slab; the one shorter in the moved mesh gained as much). The four
    triangles about the mean of its moved corners lie between the two splits, and the
    errors of the two cancel to first order; the centre lies inside the corners' hull,
    where the splits do (placing it on the exact turned surface instead made the thin
    walls of a coarse C section cross). Only quadrilaterals whose moved corner 3 lies
    farther than eps from the plane of the others get one (a quarter of them on a fine
    mesh); the others, flat to eps, are split along their shorter diagonal, 1-3 where
    `across` (a diagonal of no length where a corner repeats: merged cut points, or b on
    the plane). Without a motion (a caller that moves the vertices itself: the mesh
    Taper), none get a centre and the diagonals are measured as the corners stand.
    moved: the cut mesh's vertices (N + K, 3) where the motion takes them. Returns (fan,
    centres, across)."""
    distinct = (quads[:, 0] != quads[:, 1]) & (quads[:, 1] != quads[:, 2]) & (
        quads[:, 2] != quads[:, 3]) & (quads[:, 3] != quads[:, 0])
    at = np.flatnonzero(distinct)
    c = _corners(moved, quads.take(at, axis=0))
    d1, d2, d3 = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0], c[:, 3] - c[:, 0]
    fan = np.zeros(len(quads), bool)
    if motion_of_s is not None:
        normal = [d1[i] * d2[j] - d1[j] * d2[i] for i, j in ((1, 2), (2, 0), (0, 1))]
        off = np.abs(normal[0] * d3[0] + normal[1] * d3[1] + normal[2] * d3[2])
        fan[at] = off > eps * np.sqrt(normal[0] ** 2 + normal[1] ** 2 + normal[2] ** 2)
    across = quads[:, 1] == quads[:, 3]
    d3 -= d1                                  # the diagonal 1-3 (0-2 is d2)
    across[at] = (d3 * d3).sum(axis=0) < (d2 * d2).sum(axis=0)
    centres = c.take(np.flatnonzero(fan[at]), axis=2).sum(axis=1).T * 0.25
    return fan, centres, across


def _corners(W, quads):
    """The corners of quadrilaterals (m, 4) from the vertices W: (3, 4, m), coordinate by
    corner by quadrilateral (rows of one coordinate and corner are contiguous), from one
    gather."""
    return np.ascontiguousarray(W.take(quads.reshape(-1), axis=0).reshape(-1, 4, 3).transpose(
        2, 1, 0))


def _split(fan, across, quads, first):
    """The triangles of the quadrilaterals: four about each centre (vertices first,
    first + 1, ... in the order of the quadrilaterals with `fan`), two along the diagonal
    0-2 or, where `across`, 1-3 for the others."""
    with_centre = quads.take(np.flatnonzero(fan), axis=0)
    fans = np.empty((len(with_centre), 4, 3), np.int64)
    fans[:, :, 0] = with_centre
    fans[:, :, 1] = with_centre.take([1, 2, 3, 0], axis=1)
    fans[:, :, 2] = np.arange(first, first + len(with_centre))[:, None]
    rest = quads.take(np.flatnonzero(~fan), axis=0)
    turn = np.flatnonzero(across.take(np.flatnonzero(~fan)))
    rest[turn] = rest.take(turn, axis=0).take([1, 2, 3, 0], axis=1)
    return np.concatenate([fans.reshape(-1, 3), rest[:, :3], rest[:, [0, 2, 3]]])


def _without_fins(new, merged, size):
    """The pieces without the pairs that are one triangle both ways round. Where every
    cut point about a vertex near a plane merged into one (a spike, or a tolerance near
    half the spacing of the planes), the pieces on either side of that vertex's edges
    can come out as the same three corners in opposite orders: a fin of no volume whose
    edges four pieces would share. Only the pieces at a merged point (`merged`, of `size`
    vertices) can be, and of those only the ones whose corners another has too (numbered
    by _numbered) are paired, in a Python loop."""
    mark = np.zeros(size, bool)
    mark[merged] = True
    touched = mark.take(new)
    at = np.flatnonzero(touched[:, 0] | touched[:, 1] | touched[:, 2])
    if not len(at):
        return new
    tri = new.take(at, axis=0)
    key = np.sort(tri, axis=1)
    bits = max(int(size - 1).bit_length(), 1)
    if 3 * bits <= 63:
        _, group = _numbered((key[:, 0] << (2 * bits)) | (key[:, 1] << bits) | key[:, 2])
    else:
        group = np.unique(key, axis=0, return_inverse=True)[1].reshape(-1)
    twice = np.flatnonzero(np.bincount(group).take(group) > 1)
    if not len(twice):
        return new
    at, tri, key = at.take(twice), tri.take(twice, axis=0), key.take(twice, axis=0)
    first = np.argmin(tri, axis=1)
    turned = np.take_along_axis(tri, (first[:, None] + np.arange(3)) % 3, 1)
    ascending = turned[:, 1] < turned[:, 2]   # the orientation, against the sorted corners
    seen, fins = {}, []
    for row, corners, up in zip(at.tolist(), map(tuple, key.tolist()), ascending.tolist()):
        pending = seen.setdefault(corners, ([], []))
        if pending[not up]:
            fins += [pending[not up].pop(), row]
        else:
            pending[up].append(row)
    return np.delete(new, fins, axis=0) if fins else new


def _crossed(T, u, maybe, samples):
    """The rows of the triangles `maybe` that cross a plane, their corners sorted by level
    (a, b, c, odd: see _sorted), the levels ub, uc, and the planes (first, count) each edge
    a -> b, b -> c, a -> c crosses (see _planes_between)."""
    Tm = T.take(maybe, axis=0)
    U = u.take(Tm)
    order, odd = _sorted(U)
    S = U.reshape(-1).take(order)             # the levels sorted
    f_ac, n_ac = _planes_between(S[:, 0], S[:, 2], samples)
    hit = np.flatnonzero(n_ac)
    order = order.take(hit, axis=0)
    a, b, c = (Tm.reshape(-1).take(order[:, k]) for k in range(3))
    ua, ub, uc = (S[:, k].take(hit) for k in range(3))
    planes = (*_planes_between(ua, ub, samples), *_planes_between(ub, uc, samples),
              f_ac.take(hit), n_ac.take(hit))
    return maybe.take(hit), a, b, c, odd.take(hit), ub, uc, planes


def _cut_points(V, levels, a, b, c, ub, planes, gap, samples, eps, motion_of_s):
    """One new vertex per (edge, plane) for the edges that cross one (keyed by their sorted
    vertex indices), those joined by a section segment shorter than eps merged, moved by
    the motion at their plane's fraction. Returns (the points (K, 3), point(e, plane): the
    vertex of edge e's point on that plane (N + its row), the edge numbers (e_ab, e_bc,
    e_ac) of the triangles, -1 where an edge crosses none, the rows of the points that
    several were merged into)."""
    f_ab, n_ab, f_bc, n_bc, f_ac, n_ac = planes
    N = len(V)
    lo = np.concatenate([a, b, a])
    hi = np.concatenate([b, c, c])
    crossing = np.flatnonzero(np.concatenate([n_ab, n_bc, n_ac]))
    lo, hi = lo.take(crossing), hi.take(crossing)
    at, inv = _numbered(np.minimum(lo, hi) * N + np.maximum(lo, hi))
    e_of = np.full(3 * len(a), -1)
    e_of[crossing] = inv.reshape(-1)
    e_ab, e_bc, e_ac = np.split(e_of, 3)
    # each edge from its lower level to its higher (lo -> hi: a crossing edge's levels
    # differ): its ends' levels and (snapped) places
    (sp, up, Wp), (sq, uq, Wq) = (levels.placed(V.take(x.take(at), axis=0)) for x in (lo, hi))
    del lo, hi
    e_first, e_count = _planes_between(up, uq, samples)
    e_start = np.cumsum(e_count) - e_count
    edge, k = _ranges(e_count)
    jp = e_first.take(edge) + k
    level = gap * jp / samples
    dp = sp.take(edge) - level
    dq = sq.take(edge) - level
    Wp = Wp.take(edge, axis=0)
    P = Wq.take(edge, axis=0)
    P -= Wp
    P *= (dp / (dp - dq))[:, None]
    P += Wp
    levels.onto(P, level)
    del Wp, Wq, dp, dq

    def raw(e, jj):                       # index in P of edge e's point on plane jj
        return e_start.take(e) + jj - e_first.take(e)

    # the section segments: on each plane a triangle crosses, its long chain's point to its
    # short chain's (b itself when b lies on that plane)
    t, i = _ranges(n_ac)
    jj = f_ac.take(t) + i
    ubt = ub.take(t)
    short = np.where(jj < ubt, raw(np.maximum(e_ab.take(t), 0), jj),   # (-1: the edge crosses
                     raw(np.maximum(e_bc.take(t), 0), jj))             # none; not chosen)
    seg = np.stack([raw(e_ac.take(t), jj), short], 1).take(np.flatnonzero(jj != ubt), axis=0)
    unmoved, label = _merge_segments(P, seg, eps)
    P = unmoved
    if motion_of_s is not None:
        f = np.empty(len(P))
        f[label] = jp / samples
        P = move_by_fraction(unmoved, f, motion_of_s)

    def point(e, jj):
        return N + label.take(raw(e, jj))

    return P, point, (e_ab, e_bc, e_ac), np.flatnonzero(np.bincount(label) > 1)


def _pieces(point, a, b, c, ub, uc, odd, planes, e):
    """The pieces of the cut triangles, (triangles (k, 3), quadrilaterals (m, 4)): those of
    the triangles crossing one plane (most), written directly (_one_plane), then the
    others', by zipping their two chains (_zipped)."""
    f_ab, n_ab, f_bc, n_bc, f_ac, n_ac = planes
    e_ab, e_bc, e_ac = e
    one = n_ac == 1
    t1, tz = np.flatnonzero(one), np.flatnonzero(~one)
    j = f_ac.take(t1)
    lower = n_bc.take(t1) == 1                # b below the plane: its short point on b -> c
    q = b.take(t1)                            # else on a -> b, or b itself when on the plane
    ab = np.flatnonzero(n_ab.take(t1))
    bc = np.flatnonzero(lower)
    q[ab] = point(e_ab.take(t1.take(ab)), j.take(ab))
    q[bc] = point(e_bc.take(t1.take(bc)), j.take(bc))
    lone, quads = _one_plane(a.take(t1), b.take(t1), c.take(t1), q, point(e_ac.take(t1), j),
                             lower, odd.take(t1))
    if not len(tz):
        return lone, quads
    more, quads_z = _zipped(point, *(x.take(tz) for x in (
        a, b, c, ub, uc, odd, f_ab, n_ab, f_bc, n_bc, f_ac, n_ac, e_ab, e_bc, e_ac)))
    return np.concatenate([lone, more]), np.concatenate([quads, quads_z])


class _Levels:
    """The signed distance s of points to Plane and their level u = s / h in plane units
    (h = gap / samples), those within eps of a plane j snapped onto it (u exactly j), u
    clipped to [-1, samples + 1] so that floor and ceil stay small integers. Computed
    column by column, so a point gets the same numbers in a block of the vertex pass and
    among the few vertices looked at again (a matrix product need not)."""

    def __init__(self, o, n, gap, samples, eps, rows):
        self.o, self.n, self.gap, self.samples, self.eps = o, n, gap, samples, eps
        self.h = gap / samples
        self.terms = [k for k in range(3) if n[k] != 0]     # (a zero term adds nothing)
        self.blind = len(self.terms) < 3      # s does not see every coordinate
        self.range = np.full(rows, -1.0), np.full(rows, samples + 1.0)   # of u, for
        self.unit = np.zeros(rows), np.ones(rows)         # blocks of up to `rows` rows

    def __call__(self, v, u):
        """(s, on, d) of the rows v (k, 3), their levels written to u (k,): on the snapped
        rows (None when none) and d how far each was from its plane."""
        s = self.signed(v)
        np.divide(s, self.h, out=u)
        j = np.rint(u)
        near = np.abs(np.subtract(u, j, out=j)) <= self.eps / self.h
        on, d = None, None
        if near.any():
            on = np.flatnonzero(near)
            j = np.rint(u.take(on))
            inside = (j >= 0) & (j <= self.samples)
            on, j = on[inside], j[inside]
            if len(on):
                d = s.take(on) - self.gap * j / self.samples
                s[on] -= d
                u[on] = j
            else:
                on = None
        _clip(u, self.range)
        return s, on, d

    def signed(self, v):
        """The signed distances s of the rows v (k, 3)."""
        s = None
        for k in self.terms:
            t = v[:, k] - self.o[k]
            if self.n[k] != 1:
                t *= self.n[k]
            s = t if s is None else np.add(s, t, out=s)
        return s

    def onto(self, P, s):
        """The rows P (k, 3) moved along the normal to the signed distances s, in place."""
        d = self.signed(P)
        d -= s
        for k in self.terms:
            P[:, k] -= d if self.n[k] == 1 else d * self.n[k]

    def placed(self, v):
        """(s, u, the rows v snapped onto their planes) for rows v (k, 3) taken from V."""
        u = np.empty(len(v))
        s, on, d = self(v, u)
        if on is not None:
            v[on] -= d[:, None] * self.n
        return s, u, v


def _clip(x, bounds):
    """np.clip(x, lo, hi, out=x) for bounds (lo, hi), two arrays of copies: maximum
    and minimum against arrays are about 2.5x faster on numpy 1.24 (np.clip, and a scalar
    bound, take slower loops)."""
    low, high = bounds
    if len(x) > len(low):                     # (rows gathered again: a scalar will do)
        low, high = low[0], high[0]
    else:
        low, high = low[:len(x)], high[:len(x)]
    np.maximum(x, low, out=x)
    return np.minimum(x, high, out=x)


def _zipped(point, a, b, c, ub, uc, odd, f_ab, n_ab, f_bc, n_bc, f_ac, n_ac, e_ab, e_bc, e_ac):
    """The pieces of triangles crossing planes, each triangle's (a, b, c: its corners sorted
    by level ub, uc; odd: that order reverses it) in turn, flat ones included: its two
    chains a -> c and a -> b -> c (f_*, n_*: the first plane and count each edge crosses;
    e_*: the edge's number for point(e, plane), its cut point's vertex) zipped from a to c.
    Returns (triangles (k, 3), quadrilaterals (m, 4)), in the triangles' orientation.
    """
    # the events of each triangle (the vertices of its two chains after a) in level order,
    # ties put the long chain (a -> c) first
    m = len(a)
    count = n_ab + n_bc + n_ac + 3
    offset = np.cumsum(count) - count
    E = int(count.sum())
    vert = np.empty(E, np.int64)
    long = np.zeros(E, bool)
    lvl = np.empty(E)

    def put(t, pos, v, lv, is_long):
        g = offset.take(t) + pos
        vert[g], lvl[g], long[g] = v, lv, is_long

    def below(jj, first_, count_):        # how many of a chain's planes lie below jj
        return np.clip(jj - first_, 0, count_)

    t, i = _ranges(n_ac)                  # the long chain's cut points, then c
    jj = f_ac.take(t) + i
    put(t, i + below(jj, f_ab.take(t), n_ab.take(t)) + (ub.take(t) < jj)
          + below(jj, f_bc.take(t), n_bc.take(t)), point(e_ac.take(t), jj), jj, True)
    t = np.arange(m)
    put(t, n_ac + n_ab + (ub < uc) + n_bc, c, uc, True)
    t, i = _ranges(n_ab)                  # the short chain: cut points of ab, b, of bc, c
    jj = f_ab.take(t) + i
    put(t, i + below(jj + 1, f_ac.take(t), n_ac.take(t)), point(e_ab.take(t), jj), jj, False)
    t = np.arange(m)
    put(t, n_ab + below(np.floor(ub).astype(np.int64) + 1, f_ac, n_ac) + (uc <= ub), b, ub,
          False)
    t, i = _ranges(n_bc)
    jj = f_bc.take(t) + i
    put(t, n_ab.take(t) + 1 + i + below(jj + 1, f_ac.take(t), n_ac.take(t)),
          point(e_bc.take(t), jj), jj, False)
    t = np.arange(m)
    put(t, count - 1, c, uc, False)

    # each event closes the triangle (current long-chain vertex, current short-chain
    # vertex, the event's vertex); the current vertices start at a
    tri = np.repeat(np.arange(m), count)
    idx = np.arange(E)
    start = offset.take(tri)
    at_a = a.take(tri)
    last_long = np.maximum.accumulate(np.where(long, idx, -1))
    last_short = np.maximum.accumulate(np.where(long, -1, idx))
    new = np.empty((E, 3), np.int64)
    cur_long, cur_short = new[:, 0], new[:, 1]
    new[0, :2] = a[0]
    cur_long[1:] = np.where(last_long[:-1] >= start[1:], vert.take(np.maximum(last_long[:-1], 0)),
                            at_a[1:])
    cur_short[1:] = np.where(last_short[:-1] >= start[1:],
                             vert.take(np.maximum(last_short[:-1], 0)), at_a[1:])
    new[:, 2] = vert
    # a long event followed by a short one on the same level closes a quadrilateral
    # (Lp, Sp, Sj, Lj): its two rows leave the triangles for the quadrilaterals
    x = np.flatnonzero(long[:-1] & ~long[1:] & (tri[:-1] == tri[1:]) & (lvl[:-1] == lvl[1:]))
    quads = np.stack([cur_long.take(x), cur_short.take(x), vert.take(x + 1), vert.take(x)], 1)
    flip = odd.take(tri.take(x))
    quads[flip] = quads.take(np.flatnonzero(flip), axis=0)[:, ::-1]
    rev = np.flatnonzero(odd.take(tri))
    new[rev] = new.take(rev, axis=0)[:, ::-1]
    return np.delete(new, np.concatenate([x, x + 1]), axis=0), quads


def _one_plane(a, b, c, q, p, lower, odd):
    """The pieces of k triangles crossing one plane: corners a, b, c sorted by level; p the
    cut point on a -> c, q the short chain's point on the plane (on b -> c when b is
    `lower` than it, else on a -> b, or b itself). Returns the lone corner's triangles
    (k, 3) and the quadrilaterals on the other side (k, 4), in the triangles' orientation
    (reversed where `odd`), from a table of the 4 cases (_ONE_PLANE) in one gather."""
    source = np.stack([a, b, c, p, q], axis=1)
    at = _ONE_PLANE.take(lower.view(np.int8) * 2 + odd.view(np.int8), axis=0)
    at += (5 * np.arange(len(a)))[:, None]
    pieces = source.reshape(-1).take(at)
    return pieces[:, :3], pieces[:, 3:]


def _one_plane_table():
    """_one_plane's corners by case lower * 2 + odd, as indices into (a, b, c, p, q): the
    lone triangle, then the quadrilateral. Below (a and b below the plane, c above):
    (p, q, c) and (a, b, q, p); above (a alone below): (a, q, p) and (q, b, c, p)."""
    a, b, c, p, q = range(5)
    table = np.empty((4, 7), np.int64)
    for lower, (lone, quad) in enumerate((((a, q, p), (q, b, c, p)),
                                          ((p, q, c), (a, b, q, p)))):
        table[2 * lower] = lone + quad
        table[2 * lower + 1] = lone[::-1] + quad[::-1]
    return table


_ONE_PLANE = _one_plane_table()


def _sorted(U):
    """For the rows U (k, 3) of corner levels: the flat indices into U of each row's
    corners sorted by level, ties kept in corner order (k, 3), and whether that order
    reverses the triangle's orientation (an odd permutation). From three comparisons, a
    case 0..7, and a table of the cases (_SORTED, _ODD)."""
    u0, u1, u2 = U.T
    case = (u1 < u0).view(np.int8) + (u2 < u0).view(np.int8) * 2 + (u2 < u1).view(np.int8) * 4
    order = _SORTED.take(case, axis=0)
    order += (3 * np.arange(len(U)))[:, None]
    return order, _ODD.take(case)


def _sorted_table():
    """_sorted's corner order and oddness by case (u1 < u0) + 2 (u2 < u0) + 4 (u2 < u1);
    the two cases that cannot happen (the comparisons contradict) are given corner order."""
    order, odd = np.tile(np.arange(3), (8, 1)), np.zeros(8, bool)
    for case in range(8):
        c10, c20, c21 = case & 1, case >> 1 & 1, case >> 2 & 1
        rank = (c10 + c20, 1 - c10 + c21, 2 - c20 - c21)
        if sorted(rank) == [0, 1, 2]:
            order[case] = np.argsort(rank)
            odd[case] = (rank[1] - rank[0]) % 3 != 1
    return order, odd


_SORTED, _ODD = _sorted_table()


def _merge_segments(P, segments, eps):
    """Cut points joined by a section segment shorter than eps become one (the first of
    each chain): returns (points kept, the kept index of every point). A sliver triangle
    crossing a plane near its sharp tip puts its two cut points almost together; stored
    apart they would make a needle facet (and in float32 one point). Merged, the two facets
    on that tiny edge vanish (an edge collapse on the plane) and the mesh stays a closed
    2-manifold."""
    d = P.take(segments[:, 0], axis=0)
    d -= P.take(segments[:, 1], axis=0)
    d *= d
    short = segments[np.sqrt(d[:, 0] + d[:, 1] + d[:, 2]) <= eps]
    if not len(short):
        return P, np.arange(len(P))
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    nodes, pair = np.unique(short, return_inverse=True)
    pair = pair.reshape(-1, 2)
    graph = coo_matrix((np.ones(len(pair)), (pair[:, 0], pair[:, 1])), (len(nodes),) * 2)
    _, chain = connected_components(graph, directed=False)
    first = np.full(chain.max() + 1, len(P))
    np.minimum.at(first, chain, nodes)
    target = np.arange(len(P))
    target[nodes] = first[chain]
    keep = target == np.arange(len(P))
    return P.take(np.flatnonzero(keep), axis=0), (np.cumsum(keep) - 1)[target]


def _numbered(keys):
    """(an index of each distinct key, the number of each key among them): the keys
    numbered in the order of those indices, as np.unique(keys, return_inverse=True)
    numbers them in sorted order, without its sort. Non-negative int64 keys go through a
    table 4 to 8 times their count by a multiplicative hash, the last one written to a
    slot keeping it; the keys that find another key in their slot (about 4 % of them) are
    numbered among themselves by np.unique. 5 to 7x faster than the sort on the edges of
    cut triangles."""
    m = len(keys)
    bits = max(10, (4 * m - 1).bit_length())
    slot = keys * np.int64(-7046029254386353131)        # (wraps: a hash)
    slot >>= np.int64(64 - bits)
    slot &= (1 << bits) - 1
    table = np.empty(1 << bits, np.int32 if m < 2 ** 31 else np.int64)
    table[slot] = np.arange(m)
    first = table.take(slot)                  # an index of the same key, one per key
    clash = np.flatnonzero(keys.take(first) != keys)
    if len(clash):
        _, at, back = np.unique(keys.take(clash), return_index=True, return_inverse=True)
        first[clash] = clash.take(at).take(back.reshape(-1))
    own = first == np.arange(m)
    number = np.cumsum(own) - 1
    return np.flatnonzero(own), number.take(first)


def _planes_between(lo, hi, samples):
    """(first, count) of the planes j = 0..samples strictly between the levels lo <= hi."""
    first = np.floor(lo).astype(np.int64) + 1
    first = np.maximum(first, 0)
    last = np.minimum(np.ceil(hi).astype(np.int64) - 1, samples)
    return first, np.maximum(last - first + 1, 0)


def _ranges(counts):
    """(owner, index) for counts: owner i repeated counts[i] times, index 0..counts[i]-1."""
    owner = np.repeat(np.arange(len(counts)), counts)
    return owner, np.arange(len(owner)) - (np.cumsum(counts) - counts)[owner]


def _check_gap(gap):
    gap = float(gap)
    if not np.isfinite(gap) or gap <= 0:
        raise DeformError("Plane2 must lie beyond Plane along its normal (on the moving side); "
                          "move Plane2.", "Plane2")
    return gap


def _vectorized(fn, point, direction, angle, shift=None):
    """Mark fn (fraction -> rotation(point, direction, fraction * angle) @
    translation(-fraction * shift)) as taking arrays, and give it `shifts(points, fracs)`:
    minus the displacement of each column (x, y, z) of the points (K, 3) by fn(fracs[i]),
    without 4x4s (None for a column the motion leaves alone: the axis's, about a
    coordinate axis without shift).

    With Q = p - f shift and r = Q - point, column i moves by -f shift_i + sum_j (sin(phi)
    A_ij + (1 - cos(phi)) B_ij) r_j, A = [k]x and B = [k]x^2 = k k^T - I (Rodrigues), on
    float columns (contiguous 1-D passes; a (K, 3) array times a (K, 1) one is 3x slower),
    the zero terms left out: about a coordinate axis, two terms per column. A term with
    coefficient +-1 needs no product, and a negative one is put first where there is one
    (its negative then needs no negation)."""
    c = np.asarray(point, float).reshape(3)
    k = unit(direction, "Axis").reshape(3)
    d = np.zeros(3) if shift is None else np.asarray(shift, float).reshape(3)
    A, B = skew(k), np.outer(k, k) - np.eye(3)
    # per column: (-coefficient, base, j) of each term, base 0 sin, 1 versine, 2 f (the
    # shift's term: j None), the positive ones first
    terms = [sorted([(-coefficient, base, j) for j in range(3)
                     for coefficient, base in ((A[i, j], 0), (B[i, j], 1)) if coefficient]
                    + ([(d[i], 2, None)] if d[i] else []), key=lambda term: term[0] <= 0)
             for i in range(3)]
    used = sorted({j for row in terms for _, base, j in row if j is not None})

    def shifts(points, fracs):
        f = np.asarray(fracs, float)
        P = np.asarray(points, float)
        r = {}
        for j in used:
            r[j] = P[:, j] - f * d[j] if d[j] else P[:, j] - c[j]
            if d[j]:
                r[j] -= c[j]
        phi = f * angle
        bases = (np.sin(phi), 1.0 - np.cos(phi), f)
        out = []
        for row in terms:
            x = None
            for scale, base, j in row:
                b = bases[base]
                if j is None:
                    term = scale * b
                elif abs(scale) == 1:
                    term = b * r[j]               # its sign applied below
                else:
                    term = (scale * b) * r[j]
                if x is None:
                    x = term
                    if scale == -1 and j is not None:
                        np.negative(x, out=x)
                elif scale == -1 and j is not None:
                    x -= term
                else:
                    x += term
            out.append(x)
        return out

    fn.vectorized = True
    fn.shifts = shifts
    return fn


def twist_motion(origin, normal, gap, angle, axis_point=None, axis_direction=None):
    """f(frac) -> 4x4 taking the section at s = frac*gap to its twisted place: a rotation by
    frac*angle (radians) about the axis (default: the Plane normal through `origin`). No
    translation, so the length along the axis is kept. f also takes an array of fractions
    (K,) and then returns (K, 4, 4)."""
    n = unit_normal(normal)
    _check_gap(gap)
    point = np.asarray(origin if axis_point is None else axis_point, float)
    direction = n if axis_direction is None else axis_direction
    rotation(point, direction, 0.0)                       # checks the direction now
    angle = float(angle)

    def motion_of_s(frac):
        return rotation(point, direction, np.asarray(frac, float) * angle)

    return _vectorized(motion_of_s, point, direction, angle)


def bend_motion(axis_point, axis_direction, angle, origin, normal, gap):
    """f(frac) -> 4x4 for a bend between two planes: the section at s = frac*gap goes to the
    place of the section at s = 0 turned by frac*angle about the axis (which should lie in
    Plane, outside the section): rotation(frac*angle) @ translation(-frac*gap*normal).
    The slab becomes the section at Plane revolved by `angle`; the part beyond Plane2 is moved
    by f(1). Vectorized like twist_motion."""
    n = unit_normal(normal)
    gap = _check_gap(gap)
    point = np.asarray(axis_point, float)
    rotation(point, axis_direction, 0.0)
    angle = float(angle)

    def motion_of_s(frac):
        f = np.asarray(frac, float)
        return rotation(point, axis_direction, f * angle) @ translation(
            -(f * gap)[..., None] * n)

    return _vectorized(motion_of_s, point, axis_direction, angle, gap * n)
