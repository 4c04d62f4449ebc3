"""Direct deformation kernel (Yamashita & Fukui): exact landing, least norm, knot insertion,
fixed points, straight spans, angles, surfaces.

Oracles written here: scipy's BSpline evaluation of the poles (not the kernel's rows), the
closed-form least-norm step of the paper (V'_j = V_j + w_j d / sum w^2), sampled points
for straightness, angles between legs from the poles' geometry."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from freecad_deform.geometry.nurbs import direct_push as dp
from freecad_deform.geometry.errors import DeformError

from ..oracles.nurbs import canopy, clamped


def wavy(n=9, degree=3):
    x = np.linspace(0, 80, n)
    poles = np.column_stack([x, 10 * np.sin(x / 12), 3 * np.cos(x / 20)])
    knots = np.r_[np.zeros(degree + 1), np.linspace(0, 1, n - degree + 1)[1:-1],
                  np.ones(degree + 1)]
    return dp.Curve(poles, np.ones(n), knots, degree)


def at(c, t, nu=0):
    """The test's own evaluation (non-rational curves): scipy BSpline on the poles."""
    b = BSpline(c.knots, c.poles, c.degree)
    return (b.derivative(nu) if nu else b)(t)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.05, 0.95), st.tuples(*[st.floats(-20, 20)] * 3))
def test_push_lands_exactly_and_keeps_the_ends(t, move):
    c = wavy()
    target = at(c, t) + np.array(move)
    new = dp.push_curve(c, t, target, c.degree + 2)
    assert np.abs(at(new, t) - target).max() < 1e-9
    assert np.all(new.poles[[0, -1]] == c.poles[[0, -1]])
    assert np.count_nonzero(np.abs(new.poles - c.poles).max(axis=1)) <= c.degree + 2


def test_one_push_is_the_papers_formula_with_the_least_norm_factor():
    c = wavy()
    t, d = 0.37, np.array([0.0, 2.0, 5.0])
    row = dp.curve_row(c, t)
    window = np.nonzero(row)[0]                       # the degree + 1 poles at t (paper: m = 3)
    new = dp.push_curve(c, t, at(c, t) + d, len(window))
    w = row[window]
    np.testing.assert_allclose(new.poles[window] - c.poles[window], np.outer(w, d) / (w @ w),
                               atol=1e-12)


def test_knot_insertion_keeps_the_curve():
    c = wavy()
    U, P, w = dp.insert_knot(c.knots, c.degree, c.poles, c.weights, 0.41, 3)
    refined = dp.Curve(P, w, U, c.degree)
    ts = np.linspace(0, 1, 101)
    assert np.abs(at(refined, ts) - at(c, ts)).max() < 1e-12
    assert len(P) == len(c.poles) + 3
    assert np.abs(P[dp.pole_at(refined, 0.41)] - at(c, 0.41)).max() < 1e-12   # on the curve


def test_fixed_point_keeps_position_and_tangent_under_a_push_next_to_it():
    c = wavy()
    tf = 0.5
    fixed = dp.curve_with_knot(c, tf, c.degree)
    k = dp.pole_at(fixed, tf)
    before, tangent = at(c, tf), at(c, tf, 1)
    pushed = dp.push_curve(fixed, 0.42, at(c, 0.42) + [0, 6, 2], c.degree + 2, [k - 1, k, k + 1])
    assert np.abs(at(pushed, 0.42) - at(c, 0.42) - [0, 6, 2]).max() < 1e-9
    assert np.abs(at(pushed, tf) - before).max() < 1e-12
    for side in (tf - 1e-12, tf + 1e-12):
        d = at(pushed, side, 1)
        angle = np.arccos(np.clip(d @ tangent / np.linalg.norm(d) / np.linalg.norm(tangent), -1, 1))
        assert angle < 1e-7


def test_straight_span_is_straight_and_stays_straight():
    c = wavy()
    s, group = dp.make_straight(c, 0.6, 0.8)
    pushed = dp.push_curve(s, 0.5, at(s, 0.5) + [0, 0, 5], c.degree + 2, (), [group])
    for curve in (s, pushed):
        pts = at(curve, np.linspace(0.6, 0.8, 41))
        d = (pts[-1] - pts[0]) / np.linalg.norm(pts[-1] - pts[0])
        off = pts - pts[0]
        assert np.abs(off - np.outer(off @ d, d)).max() < 1e-9
    assert np.abs(at(pushed, 0.5) - at(s, 0.5) - [0, 0, 5]).max() < 1e-9


def test_angle_has_straight_legs_at_the_angle_and_lengths_asked():
    c = wavy()
    a, _ = dp.make_angle(c, 0.5, np.radians(60), (6.0, 9.0), corner=[40, 5, 1])
    corner = at(a, 0.5)
    np.testing.assert_allclose(corner, [40, 5, 1], atol=1e-12)
    k = dp.pole_at(a, 0.5)
    p = c.degree
    legs = a.poles[k - p] - corner, a.poles[k + p] - corner
    assert np.linalg.norm(legs[0]) == pytest.approx(6.0) and np.linalg.norm(legs[1]) == pytest.approx(9.0)
    cos = legs[0] @ legs[1] / np.linalg.norm(legs[0]) / np.linalg.norm(legs[1])
    assert np.degrees(np.arccos(cos)) == pytest.approx(60.0, abs=1e-9)
    for side in (np.linspace(0.5 - 0.1, 0.5, 20), np.linspace(0.5, 0.6, 20)):
        pts = at(a, side)                            # each leg a straight segment
        d = (pts[-1] - pts[0]) / np.linalg.norm(pts[-1] - pts[0])
        off = pts - pts[0]
        assert np.abs(off - np.outer(off @ d, d)).max() < 1e-9


def test_contradicting_constraints_are_refused():
    c = wavy()
    k = len(c.poles) // 2
    with pytest.raises(DeformError, match="contradict"):
        # the only movable poles are held: nothing can move the point
        dp.least_norm(len(c.poles), [k], [np.eye(len(c.poles))[k], np.eye(len(c.poles))[k]],
                      [[0, 0, 1], [0, 0, 2]])


def test_surface_push_along_the_normal_lands_and_the_border_stays():
    s = canopy()
    u, v = 0.37, 0.61
    P = s.poles.reshape(-1, 3)
    point = dp.surface_row(s, u, v) @ P
    n = np.cross(dp.surface_row(s, u, v, 1, 0) @ P, dp.surface_row(s, u, v, 0, 1) @ P)
    target = point + 5 * n / np.linalg.norm(n)
    new = dp.push_surface(s, u, v, target, 5)
    su = BSpline(s.uknots, new.poles, 3)(u)            # the test's own evaluation
    assert np.abs(BSpline(s.vknots, su, 3)(v) - target).max() < 1e-9
    border = np.ones((6, 6), bool)
    border[1:-1, 1:-1] = False
    assert np.all(new.poles[border] == s.poles[border])


def test_surface_fixed_point_keeps_position_and_tangent_plane():
    s = canopy()
    P = s.poles.reshape(-1, 3)
    f = (0.55, 0.5)
    rows = [dp.surface_row(s, *f, du, dv) for du, dv in ((0, 0), (1, 0), (0, 1))]
    new = dp.push_surface(s, 0.35, 0.45, dp.surface_row(s, 0.35, 0.45) @ P + [0, 0, 4], 5, [f])
    Q = new.poles.reshape(-1, 3)
    for r in rows:
        assert np.abs(r @ Q - r @ P).max() < 1e-9


def test_closest_parameters_find_points_on_curves_and_surfaces():
    c = wavy()
    t, d = dp.closest_parameter(c, at(c, 0.3141))
    assert abs(t - 0.3141) < 1e-9 and d < 1e-9
    s = canopy()
    x = dp.surface_row(s, 0.27, 0.83) @ s.poles.reshape(-1, 3)
    u, v, d = dp.closest_uv(s, x)
    assert abs(u - 0.27) < 1e-9 and abs(v - 0.83) < 1e-9 and d < 1e-9


def test_bezier_patch_of_a_planar_quad_is_exact():
    corners = [[0, 0, 10], [20, 0, 10], [20, 30, 10], [0, 30, 10]]
    s = dp.bezier_patch(corners)
    P = s.poles.reshape(-1, 3)
    for u, v in ((0, 0), (1, 0), (1, 1), (0, 1), (0.3, 0.7)):
        np.testing.assert_allclose(dp.surface_row(s, u, v) @ P,
                                   [20 * u, 30 * v, 10], atol=1e-12)


def test_a_push_on_a_straight_span_moves_it_whole_and_keeps_it_straight():
    c = wavy()
    s, group = dp.make_straight(c, 0.4, 0.7)
    target = at(s, 0.55) + [0, 0, 3]
    pushed = dp.push_curve(s, 0.55, target, c.degree + 2, (), [group])
    assert np.abs(at(pushed, 0.55) - target).max() < 1e-9
    moves = pushed.poles[group] - s.poles[group]
    assert np.abs(moves - moves[0]).max() < 1e-12 and np.abs(moves[0]).max() > 0
    pts = at(pushed, np.linspace(0.4, 0.7, 31))
    d = (pts[-1] - pts[0]) / np.linalg.norm(pts[-1] - pts[0])
    assert np.abs((pts - pts[0]) - np.outer((pts - pts[0]) @ d, d)).max() < 1e-9


def test_surface_refinement_keeps_the_surface_and_adds_interior_poles():
    s = canopy(4)                                       # a Bezier patch: 2 x 2 interior poles
    r = dp.refine_surface(s, 0.3, 0.6, 4)
    assert r.weights.shape[0] - 2 >= 4 and r.weights.shape[1] - 2 >= 4
    for u, v in ((0.1, 0.2), (0.3, 0.6), (0.9, 0.45)):
        a = dp.surface_row(s, u, v) @ s.poles.reshape(-1, 3)
        b = dp.surface_row(r, u, v) @ r.poles.reshape(-1, 3)
        assert np.abs(a - b).max() < 1e-12


@settings(max_examples=30, deadline=None)
@given(st.floats(0.1, 0.9), st.floats(-15, 15), st.floats(2, 15))
def test_condition_1_the_curve_ends_on_the_far_side_of_the_cursor_path(t, slide, depth):
    """The paper's Condition 1, in the plane of a flat curve: the pushed curve does not
    cross the cursor's path m0 -> m1 before its end m1 (where the point landed)."""
    c = wavy()
    c = c._replace(poles=c.poles * [1, 1, 0])
    p = at(c, t)
    normal = np.array([-at(c, t, 1)[1], at(c, t, 1)[0], 0.0])
    normal /= np.linalg.norm(normal)
    m0 = p - 2 * normal + [slide * 0.1, 0, 0]
    m1 = p + depth * normal
    new = dp.push_curve(c, t, m1, c.degree + 2)
    pts = at(new, np.linspace(0, 1, 4001))[:, :2]
    a, b = m0[:2], m1[:2] - 0.01 * (m1[:2] - m0[:2])        # the path, short of its end

    def cross(o, x, y):
        return (x[..., 0] - o[0]) * (y[..., 1] - o[1]) - (x[..., 1] - o[1]) * (y[..., 0] - o[0])
    q, r = pts[:-1], pts[1:]
    s1, s2 = cross(a, b, q), cross(a, b, r)
    s3 = (r[:, 0] - q[:, 0]) * (a[1] - q[:, 1]) - (r[:, 1] - q[:, 1]) * (a[0] - q[:, 0])
    s4 = (r[:, 0] - q[:, 0]) * (b[1] - q[:, 1]) - (r[:, 1] - q[:, 1]) * (b[0] - q[:, 0])
    assert not np.any((s1 * s2 < 0) & (s3 * s4 < 0))


def test_surface_straight_iso_span_is_straight_and_stays_under_a_push():
    s = canopy()
    a, b = (0.3, 0.55), (0.7, 0.55)
    st_, group = dp.make_straight_surface(s, a, b)
    P = st_.poles.reshape(-1, 3)

    def line_dev(surface):
        Q = surface.poles.reshape(-1, 3)
        pts = np.array([dp.surface_row(surface, u, 0.55) @ Q for u in np.linspace(0.3, 0.7, 41)])
        d = (pts[-1] - pts[0]) / np.linalg.norm(pts[-1] - pts[0])
        off = pts - pts[0]
        return np.abs(off - np.outer(off @ d, d)).max()
    assert line_dev(st_) < 1e-9
    pushed = dp.push_surface(st_, 0.5, 0.25, dp.surface_row(st_, 0.5, 0.25) @ P + [0, 0, 3], 5,
                             groups=[group])
    assert line_dev(pushed) < 1e-9
    Q = pushed.poles.reshape(-1, 3)
    assert np.abs(dp.surface_row(pushed, 0.5, 0.25) @ Q - dp.surface_row(st_, 0.5, 0.25) @ P
                  - [0, 0, 3]).max() < 1e-9
    # the surface away from the iso-line keeps its shape
    far = dp.surface_row(s, 0.5, 0.95) @ s.poles.reshape(-1, 3)
    assert np.abs(dp.surface_row(st_, 0.5, 0.95) @ P - far).max() < 1e-9


def test_surface_angle_is_a_crease_with_straight_sides_at_the_angle():
    s = canopy()
    a, held = dp.make_angle_surface(s, (0.5, 0.5), np.radians(120), (8.0, 8.0))
    Q = a.poles.reshape(-1, 3)
    crease = dp.surface_row(a, 0.5, 0.5) @ Q
    np.testing.assert_allclose(crease, dp.surface_row(s, 0.5, 0.5) @ s.poles.reshape(-1, 3),
                               atol=1e-9)
    j0 = int(np.searchsorted(a.vknots, 0.5 - 1e-12)) - 1
    i = 3
    legs = a.poles[i, j0 - 3] - a.poles[i, j0], a.poles[i, j0 + 3] - a.poles[i, j0]
    cos = legs[0] @ legs[1] / np.linalg.norm(legs[0]) / np.linalg.norm(legs[1])
    assert np.degrees(np.arccos(cos)) == pytest.approx(120, abs=1e-9)
    for side in (np.linspace(0.35, 0.5, 15), np.linspace(0.5, 0.62, 15)):   # straight in v
        pts = np.array([dp.surface_row(a, 0.4, t) @ Q for t in side])
        d = (pts[-1] - pts[0]) / np.linalg.norm(pts[-1] - pts[0])
        assert np.abs((pts - pts[0]) - np.outer((pts - pts[0]) @ d, d)).max() < 1e-9
    assert len(held) == a.weights.shape[0] * 7 and max(held) < a.weights.size


def test_coons_patch_of_four_quarter_circles_is_the_disk():
    """A disk bounded by four rational quarter arcs: the border rows are the arcs and the
    area is pi r^2 (the test's own Gauss-Legendre integration of |S_u x S_v|)."""
    r, w = 5.0, np.sqrt(0.5)

    def arc(a0, a1):
        mid = (a0 + a1) / 2
        k = r / np.cos((a1 - a0) / 2)
        return dp.Curve(np.array([[r * np.cos(a0), r * np.sin(a0), 0],
                                  [k * np.cos(mid), k * np.sin(mid), 0],
                                  [r * np.cos(a1), r * np.sin(a1), 0]]),
                        np.array([1, w, 1]), np.array([0, 0, 0, 1, 1, 1.0]), 2)
    d = np.radians
    s = dp.coons_patch(arc(d(-45), d(45)), arc(d(225), d(135)), arc(d(-45), d(-135)),
                       arc(d(45), d(135)))
    x, gw = np.polynomial.legendre.leggauss(30)
    u = (x + 1) / 2
    P = s.poles.reshape(-1, 3)
    area = 0.0
    for a, wa in zip(u, gw / 2):
        for b, wb in zip(u, gw / 2):
            area += wa * wb * np.linalg.norm(np.cross(dp.surface_row(s, a, b, 1, 0) @ P,
                                                      dp.surface_row(s, a, b, 0, 1) @ P))
    assert area == pytest.approx(np.pi * r * r, rel=1e-12)
    assert np.all(s.poles[..., 2] == 0)


# --- real-surface traits: C1 knots, collapsed rows, trimmed boundaries, large nets ----------

def c1_surface(nu=18, nv=8, collapsed=False, scale=1.0, offset=(0, 0, 0)):
    """A bicubic surface like real IGES ones: interior knots of multiplicity 2 (C1), a
    wavy net; `collapsed`: the first row of poles is one point (a degenerated edge)."""
    def knots(n):
        inner = np.repeat(np.linspace(0, 1, (n - 4) // 2 + 2)[1:-1], 2)
        return np.r_[np.zeros(4), inner, np.ones(4)]
    assert nu % 2 == 0 and nv % 2 == 0
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    P = np.stack([10 * i, 12 * j, 6 * np.sin(i / 3) * np.cos(j / 2.5)], axis=2) * scale
    if collapsed:
        P[0] = P[0, 0]
    P = P + np.asarray(offset, float)
    return dp.Surface(P, np.ones((nu, nv)), knots(nu), knots(nv), 3, 3)


def scipy_point(s, u, v, poles=None):
    """The test's own evaluation (non-rational): scipy BSpline along u, then along v."""
    su = BSpline(s.uknots, s.poles if poles is None else poles, s.udegree)(u)
    return BSpline(s.vknots, su, s.vdegree)(v)


def test_local_rows_equal_the_full_basis_on_c1_knots():
    s = c1_surface(18, 14)
    nu, nv = s.weights.shape
    for u, v in ((0.0, 0.0), (1 / 7, 0.5), (0.3, 1.0), (1.0, 0.77), (0.5, 1 / 6)):
        Nu = BSpline(s.uknots, np.eye(nu), 3)(u)
        Nv = BSpline(s.vknots, np.eye(nv), 3)(v)
        np.testing.assert_allclose(dp.surface_row(s, u, v), np.outer(Nu, Nv).ravel(),
                                   atol=1e-14)
        dNu = BSpline(s.uknots, np.eye(nu), 3).derivative()(u)
        np.testing.assert_allclose(dp.surface_row(s, u, v, 1, 0), np.outer(dNu, Nv).ravel(),
                                   atol=1e-11)


def test_influencing_poles_are_those_with_a_nonzero_basis_on_the_boundary():
    s = c1_surface(18, 8)
    t = np.linspace(0, 1, 50)
    loop = np.column_stack([0.3 + 0.2 * np.cos(2 * np.pi * t), 0.5 + 0.3 * np.sin(2 * np.pi * t)])
    found = dp.influencing(s, loop)
    Nu = BSpline(s.uknots, np.eye(18), 3)(loop[:, 0])
    Nv = BSpline(s.vknots, np.eye(8), 3)(loop[:, 1])
    expected = {i * 8 + j for k in range(len(loop)) for i in np.nonzero(Nu[k])[0]
                for j in np.nonzero(Nv[k])[0]}
    assert found == expected


def test_refining_at_a_point_keeps_the_surface():
    s = c1_surface(18, 8, collapsed=True)
    r = dp.refine_at(s, 0.31, 0.52)
    assert r.weights.shape[0] > 18 and r.weights.shape[1] > 8
    for u, v in np.random.default_rng(1).random((40, 2)):
        assert np.abs(scipy_point(r, u, v) - scipy_point(s, u, v)).max() < 1e-12


def test_push_next_to_a_trimmed_boundary_with_its_poles_held_keeps_the_boundary():
    s = c1_surface(18, 8)
    t = np.linspace(0, 1, 400)
    boundary = np.column_stack([0.2 + 0.6 * t, 0.25 + 0.1 * np.sin(6 * t)])   # a trim curve
    held = dp.influencing(s, boundary)
    u, v = 0.5, 0.7
    target = scipy_point(s, u, v) + [0, 0, 4]
    new = dp.push_surface(s, u, v, target, 5, held=held)
    assert np.abs(scipy_point(new, u, v) - target).max() < 1e-9
    moved = np.abs(scipy_point(new, boundary[:, 0], boundary[:, 1]) -
                   scipy_point(s, boundary[:, 0], boundary[:, 1])).max()
    assert moved == 0.0


def test_a_point_on_a_collapsed_row_is_refused_and_one_beside_it_lands():
    s = c1_surface(18, 14, collapsed=True)
    apex = s.poles[0, 0]
    u, v, d = dp.closest_uv(s, apex)
    assert np.isfinite([u, v, d]).all() and d < 1e-12
    with pytest.raises(DeformError, match="border") as err:
        dp.push_surface(s, u, v, apex + [0, 0, 3], 5)
    assert err.value.prop == "Points"
    target = scipy_point(s, 0.02, 0.5) + [0, 0, 3]
    new = dp.push_surface(s, 0.02, 0.5, target, 5)
    assert np.isfinite(new.poles).all()
    assert np.abs(scipy_point(new, 0.02, 0.5) - target).max() < 1e-9
    assert np.all(new.poles[0] == apex)                      # the collapsed row stays


def test_a_terrain_sized_net_is_pushed_locally_and_lands_to_its_scale():
    """312 x 322 poles at km coordinates (like occt_terrain.brep's 312 x 323): only the
    local poles move, the point lands to 1e-12 of the model size."""
    nu, nv = 312, 322
    s = c1_surface(nu, nv, scale=25.0, offset=(82100, 80300, 9700))
    u, v = 0.4123, 0.7771
    x = scipy_point(s, u, v)
    uu, vv, d = dp.closest_uv(s, x)
    assert d < 1e-9 * 1e4
    target = x + [3, -2, 25]
    new = dp.push_surface(s, uu, vv, target, 5)
    assert np.abs(scipy_point(new, uu, vv) - target).max() < 1e-12 * 1e5
    moved = np.nonzero(np.abs(new.poles - s.poles).max(axis=2))
    assert len(moved[0]) <= 25


def test_poles_compare_after_the_same_knots_are_inserted():
    s = c1_surface(18, 8)
    refined = dp.refine_at(dp.refine_at(s, 0.3, 0.6), 0.31, 0.62)
    same = dp.with_knots_of(s, refined)
    assert same.poles.shape == refined.poles.shape
    assert np.abs(same.poles - refined.poles).max() < 1e-12
    assert dp.with_knots_of(refined, s) is None
    c = wavy()
    longer = dp.curve_with_knot(c, 0.41, 2)
    assert np.abs(dp.with_knots_of(c, longer).poles - longer.poles).max() < 1e-12


def test_refinement_terminates_when_the_spans_at_the_point_cannot_be_split():
    """Issue 11: a huge Range halved the knot span at t below the knot tolerance and spun.
    Refinement stops there; the curve is kept (scipy on both)."""
    c = wavy()
    refined = dp.refine_curve(c, 0.37, 10 ** 6)
    assert len(refined.poles) < 200                   # about 40 halvings of one span
    ts = np.linspace(0, 1, 101)
    assert np.abs(at(refined, ts) - at(c, ts)).max() < 1e-9
    s = dp.bezier_patch([(0, 0, 0), (10, 0, 0), (10, 10, 0), (0, 10, 0)])
    assert min(dp.refine_surface(s, 0.5, 0.5, 10 ** 6).weights.shape) < 200
    assert dp.range_bound(9, 3) == 9 and dp.range_bound(2, 3) == 5


def closed_cubic(n=10):
    """A closed clamped cubic: poles round a circle of radius 10, the last one the first."""
    a = np.linspace(0, 2 * np.pi, n)
    poles = np.column_stack([10 * np.cos(a), 10 * np.sin(a), np.zeros(n)])
    poles[-1] = poles[0]
    knots = np.r_[np.zeros(4), np.linspace(0, 1, n - 2)[1:-1], np.ones(4)]
    return dp.Curve(poles, np.ones(n), knots, 3)


@pytest.mark.parametrize("t", [0.0, 1.0, 0.01])
def test_a_closed_curve_is_pushed_at_its_seam_and_stays_closed(t):
    c = closed_cubic()
    assert dp.is_closed(c, 1e-12)
    target = at(c, t) + np.array([0.0, 1.0, 3.0])
    new = dp.push_curve(c, t, target, c.degree + 2, closed=True)
    assert np.abs(at(new, t) - target).max() < 1e-9
    np.testing.assert_array_equal(new.poles[0], new.poles[-1])   # still closed
    # an open curve refuses its end: only the (held) end pole carries it
    if t == 0.0:
        with pytest.raises(DeformError) as e:
            dp.push_curve(c, t, target, c.degree + 2)
        assert e.value.prop == "Points"


def rational_eval(s, poles, u, v):
    """The test's own evaluation of a rational surface: scipy's design matrices in u and v
    on the homogeneous poles."""
    Bu = BSpline.design_matrix([u], s.uknots, s.udegree).toarray()[0]
    Bv = BSpline.design_matrix([v], s.vknots, s.vdegree).toarray()[0]
    w = np.einsum("i,ij,j->", Bu, s.weights, Bv)
    return np.einsum("i,ijk,j->k", Bu, poles * s.weights[..., None], Bv) / w


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5])
def test_span_basis_equals_scipy_and_the_cubic_path_equals_de_boor(degree):
    """span_basis (the closed-form push's basis) against scipy's BSpline on uniform,
    repeated-knot and random knot vectors, at random parameters, on every knot and at the
    ends; for degree 3 its unrolled path gives the very floats of the general triangle."""
    rng = np.random.default_rng(degree)
    n = 11
    inner = [np.linspace(0, 1, n - degree + 1)[1:-1],
             np.repeat(np.linspace(0, 1, (n - degree - 1) // 2 + 2)[1:-1], 2)[:n - degree - 1],
             np.sort(rng.uniform(0, 1, n - degree - 1))]
    for middle in inner:
        knots = np.r_[np.zeros(degree + 1), middle, np.ones(degree + 1)]
        scipy_basis = BSpline(knots, np.eye(n), degree)
        for t in np.r_[rng.uniform(0, 1, 200), knots]:
            first, values = dp.span_basis(knots.tolist(), degree, float(t))
            expected = scipy_basis(t)
            np.testing.assert_allclose(values, expected[first:first + degree + 1], rtol=0,
                                       atol=1e-14)
            assert np.abs(np.delete(expected, range(first, first + degree + 1))).max() < 1e-14
            if degree == 3:
                k = first + 3
                assert dp._cubic_basis(knots.tolist(), k, float(t)) == \
                    dp._de_boor(knots.tolist(), 3, k, float(t))


@settings(max_examples=80, deadline=None)
@given(st.sampled_from(["canopy", "c1", "rational", "quadratic", "mixed"]), st.floats(0, 1),
       st.floats(0, 1), st.integers(0, 6), st.tuples(*[st.floats(-5, 5)] * 3),
       st.integers(1, 8))
def test_unconstrained_surface_push_equals_the_general_solve_and_lands(kind, a, b, knot,
                                                                        move, size):
    """The closed-form push (no constraints) moves the same poles by the same amounts as the
    general least-norm solve (forced by holding a pole far from the point), and the point
    lands on the target by scipy's evaluation; parameters on knots are drawn too. Bicubic
    surfaces take the closed form's degree-3 basis, the quadratic and the mixed (degree 2
    in u, 4 in v, rational) ones its general one."""
    if kind == "canopy":
        s = canopy(12, 9)
    elif kind == "c1":
        s = c1_surface(14, 10)
    elif kind == "quadratic":
        s = canopy(12, 9, degree=2)
    else:
        s = canopy(12, 9)._replace(weights=np.random.default_rng(knot).uniform(0.5, 2, (12, 9)))
        if kind == "mixed":
            s = s._replace(uknots=clamped(12, 2), udegree=2, vknots=clamped(9, 4), vdegree=4)
    u, v = (a, b) if knot == 0 else (s.uknots[3 + knot], s.vknots[2 + knot])
    target = rational_eval(s, s.poles, u, v) + np.array(move)
    far = 0 if u > 0.5 else s.weights.size - 1         # a border pole: never movable anyway
    try:
        general = dp.push_surface(s, u, v, target, size, held=[far])
    except DeformError as e:
        with pytest.raises(DeformError, match="border of the face"):
            dp.push_surface(s, u, v, target, size)
        assert "border of the face" in str(e)
        return
    new = dp.push_surface(s, u, v, target, size)
    np.testing.assert_allclose(new.poles, general.poles, rtol=0, atol=1e-12 * 100)
    assert np.abs(rational_eval(s, new.poles, u, v) - target).max() < 1e-11
    assert np.count_nonzero(np.abs(new.poles - s.poles).max(axis=2)) <= size * size
