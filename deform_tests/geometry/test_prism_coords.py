"""Warren coordinates in triangular prisms: the properties eq. 2.2 promises, checked on
random right and oblique prisms (oracle: the definition of barycentric coordinates)."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from freecad_deform.geometry.mesh.prism_coords import coordinates

seeds = st.integers(0, 2**32 - 1)


def _prism(rng, oblique):
    tri = rng.uniform(-10, 10, (3, 3))
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    n /= np.linalg.norm(n)
    h = rng.uniform(0.1, 5)
    shift = rng.uniform(-0.5, 0.5, 3) * h if oblique else 0.0
    return np.vstack([tri - h * n, tri + h * n + shift])


def _inside(rng, prism, k):
    lam = rng.dirichlet([1, 1, 1], k)
    t = rng.uniform(0, 1, k)[:, None]
    return (1 - t) * (lam @ prism[:3]) + t * (lam @ prism[3:])


def _well_shaped(prism):
    e = prism[1:3] - prism[0]
    return np.linalg.norm(np.cross(*e)) > 1.0


@settings(max_examples=60, deadline=None)
@given(seeds, st.booleans())
def test_partition_of_unity_positivity_and_linear_precision(seed, oblique):
    rng = np.random.default_rng(seed)
    prism = _prism(rng, oblique)
    if not _well_shaped(prism):
        return
    x = _inside(rng, prism, 40)
    b, depth = coordinates(prism[None], np.zeros(len(x), int), x)
    assert np.all(depth >= -1e-9)
    assert np.all(b >= -1e-15)
    assert np.allclose(b.sum(axis=1), 1.0, atol=1e-14)
    assert np.abs(b @ prism - x).max() < 1e-10 * (1 + np.abs(prism).max())


@settings(max_examples=40, deadline=None)
@given(seeds)
def test_affine_maps_are_reproduced(seed):
    """Linear precision + partition of unity: moving the prism by an affine map moves
    every inside point by the same map (what makes planes stay planes in the drive)."""
    rng = np.random.default_rng(seed)
    prism = _prism(rng, True)
    if not _well_shaped(prism):
        return
    A, t = rng.normal(size=(3, 3)), rng.normal(size=3)
    x = _inside(rng, prism, 30)
    b, _ = coordinates(prism[None], np.zeros(len(x), int), x)
    assert np.abs(b @ (prism @ A.T + t) - (x @ A.T + t)).max() < 1e-9 * (1 + np.abs(A).max() * 20)


def test_vertices_and_faces():
    """At a prism vertex only that vertex counts; on a face only the face's vertices."""
    rng = np.random.default_rng(3)
    prism = _prism(rng, True)
    b, _ = coordinates(prism[None], np.zeros(6, int), prism)
    assert np.allclose(b, np.eye(6), atol=1e-12)
    on_bottom = rng.dirichlet([1, 1, 1], 10) @ prism[:3]
    b, _ = coordinates(prism[None], np.zeros(10, int), on_bottom)
    assert np.abs(b[:, 3:]).max() < 1e-12
    assert np.abs(b[:, :3] @ prism[:3] - on_bottom).max() < 1e-10


def test_outside_points_are_clamped_to_a_convex_combination():
    prism = np.array([[0, 0, -1], [1, 0, -1], [0, 1, -1], [0, 0, 1], [1, 0, 1], [0, 1, 1]], float)
    x = np.array([[0.2, 0.2, 3.0], [-0.5, 0.3, 0.0]])
    b, depth = coordinates(prism[None], np.zeros(2, int), x)
    assert np.all(depth < 0)
    assert np.all(b >= 0) and np.allclose(b.sum(axis=1), 1)
    assert np.allclose(b[0, :3], 0)          # above the top: only the top vertices
    assert np.allclose(b[0] @ prism, [0.2, 0.2, 1.0])   # straight above: its projection
    assert np.allclose(b[1, [1, 4]], 0)                 # beside the x = 0 face: on it
    assert abs((b[1] @ prism)[0]) < 1e-15
