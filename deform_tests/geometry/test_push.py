"""DirectPush's pushes in order (geometry.nurbs.push): basis rows, re-landing a point on
its parameter, replays, the moved region, the blend's border rows and re-landing after a
blend, drawing points; AreaConstrain's Poles entries.

Oracles written here: scipy's BSpline evaluation of the poles (rational: of the homogeneous
poles), never the kernel's own rows; pole indices counted by hand."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from freecad_deform.geometry.errors import DeformError
from freecad_deform.geometry.nurbs import area_constrain as ac
from freecad_deform.geometry.nurbs import direct_push as dp
from freecad_deform.geometry.nurbs import push


def wavy(n=9, degree=3, weights=None):
    x = np.linspace(0, 80, n)
    poles = np.column_stack([x, 10 * np.sin(x / 12), 3 * np.cos(x / 20)])
    knots = np.r_[np.zeros(degree + 1), np.linspace(0, 1, n - degree + 1)[1:-1],
                  np.ones(degree + 1)]
    return dp.Curve(poles, np.ones(n) if weights is None else np.asarray(weights, float),
                    knots, degree)


def hill(nu=7, nv=6, weights=None):
    """A bicubic surface over [0, 60] x [0, 50] (a height field: one point per (x, y))."""
    def knots(n):
        return np.r_[np.zeros(4), np.linspace(0, 1, n - 2)[1:-1], np.ones(4)]
    i, j = np.meshgrid(np.linspace(0, 60, nu), np.linspace(0, 50, nv), indexing="ij")
    P = np.stack([i, j, 8 * np.sin(i / 15) * np.cos(j / 18)], axis=2)
    w = np.ones((nu, nv)) if weights is None else np.asarray(weights, float)
    return dp.Surface(P, w, knots(nu), knots(nv), 3, 3)


def curve_point(c, t):
    """scipy's evaluation of the (rational) curve."""
    h = BSpline(c.knots, np.column_stack([c.poles * c.weights[:, None], c.weights]), c.degree)(t)
    return h[..., :3] / h[..., 3:]


def surface_point(s, u, v):
    """scipy's evaluation of the (rational) surface: along u, then along v."""
    H = np.concatenate([s.poles * s.weights[..., None], s.weights[..., None]], axis=2)
    h = BSpline(s.vknots, BSpline(s.uknots, H, s.udegree)(u), s.vdegree)(v)
    return h[..., :3] / h[..., 3:]


weights_9 = st.lists(st.floats(0.3, 3.0), min_size=9, max_size=9)


# --- basis rows and points --------------------------------------------------------------------

@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1.0), weights_9)
def test_a_curve_row_sums_to_one_and_gives_the_curve_point(t, w):
    c = wavy(weights=w)
    row = dp.curve_row(c, t)
    assert abs(row.sum() - 1) < 1e-12
    assert np.all(row >= -1e-15)
    np.testing.assert_allclose(row @ c.poles, curve_point(c, t), atol=1e-10)
    np.testing.assert_allclose(push.point_at(c, t), curve_point(c, t), atol=1e-10)


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0),
       st.lists(st.floats(0.3, 3.0), min_size=42, max_size=42))
def test_a_surface_row_sums_to_one_and_gives_the_surface_point(u, v, w):
    s = hill(weights=np.reshape(w, (7, 6)))
    row = dp.surface_row(s, u, v)
    assert abs(row.sum() - 1) < 1e-12
    np.testing.assert_allclose(push.point_at(s, (u, v)), surface_point(s, u, v), atol=1e-10)


def test_drawing_points_are_the_curve_and_the_surface():
    c = wavy(weights=np.linspace(0.5, 2.0, 9))
    pts = push.sample_points(c, 57)
    np.testing.assert_allclose(pts, curve_point(c, np.linspace(0, 1, 57)), atol=1e-10)
    s = hill(weights=1 + 0.5 * np.random.default_rng(1).random((7, 6)))
    grid = push.sample_points(s)
    assert grid.shape == (30, 30, 3)   # 3 per pole, at least 30
    us, vs = np.linspace(0, 1, 30), np.linspace(0, 1, 30)
    for a in (0, 11, 29):
        for b in (0, 17, 29):
            np.testing.assert_allclose(grid[a, b], surface_point(s, us[a], vs[b]), atol=1e-10)


# --- re-landing: the parameter of a point on the element --------------------------------------

@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 1.0), weights_9)
def test_the_parameter_of_a_point_on_a_curve_is_found(t, w):
    c = wavy(weights=w)
    x = curve_point(c, t)
    found, distance = dp.closest_parameter(c, x)
    assert distance < 1e-9
    assert np.linalg.norm(curve_point(c, found) - x) < 1e-9
    assert abs(found - t) < 1e-7     # the curve does not come back near itself


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_the_parameters_of_a_point_on_a_surface_are_found(u, v):
    s = hill()
    x = surface_point(s, u, v)
    fu, fv, distance = dp.closest_uv(s, x)
    assert distance < 1e-9
    assert np.linalg.norm(surface_point(s, fu, fv) - x) < 1e-9
    assert abs(fu - u) < 1e-7 and abs(fv - v) < 1e-7   # a height field: one point per (x, y)


def test_a_point_off_the_element_names_the_property():
    c = wavy()
    with pytest.raises(DeformError) as e:
        push.curve_state(c, fixed=[curve_point(c, 0.5) + [0, 0, 1.0]], tol=1e-6, name="Edge1")
    assert e.value.prop == "Fixed" and "Fixed[0]" in str(e.value) and "Edge1" in str(e.value)


# --- replays ----------------------------------------------------------------------------------

pushes = st.lists(st.tuples(st.floats(0.1, 0.9), st.tuples(*[st.floats(-8, 8)] * 3)),
                  min_size=1, max_size=4)


@settings(max_examples=30, deadline=None)
@given(pushes)
def test_each_push_of_a_curve_replay_lands_on_its_target(moves):
    state = push.curve_state(wavy(), range=2, tol=1e-6)
    params = [t for t, _ in moves]
    targets, current = [], state.start
    for t, d in moves:     # each target: the point as the pushes before left it, moved
        targets.append(curve_point(current, t) + np.array(d))
        current = push.replay(state, targets, lambda i, _: params[i]).current
    for k in range(len(moves)):
        after = push.replay(state, targets[:k + 1], lambda i, _: params[i]).current
        assert np.linalg.norm(curve_point(after, params[k]) - targets[k]) < 1e-8
    final = push.replay(state, targets, lambda i, _: params[i])
    assert final.params == params and len(final.points) == len(moves)
    np.testing.assert_array_equal(final.current.poles[[0, -1]], state.start.poles[[0, -1]])


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(st.integers(15, 85), st.integers(15, 85), st.integers(-60, 60)).map(
    lambda x: (x[0] / 100, x[1] / 100, x[2] / 10)), min_size=1, max_size=3))   # (u, v, height)
def test_each_push_of_a_surface_replay_lands_and_the_border_stays(moves):
    state = push.surface_state(hill(), tol=1e-6)
    params = [(u, v) for u, v, _ in moves]
    targets, current = [], state.start
    for (u, v), (_, _, h) in zip(params, moves):
        targets.append(surface_point(current, u, v) + [0, 0, h])
        current = push.replay(state, targets, lambda i, _: params[i]).current
        assert np.linalg.norm(surface_point(current, u, v) - targets[-1]) < 1e-8
    P0, P = hill().poles, current.poles
    if P.shape == P0.shape:
        for border in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
            np.testing.assert_array_equal(P[border], P0[border])


def test_replay_locates_each_push_on_the_element_as_the_pushes_before_left_it():
    state = push.curve_state(wavy(), tol=1e-6)
    seen = []

    def grab_at(i, current):
        seen.append(current)
        return 0.4
    target = curve_point(state.start, 0.4) + [0, 5, 0]
    push.replay(state, [target, target + [0, 1, 0]], grab_at)
    assert seen[0] is state.start
    assert np.linalg.norm(curve_point(seen[1], 0.4) - target) < 1e-9


def test_a_push_against_a_fixed_point_names_it():
    c = wavy()
    state = push.curve_state(c, fixed=[curve_point(c, 0.5)], tol=1e-6)
    with pytest.raises(DeformError) as e:
        push.replay(state, [curve_point(c, 0.5) + [0, 3, 0]], lambda i, _: state.fixed[0])
    assert e.value.prop == "Fixed" and str(e.value).startswith("Points[0]: ")


def test_range_angles_and_pairs_name_their_property():
    for call, prop in ((lambda: push.range_size(-1, 3, 5), "Range"),
                       (lambda: push.check_angle(190, 1, 1), "Angles"),
                       (lambda: push.check_angle(90, 0, 1), "Angles"),
                       (lambda: push.pairs([(0, 0, 0)], "Straight"), "Straight")):
        with pytest.raises(DeformError) as e:
            call()
        assert e.value.prop == prop
    assert push.range_size(0, 3, 20) == 5          # Range 0: degree + 1, so 5 poles
    assert push.range_size(50, 3, 20) == push.range_size(99, 3, 20)   # capped by the element


# --- what the result reports ------------------------------------------------------------------

def test_a_refinement_is_no_pole_move_and_a_push_is_measured():
    c = wavy()
    refined = dp.refine_curve(c, 0.5, len(c.poles) + 3)
    assert len(refined.poles) > len(c.poles)
    assert push.max_pole_move(c, refined) < 1e-12
    moved = refined._replace(poles=refined.poles + np.where(
        np.arange(len(refined.poles))[:, None] == 4, [0.0, 0.0, 2.5], 0.0))
    assert abs(push.max_pole_move(c, moved) - 2.5) < 1e-12


def test_the_moved_region_holds_every_change_of_the_surface():
    s = hill(11, 10)
    after = dp.push_surface(s, 0.3, 0.6, surface_point(s, 0.3, 0.6) + [0, 0, 4], 3)
    u0, u1, v0, v1 = push.moved_region(s, after)
    assert 0 <= u0 < 0.3 < u1 <= 1 and 0 <= v0 < 0.6 < v1 <= 1
    g = np.linspace(0, 1, 41)
    U, V = np.meshgrid(g, g, indexing="ij")
    diff = np.array([[np.linalg.norm(surface_point(after, u, v) - surface_point(s, u, v))
                      for v in g] for u in g])
    outside = (U < u0) | (U > u1) | (V < v0) | (V > v1)
    assert diff[outside].max() < 1e-12 and diff.max() > 1
    assert push.moved_region(s, s) is None


# --- Pratt's blend ----------------------------------------------------------------------------

def test_border_rows_follow_the_edge_and_the_row_inside_is_next_to_it():
    corners = [np.array(p, float) for p in ((0, 0, 0), (30, 0, 0), (30, 20, 0), (0, 20, 0))]
    patch = dp.bezier_patch(corners)
    for ends in ((corners[1], corners[2]), (corners[2], corners[1]), (corners[0], corners[3])):
        row, inner = push.border_rows(patch, ends, 1e-9, "Edge1")
        pts, nxt = patch.poles[row], patch.poles[inner]
        np.testing.assert_allclose(pts[[0, -1]], ends, atol=1e-12)
        assert len(pts) == 4
        step = np.linalg.norm(nxt - pts, axis=1)      # one pole in from the border, all along
        np.testing.assert_allclose(step, step[0], atol=1e-12)
        assert step[0] > 0 and np.all(np.abs((nxt - pts) @ (ends[1] - ends[0])) < 1e-9)
    with pytest.raises(DeformError) as e:
        push.border_rows(patch, (corners[0], corners[2]), 1e-9, "Edge7")
    assert e.value.prop == "Blend" and "Edge7" in str(e.value)


def test_reland_puts_the_points_back_and_keeps_the_border_and_held_poles():
    s = hill(9, 8)
    s = s._replace(poles=s.poles.copy())
    s.poles[0] += [0, 0, 3]                     # a blend moved a border row
    landed = [(0.35, 0.4, np.array([20.0, 21.0, 9.0])), (0.7, 0.55, np.array([43.0, 27.0, -4.0]))]
    nv = s.weights.shape[1]
    held = {1 * nv + 3, 2 * nv + 3}
    new = push.reland(s, landed, held)
    for u, v, t in landed:
        assert np.linalg.norm(surface_point(new, u, v) - t) < 1e-9
    for border in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        np.testing.assert_array_equal(new.poles[border], s.poles[border])
    for k in held:
        np.testing.assert_array_equal(new.poles[divmod(k, nv)], s.poles[divmod(k, nv)])


def test_held_boundary_poles_keep_a_trimmed_boundary_under_a_push():
    s = hill(12, 12)
    boundary = np.column_stack([np.linspace(0.1, 0.9, 25), np.full(25, 0.3)])   # a pcurve
    state = push.surface_state(s, tol=1e-6)._replace(boundary=boundary)
    grab = push.Grab(state, state.start, (0.5, 0.6))
    before = [surface_point(grab.arrays, u, v) for u, v in boundary]
    new = grab.pushed(grab.point + [0, 0, 5])
    assert np.linalg.norm(surface_point(new, 0.5, 0.6) - grab.point - [0, 0, 5]) < 1e-8
    after = [surface_point(new, u, v) for u, v in boundary]
    assert np.abs(np.array(after) - before).max() < 1e-9
    assert set(grab.held) >= dp.influencing(grab.arrays, boundary)


# --- AreaConstrain's Poles --------------------------------------------------------------------

@settings(max_examples=30, deadline=None)
@given(st.integers(2, 9), st.integers(2, 9))
def test_default_poles_are_the_interior_ones_or_all_but_the_corners(nu, nv):
    if nu == nv == 2:
        return                    # corners only: refused (test_poles_entries_...)
    flat = ac.parse_poles([], (nu, nv))
    i, j = np.divmod(flat, nv)
    if nu > 2 and nv > 2:
        assert len(flat) == (nu - 2) * (nv - 2)
        assert np.all((i > 0) & (i < nu - 1) & (j > 0) & (j < nv - 1))
        assert not ac.on_boundary(flat, (nu, nv))
    else:
        assert len(flat) == nu * nv - 4 and ac.on_boundary(flat, (nu, nv))
    assert len(set(flat)) == len(flat)


def test_poles_entries_are_one_based_and_bad_ones_name_poles():
    assert ac.parse_poles(["2,3", "(4, 1)", "2,3"], (5, 6)) == [1 * 6 + 2, 3 * 6 + 0]
    assert ac.on_boundary([3 * 6 + 0], (5, 6)) and not ac.on_boundary([1 * 6 + 2], (5, 6))
    for entries, shape in ((["x"], (5, 6)), (["6,1"], (5, 6)), (["0,2"], (5, 6)), ([], (2, 2))):
        with pytest.raises(DeformError) as e:
            ac.parse_poles(entries, shape)
        assert e.value.prop == "Poles"


# --- knot vectors (shapes.bspline builds Part curves and Coons sides from these) ------------

@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 1), st.integers(1, 4)), min_size=1, max_size=8))
def test_knots_and_mults_give_back_the_full_vector(entries):
    distinct = sorted({round(k, 6) for k, _ in entries})
    mults = [dict((round(k, 6), m) for k, m in entries)[k] for k in distinct]
    knots, found = dp.knots_and_mults(np.repeat(distinct, mults))
    assert knots == distinct and found == mults


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 1.0), weights_9)
def test_a_reversed_curve_runs_backwards(t, w):
    c = wavy(weights=w)
    np.testing.assert_allclose(curve_point(dp.reversed_curve(c), t), curve_point(c, 1 - t),
                               atol=1e-10)


def test_compatible_curves_share_knots_and_keep_their_shape():
    a = wavy(9)
    b = wavy(7, weights=np.linspace(1, 2, 7))
    b = b._replace(poles=b.poles + [0, 30, 0])
    x, y = dp.compatible(a, b)
    np.testing.assert_allclose(x.knots, y.knots, atol=1e-12)
    ts = np.linspace(0, 1, 53)
    np.testing.assert_allclose(curve_point(x, ts), curve_point(a, ts), atol=1e-10)
    np.testing.assert_allclose(curve_point(y, ts), curve_point(b, ts), atol=1e-10)
