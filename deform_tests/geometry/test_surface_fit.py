"""B-spline fits at given parameters: exactness, affine invariance, the tolerance met at
points the fit never saw (checked here on a dense random sample), closed seams and poles."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from freecad_deform.geometry.nurbs import surface_fit as sf


def grid_fn(f):
    def fn(U, V):
        u, v = np.meshgrid(U, V, indexing="ij")
        return f(u, v)
    return fn


def evaluate(fit, u, v):
    """The fitted surface at scattered points, with scipy's own B-spline evaluation."""
    out = []
    for ui, vi in zip(u, v):
        cu = BSpline(fit.uknots, np.eye(fit.poles.shape[0]), fit.degree)(ui)
        cv = BSpline(fit.vknots, np.eye(fit.poles.shape[1]), fit.degree)(vi)
        out.append(np.einsum("a,abd,b->d", cu, fit.poles, cv))
    return np.array(out)


@settings(max_examples=25)
@given(st.lists(st.floats(-2, 2), min_size=6, max_size=6))
def test_cubic_polynomials_are_reproduced(c):
    def f(u, v):
        return np.stack([c[0] * u ** 3 + c[1] * v, c[2] * u * v ** 2 + c[3], c[4] * v ** 3 + c[5] * u],
                        -1)
    fit = sf.fit_surface(grid_fn(f), (0.0, 2.0), (-1.0, 1.0), 1e-9)
    assert fit.deviation < 1e-10
    rng = np.random.default_rng(0)
    u, v = rng.uniform(0, 2, 50), rng.uniform(-1, 1, 50)
    assert np.allclose(evaluate(fit, u, v), f(u, v), atol=1e-9)


@settings(max_examples=15)
@given(st.floats(0.1, 3), st.floats(-2, 2), st.floats(-2, 2))
def test_fit_commutes_with_affine_maps(scale, a, b):
    A = np.array([[scale, a, 0.0], [0.0, 1.0, b], [0.3, 0.0, 1.0]])
    shift = np.array([1.0, -2.0, 0.5])

    def f(u, v):
        return np.stack([np.cos(u) * (2 + v), np.sin(u) * (2 + v), v * u], -1)

    fit = sf.fit_surface(grid_fn(f), (0, 3), (0, 1), 1e-6, spans=(8, 8), max_spans=8)
    mapped = sf.fit_surface(grid_fn(lambda u, v: f(u, v) @ A.T + shift), (0, 3), (0, 1), 1e-6,
                            spans=(8, 8), max_spans=8)
    assert np.allclose(mapped.poles, fit.poles @ A.T + shift, atol=1e-9)


def test_tolerance_holds_at_random_points_and_refines_locally():
    def f(u, v):  # a twisted band, steeper at one end
        phi = 0.8 * v ** 3
        return np.stack([np.cos(u + phi) * 10, np.sin(u + phi) * 10, 5 * v], -1)

    tol = 1e-6
    fit = sf.fit_surface(grid_fn(f), (0, 2 * np.pi), (0, 1), tol)
    assert fit.deviation <= tol
    rng = np.random.default_rng(1)
    u, v = rng.uniform(0, 2 * np.pi, 400), rng.uniform(0, 1, 400)
    err = np.linalg.norm(evaluate(fit, u, v) - f(u, v), axis=1)
    assert err.max() <= 2 * tol
    vk = np.unique(fit.vknots)
    assert np.diff(vk)[-1] < np.diff(vk)[0]  # the steep end got the shorter spans


def test_seams_and_poles_stay_closed():
    def f(u, v):  # a sphere cap: closed in u, one point at v = -pi/2
        return np.stack([np.cos(v) * np.cos(u), np.cos(v) * np.sin(u), np.sin(v)], -1) * 3
    fit = sf.fit_surface(grid_fn(f), (0, 2 * np.pi), (-np.pi / 2, -0.5), 1e-7)
    assert np.array_equal(fit.poles[0], fit.poles[-1])
    assert np.ptp(fit.poles[:, 0], axis=0).max() == 0.0


def test_curve_fit():
    fit = sf.fit_curve(lambda t: np.stack([np.cos(t), np.sin(2 * t)], -1), 0, 6, 1e-8)
    t = np.linspace(0, 6, 777)
    err = np.linalg.norm(sf.evaluate_curve(fit, t) - np.stack([np.cos(t), np.sin(2 * t)], -1),
                         axis=1)
    assert fit.deviation <= 1e-8 and err.max() <= 2e-8
