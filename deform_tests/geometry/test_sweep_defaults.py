"""Where a new Stretch, Bend, Twist or Taper starts (geometry.sweep.defaults): each claim is
checked on points drawn in the box and on closed forms written here, not on the kernel."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from freecad_deform.geometry.sweep import defaults

coord = st.floats(-1e3, 1e3)
size = st.floats(1e-2, 1e3)
unit = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 1e-3).map(
    lambda v: np.asarray(v) / np.linalg.norm(v))


@st.composite
def boxes(draw):
    lo = np.array([draw(coord) for _ in range(3)])
    return lo, lo + np.array([draw(size) for _ in range(3)])


def inside(lo, hi, count=200, seed=0):
    """Points of the box (its corners among them)."""
    rng = np.random.default_rng(seed)
    grid = np.array(np.meshgrid(*zip(lo, hi))).reshape(3, -1).T
    return np.vstack([grid, lo + rng.random((count, 3)) * (hi - lo)])


@given(boxes(), unit, st.tuples(coord, coord, coord))
def test_extent_bounds_every_point_of_the_box(box, normal, origin):
    lo, hi = box
    low, high = defaults.extent(lo, hi, origin, normal)
    s = (inside(lo, hi) - origin) @ normal
    scale = 1e-9 * (1 + np.abs(s).max())
    assert s.min() >= low - scale and s.max() <= high + scale
    assert np.isclose(s.min(), low, atol=scale) and np.isclose(s.max(), high, atol=scale)


@given(boxes())
def test_default_plane_halves_the_longest_side(box):
    lo, hi = box
    origin, normal = defaults.default_plane(lo, hi)
    i = int(np.argmax(hi - lo))
    assert normal[i] == 1.0 and np.count_nonzero(normal) == 1
    np.testing.assert_allclose(origin, (lo + hi) / 2)


@given(boxes(), unit, st.tuples(coord, coord, coord))
def test_crossing_origin_cuts_the_box_and_keeps_the_direction(box, normal, origin):
    lo, hi = box
    moved = defaults.crossing_origin(lo, hi, origin, normal)
    # moved along the normal only
    offset = moved - np.asarray(origin)
    np.testing.assert_allclose(offset, normal * (offset @ normal), atol=1e-9 * (1 + np.abs(moved).max()))
    s = (inside(lo, hi) - moved) @ normal
    assert s.min() < 0 < s.max()


def test_crossing_origin_keeps_a_plane_that_cuts():
    lo, hi = np.zeros(3), np.array([10.0, 4, 2])
    np.testing.assert_array_equal(defaults.crossing_origin(lo, hi, [3, 9, 9], [1, 0, 0]), [3, 9, 9])
    # a face on the boundary x = 10 gives only the direction: the plane goes to the middle
    np.testing.assert_allclose(defaults.crossing_origin(lo, hi, [10, 1, 1], [1, 0, 0]), [5, 1, 1])


@given(boxes(), unit, st.tuples(coord, coord, coord))
def test_axis_through_is_the_nearest_point_of_the_line(box, direction, origin):
    point = np.asarray(box[0])
    p, d = defaults.axis_through(point, 3.0 * direction, origin)
    np.testing.assert_allclose(d, direction, atol=1e-12)
    assert abs(np.cross(p - point, d)).max() <= 1e-9 * (1 + np.abs(p).max())   # on the line
    assert abs((np.asarray(origin) - p) @ d) <= 1e-9 * (1 + np.abs(p).max() + np.abs(origin).max())


@settings(max_examples=200)
@given(boxes(), unit, st.floats(0.05, 0.95))
def test_default_bend_axis_turns_every_section_point_away(box, normal, where):
    """In the plane, outside the section, and a positive Angle moves every point of the box
    in the plane (where the section lies) along the normal: n . (w x (p - c)) > 0."""
    lo, hi = box
    low, high = defaults.extent(lo, hi, lo, normal)
    origin = lo + normal * (low + where * (high - low))
    c, w = defaults.default_bend_axis(lo, hi, origin, normal)
    assert abs(np.linalg.norm(w) - 1) < 1e-12 and abs(w @ normal) < 1e-9
    assert abs((c - origin) @ normal) <= 1e-9 * (1 + np.abs(c).max())
    pts = inside(lo, hi)
    section = pts - np.outer((pts - origin) @ normal, normal)   # the box projected on the plane
    speed = np.cross(w, section - c) @ normal
    assert speed.min() > 0


def test_default_bend_axis_closed_form():
    """A 100 x 20 x 10 bar cut at x = 50: the axis runs along y (the second-longest side),
    1 below the bar (a tenth of its height), directed so that +Angle turns the far end up:
    y x (the section's centre - c) = y x (0, 0, 6) = +x."""
    c, w = defaults.default_bend_axis([0, 0, 0], [100, 20, 10], [50, 10, 5], [1, 0, 0])
    np.testing.assert_allclose(w, [0, 1, 0])
    np.testing.assert_allclose(c, [50, 10, -1])


@given(boxes(), unit, unit, st.sampled_from([-30.0, 30.0]))
def test_oriented_axis_gives_the_angle_a_positive_speed(box, normal, direction, angle):
    lo, hi = box
    centre = (lo + hi) / 2
    assume(abs(direction @ normal) < 0.99)
    point = centre + 2 * np.linalg.norm(hi - lo) * np.cross(normal, direction) / np.linalg.norm(
        np.cross(normal, direction))
    p, d = defaults.oriented_axis(lo, hi, centre, normal, point, direction, angle)
    np.testing.assert_array_equal(p, point)
    assert np.allclose(d, direction) or np.allclose(d, -direction)
    speed = angle * (np.cross(d, centre - p) @ normal)
    assert speed > 0


def test_plane_onto_line_moves_only_for_a_parallel_line_that_still_cuts():
    lo, hi = np.zeros(3), np.array([100.0, 20, 10])
    origin, normal = np.array([50.0, 10, 5]), np.array([1.0, 0, 0])
    np.testing.assert_allclose(defaults.plane_onto_line(lo, hi, origin, normal, [30, 0, 0], [0, 1, 0]),
                               [30, 10, 5])
    # off the part: the plane stays
    np.testing.assert_allclose(defaults.plane_onto_line(lo, hi, origin, normal, [130, 0, 0], [0, 1, 0]),
                               origin)
    # not parallel to the plane: the plane stays
    np.testing.assert_allclose(defaults.plane_onto_line(lo, hi, origin, normal, [30, 0, 0], [1, 1, 0]),
                               origin)


@given(boxes())
def test_region_planes_at_thirds_of_the_longest_side(box):
    lo, hi = box
    origin, normal, offset = defaults.region_planes(lo, hi)
    i = int(np.argmax(hi - lo))
    length = (hi - lo)[i]
    assert normal[i] == 1.0
    assert origin[i] == pytest.approx(lo[i] + length / 3)
    assert (origin + normal * offset)[i] == pytest.approx(lo[i] + 2 * length / 3)


def test_region_planes_from_a_picked_plane():
    lo, hi = np.zeros(3), np.array([120.0, 20, 10])
    origin, normal, offset = defaults.region_planes(lo, hi, [40, 3, 3], [1, 0, 0])
    np.testing.assert_allclose(origin, [40, 3, 3])
    assert offset == pytest.approx(40.0)   # halfway to the far end at x = 120


@given(unit)
def test_across_is_a_unit_vector_across_the_normal(normal):
    w = defaults.across(normal)
    assert abs(np.linalg.norm(w) - 1) < 1e-12 and abs(w @ normal) < 1e-12
