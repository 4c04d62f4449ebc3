"""Point-cloud stretch: rigid parts moved exactly, the gap filled on the section, errors named."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from freecad_deform.geometry import DeformError
from freecad_deform.geometry.points.stretch import spacing, stretch_points


def box_surface(step=1.0, size=(10.0, 6.0, 4.0)):
    """Points on the surface of an axis-aligned box on a regular grid of `step`."""
    axes = [np.arange(0.0, s + 1e-9, step) for s in size]
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(3, -1).T
    on_surface = np.any(np.isclose(grid, 0.0) | np.isclose(grid, size), axis=1)
    return grid[on_surface]


unit_vectors = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.3)


def test_spacing_is_grid_step():
    assert spacing(box_surface(0.5)) == pytest.approx(0.5)


@settings(max_examples=40, deadline=None)
@given(normal=unit_vectors, frac=st.floats(0.2, 0.8), distance=st.floats(0.5, 20.0))
def test_rigid_parts_move_exactly(normal, frac, distance):
    pts = box_surface()
    n = np.asarray(normal) / np.linalg.norm(normal)
    s_all = pts @ n
    origin = n * (s_all.min() + frac * (s_all.max() - s_all.min()))
    out = stretch_points(pts, origin, n, distance)
    s = (pts - origin) @ n
    near = s <= 1e-9  # points on the plane (to rounding) stay with the near part
    # the original points come first, in order: before the plane bit-identical, beyond it moved
    np.testing.assert_array_equal(out[: len(pts)][near], pts[near])
    np.testing.assert_allclose(out[: len(pts)][~near], pts[~near] + distance * n, atol=1e-12)
    fill = out[len(pts):]
    sf = (fill - origin) @ n
    assert np.all((sf > 0) & (sf < distance))


def test_gap_filled_at_cloud_spacing():
    pts = box_surface(0.5)
    origin, n, d = np.array([5.0, 0, 0]), np.array([1.0, 0, 0]), 3.0
    out = stretch_points(pts, origin, n, d)
    fill = out[len(pts):]
    # oracle: the section of a box surface is the rectangle outline at x=5 (y in [0,6], z in [0,4])
    y, z = fill[:, 1], fill[:, 2]
    on_outline = np.isclose(y, 0) | np.isclose(y, 6) | np.isclose(z, 0) | np.isclose(z, 4)
    assert on_outline.all()
    layers = np.unique(np.round(fill[:, 0] - 5.0, 9))
    np.testing.assert_allclose(np.diff(np.concatenate([[0], layers, [d]])), 0.5)


def test_shrink_removes_slab():
    pts = box_surface(0.5)
    out = stretch_points(pts, np.array([4.0, 0, 0]), np.array([1.0, 0, 0]), -2.0)
    assert out[:, 0].max() == pytest.approx(8.0)
    kept = pts[(pts[:, 0] <= 4.0) | (pts[:, 0] >= 6.0)]
    assert len(out) == len(kept)


def test_two_planes_scale_between():
    pts = box_surface(0.5)
    n = np.array([1.0, 0, 0])
    out = stretch_points(pts, np.array([2.0, 0, 0]), n, 4.0, np.array([6.0, 0, 0]), n)
    expected = pts.copy()
    x = pts[:, 0]
    expected[:, 0] = np.where(x <= 2, x, np.where(x >= 6, x + 4, 2 + (x - 2) * 2.0))
    np.testing.assert_allclose(out, expected, atol=1e-12)


@pytest.mark.parametrize("kwargs, prop", [
    (dict(origin=[20.0, 0, 0], normal=[1.0, 0, 0], distance=1.0), "Plane"),
    (dict(origin=[5.0, 0, 0], normal=[0.0, 0, 0], distance=1.0), "Plane"),
    (dict(origin=[5.0, 0, 0], normal=[1.0, 0, 0], distance=-7.0), "Distance"),
    (dict(origin=[5.0, 0, 0], normal=[1.0, 0, 0], distance=-5.0, origin2=[8.0, 0, 0],
          normal2=[1.0, 0, 0]), "Distance"),
    (dict(origin=[5.0, 0, 0], normal=[1.0, 0, 0], distance=1.0, origin2=[8.0, 0, 0],
          normal2=[0.0, 1.0, 0]), "Plane2"),
    (dict(origin=[5.0, 0, 0], normal=[1.0, 0, 0], distance=1.0, origin2=[3.0, 0, 0],
          normal2=[1.0, 0, 0]), "Plane2"),
])
def test_bad_input_names_the_property(kwargs, prop):
    with pytest.raises(DeformError) as err:
        stretch_points(box_surface(), **kwargs)
    assert err.value.prop == prop
    assert prop in str(err.value)


def test_spacing_ignores_repeated_points():
    pts = box_surface(0.5)
    assert spacing(np.vstack([pts, pts])) == pytest.approx(0.5)
    with pytest.raises(DeformError) as err:
        spacing(np.zeros((5, 3)))
    assert err.value.prop == "Base"


def test_depth_layers_farther_apart_than_the_spacing_still_fill_the_gap():
    """A stereo scan cut across its depth: depth in layers 8 steps apart, the plane between
    two layers. The nearest layer is the section: the fill repeats its (x, y) pattern."""
    x, y = np.meshgrid(np.arange(0.0, 20.0), np.arange(0.0, 10.0), indexing="ij")
    layers = [np.column_stack([x.ravel(), y.ravel(), np.full(x.size, z)])
              for z in np.arange(0.0, 80.0, 8.0)]
    pts = np.vstack([lay[lay[:, 0] + lay[:, 1] > k % 3] for k, lay in enumerate(layers)])
    origin, n = np.array([0.0, 0.0, 33.0]), np.array([0.0, 0.0, 1.0])   # 32 is nearest
    out = stretch_points(pts, origin, n, 5.0, step=1.0)
    fill = out[len(pts):]
    assert len(fill) > 0
    nearest = pts[pts[:, 2] == 32.0][:, :2]
    assert {tuple(p) for p in fill[:, :2]} == {tuple(p) for p in nearest}
    assert np.all((fill[:, 2] > 33.0) & (fill[:, 2] < 38.0))
