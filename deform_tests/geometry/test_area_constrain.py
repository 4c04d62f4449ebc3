"""Exact area, its derivatives and the area-constrained solve (Xu, Joneja & Tang 2009).

Oracles written here: the area of a quarter cylinder in closed form; the canopy's area by
the test's own evaluation (scipy BSpline on the poles, 40-point Gauss-Legendre per span,
and for the hood with a degenerate corner a tensor grid graded geometrically toward that
corner, 60 levels of 30 nodes); central finite differences for the gradient and the
Hessian; the paper's cases checked by that area, by which poles moved, and by the angle
between displacement and gradient."""
import numpy as np
import pytest
from scipy.interpolate import BSpline

from freecad_deform.geometry.nurbs import area_constrain as ac
from freecad_deform.geometry.nurbs.bspline_area import quadrature
from freecad_deform.geometry.errors import DeformError

from ..oracles.nurbs import canopy, cylinder_patch, hood, own_area, own_cell_areas
from ..oracles.nurbs import converged_area


def idx(s, i, j):
    """Flat index of 1-based pole (i, j), as FreeCAD's getPole(i, j)."""
    return (i - 1) * s.poles.shape[1] + (j - 1)


def test_area_is_exact_on_a_rational_cylinder_and_the_canopy():
    cyl = cylinder_patch(5.0, 20.0)
    assert quadrature(cyl).area(cyl.poles) == pytest.approx(np.pi * 5 * 20 / 2, rel=1e-13)
    s = canopy()
    assert quadrature(s).area(s.poles) == pytest.approx(own_area(s), rel=1e-13)


@pytest.mark.parametrize("surface", [canopy(), cylinder_patch()], ids=["canopy", "rational"])
def test_gradient_and_hessian_match_finite_differences(surface):
    q = quadrature(surface)
    P = surface.poles
    movable = np.array([1, 4]) if surface.poles.shape[1] == 2 else np.array([14, 15, 20])
    _, g = q.gradient(P, movable)
    H = q.hessian(P, movable)
    exact = q.hessian(P, movable, exact=True)
    h = 1e-5 * np.abs(P).max()
    fd_g, fd_H = [], []
    for m in movable:
        for c in range(3):
            up, down = P.reshape(-1, 3).copy(), P.reshape(-1, 3).copy()
            up[m, c] += h
            down[m, c] -= h
            fd_g.append((q.area(up) - q.area(down)) / (2 * h))
            fd_H.append((q.gradient(up, movable)[1] - q.gradient(down, movable)[1]).ravel()
                        / (2 * h))
    assert np.abs(g.ravel() - fd_g).max() < 1e-6 * np.abs(g).max()
    # the Hessian on the area's own nodes; the one that steers Newton uses a rule with
    # fewer nodes: within 1e-4
    assert np.abs(exact - np.array(fd_H)).max() < 1e-7 * np.abs(exact).max()
    assert np.abs(H - np.array(fd_H)).max() < 1e-4 * np.abs(H).max()
    assert np.abs(H - H.T).max() < 1e-12 * np.abs(H).max()


@pytest.mark.parametrize("surface, pairs", [
    (canopy(7, 6), [(2, 2), (2, 3), (3, 3), (5, 4), (6, 5), (4, 2)]),
    (hood(10, 6), [(3, 2), (3, 3), (9, 2), (9, 5), (6, 4)])], ids=["canopy", "hood"])
def test_rectangle_wise_hessian_matches_finite_differences_of_the_gradient(surface, pairs):
    """The Hessian assembled rectangle by rectangle from the tensor rules (non-rational),
    on the area's own nodes, against central differences of the gradient: poles whose
    cells also hold poles that stay, and the hood's rectangles graded toward its
    degenerate corner and collapsed edge (many rectangles per cell, several rules)."""
    q = quadrature(surface)
    assert q.nodes.tensor and q.light.tensor
    P = surface.poles
    movable = np.array([idx(surface, i, j) for i, j in pairs])
    H = q.hessian(P, movable, exact=True)
    h = 1e-6 * np.abs(P).max()
    fd = []
    for m in movable:
        for c in range(3):
            up, down = P.reshape(-1, 3).copy(), P.reshape(-1, 3).copy()
            up[m, c] += h
            down[m, c] -= h
            fd.append((q.gradient(up, movable)[1] - q.gradient(down, movable)[1]).ravel()
                      / (2 * h))
    assert np.abs(H - np.array(fd)).max() < 1e-7 * np.abs(H).max()
    assert np.abs(H - H.T).max() < 1e-13 * np.abs(H).max()
    light = q.hessian(P, movable)
    assert np.abs(light - H).max() < 1e-4 * np.abs(H).max()


def solve(s, movable, ratio, dof, method="Lagrange-Newton"):
    a0 = quadrature(s).area(s.poles)
    sol = ac.constrain_surface_area(s, movable, ratio * a0, dof, method)
    return sol, a0, (sol.poles - s.poles).reshape(-1, 3)


def test_all_interior_poles_along_their_normals_plus_five_percent():
    s = canopy()
    interior = [idx(s, i, j) for i in range(2, 6) for j in range(2, 6)]
    sol, a0, d = solve(s, interior, 1.05, "Normal")
    assert own_area(s, sol.poles) == pytest.approx(1.05 * a0, rel=1e-12)
    moved = np.nonzero(np.abs(d).max(axis=1) > 0)[0]
    assert set(moved) == set(interior)
    for m in interior:                       # each along its own control-net normal
        n = ac.net_normal(s.poles, m)
        assert np.linalg.norm(np.cross(d[m], n)) < 1e-12 * (1 + np.linalg.norm(d[m]))


def test_one_pole_z_only_plus_two_and_a_half_percent():
    s = canopy()
    m = idx(s, 2, 3)
    sol, a0, d = solve(s, [m], 1.025, "Z")
    assert own_area(s, sol.poles) == pytest.approx(1.025 * a0, rel=1e-12)
    assert np.count_nonzero(d) == 1 and d[m, 2] != 0


def test_four_poles_z_only_minus_two_and_a_half_percent():
    s = canopy()
    four = [idx(s, i, j) for i in (3, 4) for j in (3, 4)]
    sol, a0, d = solve(s, four, 0.975, "Z")
    assert own_area(s, sol.poles) == pytest.approx(0.975 * a0, rel=1e-12)
    assert np.all(d[:, :2] == 0) and set(np.nonzero(d[:, 2])[0]) == set(four)


@pytest.mark.parametrize("method", ["Lagrange-Newton", "Penalty"])
def test_six_free_poles_move_along_the_area_gradient(method):
    s = canopy()
    six = [idx(s, i, j) for i, j in ((2, 2), (2, 3), (3, 2), (3, 3), (4, 4), (4, 5))]
    sol, a0, d = solve(s, six, 1.05, "Free", method)
    q = quadrature(s)
    _, g = q.gradient(sol.poles, np.array(six))
    cos = abs(d[six].ravel() @ g.ravel()) / np.linalg.norm(d[six]) / np.linalg.norm(g)
    assert cos > 0.999999
    rel = 1e-12 if method == "Lagrange-Newton" else 1e-6   # the penalty misses by O(1/N)
    assert own_area(s, sol.poles) == pytest.approx(1.05 * a0, rel=rel)
    assert sol.iterations < 20


def test_rational_surface_reaches_its_target():
    cyl = cylinder_patch()
    """Checked by the test's converged quadrature: the rule kept for the original is
    1.5e-13 off on the result unless the solve goes on with more nodes."""
    sol, a0, d = solve(cyl, [1], 1.1, "Free")      # the middle pole of the bottom arc
    area, change = converged_area(sol.poles, cyl.weights, cyl.uknots, cyl.vknots, 2, 1,
                                  (0, 1), (0, 1))
    assert change < 1e-13
    assert area == pytest.approx(1.1 * np.pi * 5 * 20 / 2, rel=1e-13)


def test_half_the_area_with_one_pole_is_refused_with_the_reachable_side():
    s = canopy()
    with pytest.raises(DeformError, match=r"smallest area they give is [0-9.]+") as e:
        solve(s, [idx(s, 3, 3)], 0.5, "Z")
    assert e.value.prop == "TargetArea"
    smallest = float(str(e.value).split("give is ")[1].split(";")[0])
    assert 0.5 * quadrature(s).area(s.poles) < smallest < quadrature(s).area(s.poles)


def test_no_change_is_a_fixed_point():
    s = canopy()
    sol, a0, d = solve(s, [idx(s, 3, 3)], 1.0, "Normal")
    assert np.all(d == 0) and sol.area == a0


def interior(s):
    nu, nv = s.weights.shape
    return [i * nv + j for i in range(1, nu - 1) for j in range(1, nv - 1)]


@pytest.mark.parametrize("nv", [8, 14])
def test_area_converges_at_a_degenerate_corner(nv):
    """|S_u x S_v| vanishes at the corner (1, 0) and along the collapsed edge u = 0:
    uniform Gauss-Legendre (48 nodes per span) misses by 1e-13 there; the graded cells
    meet the graded reference, and the error estimate covers the difference."""
    s = hood(18, nv)
    q = quadrature(s)
    ref = own_area(s, nodes=30, toward=(1.0, 0.0))
    assert abs(q.area(s.poles) - ref) <= 1e-14 * ref + q.error
    assert q.error < 1e-13 * ref
    deepest = q.rects.take(q.rects.depth == q.rects.depth.max())
    assert q.rects.depth.max() > 10 and deepest.u1.max() == 1.0 and deepest.v0.min() == 0.0


@pytest.mark.parametrize("nv", [8, 14])
def test_collapsed_rows_stay_one_point_and_the_area_is_exact(nv):
    """Every interior pole along its normal (the default), +3 %: the second pole row
    coincides with the degenerate edge, so it stays there (held), the rest move."""
    s = hood(18, nv)
    sol, a0, d = solve(s, interior(s), 1.03, "Normal")
    result = s._replace(poles=sol.poles)
    assert own_area(result, nodes=30, toward=(1.0, 0.0)) == pytest.approx(1.03 * a0, rel=1e-12)
    assert sol.held == tuple((2, j) for j in range(2, nv))
    assert np.all(sol.poles[:2] == s.poles[0, 0]) and sol.fallbacks == ()
    assert sol.kkt < 1e-9 and sol.iterations < 15 and 0 < sol.error < 1e-12 * a0


def test_coincident_interior_poles_move_as_one():
    s = hood(18, 8)
    P = s.poles.copy()
    P[8, 3] = P[8, 4] = (P[8, 3] + P[8, 4]) / 2          # two interior poles made one point
    s = s._replace(poles=P)
    sol, a0, d = solve(s, [idx(s, 9, 4), idx(s, 9, 5), idx(s, 5, 5)], 1.01, "Free")
    assert np.all(sol.poles[8, 3] == sol.poles[8, 4]) and np.any(sol.poles[8, 3] != P[8, 3])
    assert own_area(s._replace(poles=sol.poles), nodes=30, toward=(1.0, 0.0)) == \
        pytest.approx(1.01 * a0, rel=1e-12)


def test_a_pole_without_a_net_normal_moves_along_the_surface_normal():
    """The four neighbours of pole (3, 3) on one line through it: no net triangle has a
    normal, so the pole moves along S_u x S_v at its Greville point."""
    s = canopy()
    P = s.poles.copy()
    e = np.array([12.0, 7.0, 1.0])
    for (i, j), f in (((1, 2), -1), ((3, 2), 1), ((2, 1), -0.5), ((2, 3), 0.5)):
        P[i, j] = P[2, 2] + f * e
    s = s._replace(poles=P)
    with_normal = [idx(s, 3, 3), idx(s, 4, 4)]
    sol, a0, d = solve(s, with_normal, 1.02, "Normal")
    assert sol.fallbacks == ((3, 3),)
    gu = np.mean(s.uknots[3:6])
    gv = np.mean(s.vknots[3:6])
    su = BSpline(s.uknots, np.moveaxis(P, 0, 0), 3)
    Su = BSpline(s.vknots, su.derivative()(gu), 3)(gv)
    Sv = BSpline(s.vknots, su(gu), 3).derivative()(gv)
    n = np.cross(Su, Sv)
    assert np.linalg.norm(np.cross(d[idx(s, 3, 3)], n)) < 1e-9 * np.linalg.norm(n) * \
        np.linalg.norm(d[idx(s, 3, 3)])
    assert np.linalg.norm(d[idx(s, 3, 3)]) > 0
    assert own_area(s, sol.poles) == pytest.approx(1.02 * a0, rel=1e-12)


def test_too_many_variables_are_refused_naming_poles_where_the_large_solver_cannot():
    s = canopy(40)
    with pytest.raises(DeformError, match="variables") as e:
        ac.constrain_surface_area(s, interior(s), 1e4, "Free", "Penalty")
    assert e.value.prop == "Poles"
    rational = s._replace(weights=np.where(np.arange(40)[:, None] % 2, 0.9, 1.0) * np.ones(40))
    with pytest.raises(DeformError, match="non-rational") as e:
        ac.constrain_surface_area(rational, interior(s), 1e4, "Free")
    assert e.value.prop == "Poles"


@pytest.mark.parametrize("dof", ["Normal", "Free"])
def test_the_large_solver_reaches_the_target_with_the_least_change(monkeypatch, dof):
    """Beyond MAX_VARIABLES (lowered here so the test stays small) the solve runs on the
    tensor grid with conjugate gradients: the same exact area and the same optimum
    (displacement along the area gradient) as the dense solver."""
    monkeypatch.setattr(ac, "MAX_VARIABLES", 10)
    s = canopy(12)
    a0 = own_area(s)
    sol = ac.constrain_surface_area(s, interior(s), 1.03 * a0, dof)
    assert own_area(s, sol.poles) == pytest.approx(1.03 * a0, rel=1e-12)
    d = (sol.poles - s.poles).reshape(-1, 3)[interior(s)]
    _, g = quadrature(s).gradient(sol.poles, np.array(interior(s)))
    if dof == "Normal":      # along each pole's net normal: compare the projections on it
        n = np.array([ac.net_normal(s.poles, m) for m in interior(s)])
        d, g = (np.sum(x * n, axis=1) for x in (d, g))
    cos = abs(d.ravel() @ g.ravel()) / np.linalg.norm(d) / np.linalg.norm(g)
    assert cos > 1 - 1e-12


def test_a_large_face_s_fixed_cells_error_does_not_refuse_a_local_change(monkeypatch):
    """On a face of more than LARGE cells the cells no listed pole touches are summed once
    by a fixed pair of rules; their error (here made 1e-6 of the area by coarse rules and
    a loose FIXED_RTOL)
    stays the same before and after, so it is no sign of a fold: the solve is not refused,
    the change of area (the test's own quadrature, before and after) is the one asked,
    and AreaError still reports the fixed cells' error."""
    from freecad_deform.geometry.nurbs import bspline_area
    monkeypatch.setattr(bspline_area, "LARGE", 50)
    monkeypatch.setattr(bspline_area, "FIXED_RULES", (2, 3))
    monkeypatch.setattr(bspline_area, "FIXED_RTOL", 1e-3)   # no cell integrated further
    s = canopy(14, size=(100.0, 100.0))
    movable = [idx(s, i, j) for i in (7, 8) for j in (7, 8)]
    q = ac.area_quadrature(s, movable)
    assert q.error > 1e-7 * q.area(s.poles)
    change = 0.01 * own_area(s)
    sol = ac.constrain_surface_area(s, movable, q.area(s.poles) + change, "Normal", q=q)
    assert own_area(s, sol.poles) - own_area(s) == pytest.approx(change, rel=1e-10)
    assert sol.error >= q.error - q.active_error


def test_a_large_face_s_cells_sum_to_its_area_within_fixed_rtol():
    """fixed_cells (every cell of a large face: cheap rules, then the cells where they
    differ most adaptively) sums to the area by the test's own rule (scipy's basis, 60
    and 80 Gauss nodes per span, agreeing to 1e-14) within FIXED_RTOL, and its error
    estimate bounds the actual error, on a rough face (random heights) where the test's
    own 8-node rule is off by 3e-6 and a cell's 6- and 8-node areas agree to 1e-8 though
    both are 9e-6 off (a pair of rules alone passed it). The cells' rule itself
    (tensor_cell_areas, blocks of spans) at 40 nodes equals the test's 40-node area."""
    from freecad_deform.geometry.nurbs import bspline_area
    s = canopy(30, size=(100.0, 100.0))
    P = s.poles.copy()
    P[..., 2] = 40 * np.random.default_rng(0).random((30, 30))
    s = s._replace(poles=P)
    exact = own_area(s, nodes=80)
    assert own_area(s, nodes=60) == pytest.approx(exact, rel=1e-14)
    assert abs(own_area(s, nodes=8) - exact) > 1e-6 * exact
    bspline_area._FIXED_CELLS.clear()
    value, error = bspline_area.fixed_cells(s)
    assert value.shape == (27 * 27,)
    assert abs(value.sum() - exact) <= bspline_area.FIXED_RTOL * exact
    assert abs(value.sum() - exact) <= error.sum() + 1e-13 * exact
    assert error.sum() <= bspline_area.FIXED_RTOL * exact
    assert bspline_area.tensor_cell_areas(s, 40).sum() == pytest.approx(
        own_area(s, nodes=40), rel=1e-13)


def test_a_non_square_face_s_fixed_cells_are_each_its_own_cell_s_area():
    """fixed_cells per cell, in `cells` order (u-major), on 31 x 19 poles with uneven knots
    along v and degrees 3 x 2, rough heights: each cell within FIXED_RTOL of the face's area
    of the test's own 60-node integral of that cell (a transposed or mis-ordered grid is
    off by whole cells), and the errors it reports bound the actual ones in sum."""
    from freecad_deform.geometry.nurbs import bspline_area
    from freecad_deform.geometry.nurbs.bspline_area import Surface
    s = canopy(31, 19, size=(120.0, 50.0))
    inner = np.cumsum(np.linspace(1, 3, 17))
    vknots = np.r_[0.0, 0.0, 0.0, inner[:-1] / inner[-1], 1.0, 1.0, 1.0]
    P = s.poles.copy()
    P[..., 2] += 10 * np.random.default_rng(1).random(P.shape[:2])
    s = Surface(P, s.weights, s.uknots, vknots, 3, 2)
    own = own_cell_areas(s)
    assert own.shape == (28, 17)
    bspline_area._FIXED_CELLS.clear()
    value, error = bspline_area.fixed_cells(s)
    total = own.sum()
    assert np.max(np.abs(value - own.ravel())) <= bspline_area.FIXED_RTOL * total
    assert np.abs(value - own.ravel()).sum() <= error.sum() + 1e-13 * total
    assert own.sum() == pytest.approx(own_area(s, nodes=60), rel=1e-14)
