"""DirectPush's pushes in order, on numpy curves and surfaces (geometry.nurbs.direct_push
does one push): the element set up under its constraints (State), a point grabbed on it
(Grab), the pushes replayed, and what the result reports (the largest pole move, the
region that moved); Pratt's blend rows and the re-landing of pushed points after a
blend; points for drawing the element.

The constraints come as points on the element (Fixed, Straight, Angles, as the feature's
properties hold them); every refusal names the property to change.
"""
from typing import NamedTuple

import numpy as np

from . import direct_push as dp
from ..errors import DeformError


class State(NamedTuple):
    """The element after its constraints (`start`) and its pushes (`current`): what the
    feature builds its result from and what the task panel drags."""
    shape_type: str    # "Edge" (a Curve) or "Face" (a Surface)
    original: object   # the element as given: constraints are given on it
    start: object      # after the constraints
    current: object    # after the constraints and every push
    size: int          # poles a push may move (per direction)
    fixed: list        # Fixed as parameters: t, or (u, v)
    spans: list        # Straight as parameter pairs
    corners: list      # the corner parameters of Angles (edges)
    held: list         # the poles an angle holds (faces)
    params: list       # where each push grabbed the element (as the pushes before left it)
    points: list       # the point there
    note: str          # how the element became a B-spline
    tol: float         # how far a point may be from the element
    surface: object = None    # the caller's surface `original` came from (kept for it)
    trim: object = None       # the caller's trimmed face whose boundary bounds the result
    boundary: object = None   # a trimmed face of a solid or shell: its boundary's (u, v)
                              # points; the poles that move them stay


def pairs(vectors, prop):
    """Consecutive pairs of a flat list of vectors (Straight, Angles)."""
    v = [np.array(tuple(x), float) for x in vectors]
    if len(v) % 2:
        raise DeformError(f"{prop} holds pairs of vectors; it has an odd count.", prop)
    return list(zip(v[0::2], v[1::2]))


def check_angle(degrees, before, after):
    if not (0 < degrees < 180 and before > 0 and after > 0):
        raise DeformError("An angle is between 0 and 180 degrees and its legs are longer "
                          "than 0; change Angles.", "Angles")


def check_on(distance, tol, what, name):
    """Refuse a point (`what`, e.g. "Fixed[0]") that is farther than tol from `name`."""
    if distance > tol:
        raise DeformError(f"{what} is not on {name} ({distance:.3g} mm away); pick a point "
                          "on it.", what.split("[")[0])


def range_size(range, degree, interior):
    """Poles a push may move (per direction): Range + 1 (Range 0: degree + 2), at most
    what the element has (dp.range_bound): a larger Range moves all of them."""
    if range < 0:
        raise DeformError(f"Range {range} is negative; give 0 (degree + 1) or more.", "Range")
    return min((range if range > 0 else degree + 1) + 1, dp.range_bound(interior, degree))


def curve_state(original, fixed=(), straight=(), angles=(), range=0, tol=1e-7, note="",
                name="the element"):
    """The State of a Curve `original` under its constraints: knots at Fixed points, Straight spans
    (pairs of points) made straight, Angles (pairs: corner, (degrees, leg before, leg
    after)) made cusps; `name` names the element in refusals."""
    c = original
    p = c.degree

    def param(x, what):
        t, d = dp.closest_parameter(original, np.array(tuple(x), float))
        check_on(d, tol, what, name)
        return t
    fixed = [param(x, f"Fixed[{i}]") for i, x in enumerate(fixed)]
    spans = [tuple(sorted((param(a, f"Straight[{2 * i}]"), param(b, f"Straight[{2 * i + 1}]"))))
             for i, (a, b) in enumerate(pairs(straight, "Straight"))]
    corners = [(param(x, f"Angles[{2 * i}]"), x, spec)
               for i, (x, spec) in enumerate(pairs(angles, "Angles"))]
    for t in fixed:
        c = dp.curve_with_knot(c, t, p)
    for a, b in spans:
        c, _ = dp.make_straight(c, a, b)
    for t, x, (degrees, before, after) in corners:
        check_angle(degrees, before, after)
        c, _ = dp.make_angle(c, t, np.radians(degrees), (before, after), x)
    size = range_size(range, p, len(c.poles) - 2)
    return State("Edge", original, c, c, size, fixed, spans, [t for t, _, _ in corners], [],
                 [], [], note, tol)


def surface_state(original, fixed=(), straight=(), angles=(), range=0, tol=1e-7, note="",
                  name="the element", **kept):
    """The State of a Surface under its constraints (as curve_state; a Straight span is
    the iso-curve from its first point toward its second, an Angle a crease along the v
    iso-curve through the corner). `kept`: State's surface, trim, boundary."""
    s = original

    def uv(x, what):
        u, v, d = dp.closest_uv(original, np.array(tuple(x), float))
        check_on(d, tol, what, name)
        return u, v
    fixed = [uv(x, f"Fixed[{i}]") for i, x in enumerate(fixed)]
    spans = [(uv(a, f"Straight[{2 * i}]"), uv(b, f"Straight[{2 * i + 1}]"))
             for i, (a, b) in enumerate(pairs(straight, "Straight"))]
    for a, b in spans:
        s, _ = dp.make_straight_surface(s, a, b)
    held = []
    for i, (x, (degrees, before, after)) in enumerate(pairs(angles, "Angles")):
        check_angle(degrees, before, after)
        s, held = dp.make_angle_surface(s, uv(x, f"Angles[{2 * i}]"), np.radians(degrees),
                                        (before, after), x)
    size = range_size(range, max(s.udegree, s.vdegree), max(s.weights.shape) - 2)
    return State("Face", original, s, s, size, fixed, spans, [], held, [], [], note, tol,
                 **kept)


def point_at(arrays, at):
    """The point of a Curve at t, or of a Surface at (u, v)."""
    if isinstance(arrays, dp.Curve):
        return dp.evaluate(arrays, at)
    return dp.surface_row(arrays, *at) @ arrays.poles.reshape(-1, 3)


def hold_boundary(arrays, at, boundary, held=(), tries=10, share=0.5):
    """(arrays, held): the poles that move a trimmed boundary (its (u, v) points) held, the
    analogue of border poles; knots inserted next to the point at (u, v) (the paper's note
    a) until the poles free to move carry `share` of the point's basis (fewer would move
    far to carry the point). With other poles already held, no knot is inserted."""
    for _ in range(tries):
        hold = set(held) | dp.influencing(arrays, boundary)
        nu, nv = arrays.weights.shape
        row = dp.surface_row(arrays, *at)
        free = sum(row[k] for k in np.nonzero(row)[0] if k not in hold and
                   0 < k // nv < nu - 1 and 0 < k % nv < nv - 1)
        if free >= share or held:
            break
        arrays = dp.refine_at(arrays, *at)
    return arrays, sorted(hold)


class Grab:
    """`arrays` (the element under the state's constraints) grabbed at parameter `at`: the
    point there, a face's unit normal there, and pushed(target): the element with that
    point moved exactly to the target."""

    def __init__(self, state, arrays, at):
        self.state, self.at, self.normal = state, at, None
        if state.shape_type == "Edge":
            arrays = dp.refine_curve(arrays, at, state.size)
            p = arrays.degree
            self.held = [k + j for t in state.fixed for k in [dp.pole_at(arrays, t)]
                         for j in (-1, 0, 1)]
            self.held += [k + j for t in state.corners for k in [dp.pole_at(arrays, t)]
                          for j in range(-p, p + 1)]
            self.groups = [dp.straight_poles(arrays, a, b) for a, b in state.spans]
        else:
            if min(arrays.weights.shape) < 3:  # no interior pole in one direction (a cylinder)
                arrays = dp.refine_surface(arrays, *at, 1)
            self.held = state.held
            if state.boundary is not None:
                arrays, self.held = hold_boundary(arrays, at, state.boundary, state.held)
            self.groups = [dp.straight_group(arrays, a, b) for a, b in state.spans]
            poles = arrays.poles.reshape(-1, 3)
            normal = np.cross(dp.surface_row(arrays, *at, 1, 0) @ poles,
                              dp.surface_row(arrays, *at, 0, 1) @ poles)
            if np.linalg.norm(normal) > 0:
                self.normal = normal / np.linalg.norm(normal)
        self.arrays = arrays
        self.point = point_at(arrays, at)

    def pushed(self, target):
        target = np.asarray(target, float)
        try:
            if self.state.shape_type == "Edge":
                return dp.push_curve(self.arrays, self.at, target, self.state.size, self.held,
                                     self.groups, dp.is_closed(self.state.original,
                                                               self.state.tol))
            return dp.push_surface(self.arrays, *self.at, target, self.state.size,
                                   self.state.fixed, self.groups, self.held)
        except DeformError as e:
            if "contradict" not in str(e):
                raise
            raise self._contradiction(e) from None

    def _contradiction(self, error):
        """The contradiction named by what holds the poles the point depends on: an end of
        the edge (Points), a Fixed point, a Straight span or an Angle; else too few poles
        in Range."""
        state, a = self.state, self.arrays
        if state.shape_type == "Edge":
            support = set(np.nonzero(dp.curve_row(a, self.at))[0].tolist())
            fixed = [{dp.pole_at(a, t) + j for j in (-1, 0, 1)} for t in state.fixed]
            p = a.degree
            angles = [{dp.pole_at(a, t) + j for j in range(-p, p + 1)} for t in state.corners]
            if support <= {0, len(a.poles) - 1}:
                return DeformError("The point is an end of the edge, and the ends of an open "
                                   "edge never move (its neighbours hold them); pick Points "
                                   "inside the edge.", "Points")
        else:
            support = dp.influencing(a, [self.at])
            fixed = [dp.influencing(a, [uv]) for uv in state.fixed]
            angles = [set(state.held)]
        for name, sets in (("Fixed", fixed), ("Angles", angles),
                           ("Straight", [set(g) for g in self.groups])):
            hit = [i for i, x in enumerate(sets) if x & support]
            if hit:
                entry = f"{name}[{hit[0]}]" if name == "Fixed" else name
                return DeformError(f"The push and {entry} contradict each other: the point "
                                   f"is on (or next to) what {name} holds in place; push "
                                   f"farther from it or change {name}.", name)
        return DeformError(f"{error} ".split(";")[0] + "; raise Range.", "Range")


def replay(state, targets, grab_at):
    """The State after every push: push i grabs the element (as the pushes before left it)
    at grab_at(i, current) and takes that point to targets[i]."""
    current = state.start
    params, points = list(state.params), list(state.points)
    for i, target in enumerate(targets):
        grab = Grab(state, current, grab_at(i, current))
        params.append(grab.at)
        points.append(grab.point)
        try:
            current = grab.pushed(np.array(tuple(target), float))
        except DeformError as e:
            raise DeformError(f"Points[{i}]: {e}", e.prop) from None
    return state._replace(current=current, params=params, points=points)


def max_pole_move(before, after):
    """The largest pole move (knots inserted since are inserted into `before` too, so the
    poles compare one to one), or nan when they cannot be."""
    if before.poles.shape != after.poles.shape:
        before = dp.with_knots_of(before, after)
        if before is None or before.poles.shape != after.poles.shape:
            return float("nan")
    return float(np.linalg.norm((after.poles - before.poles).reshape(-1, 3), axis=1).max()) \
        if after.poles.size else 0.0


def moved_region(before, after):
    """(u0, u1, v0, v1): the parameter rectangle where the surface `after` differs from
    `before` (the supports of the poles that moved), or None when none moved."""
    if before.poles.shape != after.poles.shape:
        before = dp.with_knots_of(before, after)
        if before is None or before.poles.shape != after.poles.shape:
            return (after.uknots[after.udegree], after.uknots[-after.udegree - 1],
                    after.vknots[after.vdegree], after.vknots[-after.vdegree - 1])
    i, j = np.nonzero(np.any(after.poles != before.poles, axis=2))
    if not len(i):
        return None
    (p, U), (q, W) = (after.udegree, after.uknots), (after.vdegree, after.vknots)
    # pole k's basis is nonzero on [U[k], U[k + p + 1]], within [U[p], U[n]]
    return (float(U[max(i.min(), p)]), float(U[min(i.max() + p + 1, len(U) - p - 1)]),
            float(W[max(j.min(), q)]), float(W[min(j.max() + q + 1, len(W) - q - 1)]))


def reland(s, landed, held):
    """The pushed points back on their targets after a blend moved the patch's border:
    landed holds (u, v, target); a least-norm correction of the interior poles, keeping
    the poles that make the blend C1 (`held`, flat indices)."""
    nu, nv = s.weights.shape
    P = s.poles.reshape(-1, 3)
    rows = [dp.surface_row(s, u, v) for u, v, _ in landed]
    rhs = [t - r @ P for r, (_, _, t) in zip(rows, landed)]
    movable = [i * nv + j for i in range(1, nu - 1) for j in range(1, nv - 1)
               if i * nv + j not in held]
    D = dp.least_norm(nu * nv, movable, rows, rhs)
    return s._replace(poles=(P + D).reshape(s.poles.shape))


def border_rows(patch, ends, tol, name):
    """(index of the border row of poles along the edge from ends[0] to ends[1], index of
    the row next to it inside), as numpy index tuples into patch.poles, ordered like the
    edge; `name` (the edge, an entry of Blend) names it in the refusal."""
    nu, nv = patch.weights.shape
    iu, iv = np.arange(nu), np.arange(nv)
    borders = [((np.zeros(nv, int), iv), (np.ones(nv, int), iv)),
               ((np.full(nv, nu - 1), iv), (np.full(nv, nu - 2), iv)),
               ((iu, np.zeros(nu, int)), (iu, np.ones(nu, int))),
               ((iu, np.full(nu, nv - 1)), (iu, np.full(nu, nv - 2)))]
    for row, inner in borders:
        for flip in (False, True):
            r = tuple(x[::-1] for x in row) if flip else row
            pts = patch.poles[r]
            if np.linalg.norm(pts[0] - ends[0]) <= tol and np.linalg.norm(pts[-1] - ends[1]) <= tol:
                return r, (tuple(x[::-1] for x in inner) if flip else inner)
    raise DeformError(f"Blend {name} is not along the border of its face's patch (was the "
                      "face refined?).", "Blend")


def sample_points(arrays, curve_samples=300, surface_range=(30, 90)):
    """Points for drawing: (curve_samples, 3) along a Curve; over a Surface an (a, b, 3)
    grid, 3 per pole in each direction within surface_range."""
    if isinstance(arrays, dp.Curve):
        p = arrays.degree
        ts = np.linspace(arrays.knots[p], arrays.knots[-p - 1], curve_samples)
        rows = dp.basis(arrays.knots, p, len(arrays.weights), ts) * arrays.weights
        return (rows @ arrays.poles) / rows.sum(axis=1)[:, None]
    rows = []
    for knots, degree, n in ((arrays.uknots, arrays.udegree, arrays.weights.shape[0]),
                             (arrays.vknots, arrays.vdegree, arrays.weights.shape[1])):
        ts = np.linspace(knots[degree], knots[-degree - 1], int(np.clip(3 * n, *surface_range)))
        rows.append(dp.basis(knots, degree, n, ts))
    homogeneous = np.concatenate([arrays.poles * arrays.weights[..., None],
                                  arrays.weights[..., None]], axis=-1)
    grid = np.tensordot(np.tensordot(rows[0], homogeneous, (1, 0)), rows[1], (1, 1))
    grid = grid.transpose(0, 2, 1)
    return grid[..., :3] / grid[..., 3:]
