"""Tetrahedral mesh kernels of DimensionDrive (issue 17), each against an oracle here: a
cube of tetrahedra, its closed-form volume, determinants evaluated
directly along the motion, a regular tetrahedron's quality 1."""
import itertools

import numpy as np
import pytest

from freecad_deform.geometry.mesh import volume as vm


@pytest.fixture(scope="module")
def cube():
    """The unit cube, 4 x 4 x 4 cells of 6 tetrahedra each (Freudenthal's subdivision along
    the diagonal: conforming), interior nodes jiggled."""
    n = 4
    g = np.linspace(0, 1, n + 1)
    X = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    rng = np.random.default_rng(1)
    inner = np.all((X > 0) & (X < 1), axis=1)
    X[inner] += rng.uniform(-0.05, 0.05, (inner.sum(), 3))
    index = np.arange(len(X)).reshape(n + 1, n + 1, n + 1)
    tets = []
    for i, j, k in itertools.product(range(n), repeat=3):
        for order in itertools.permutations(range(3)):
            corner = np.array([i, j, k])
            path = [index[tuple(corner)]]
            for axis in order:
                corner[axis] += 1
                path.append(index[tuple(corner)])
            tets.append(path)
    return X, np.array(tets)


def test_boundary_is_the_closed_outward_surface(cube):
    X, tets = cube
    T = vm.boundary_triangles(X, tets)
    assert len(T) == 6 * 2 * 16
    tri = X[T]
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6
    assert volume == pytest.approx(1.0, abs=1e-12)
    on_faces = np.any((np.abs(X[np.unique(T)]) < 1e-12) | (np.abs(X[np.unique(T)] - 1) < 1e-12),
                      axis=1)
    assert on_faces.all()


def test_quadratic_split_fills_the_parent():
    X = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2.0]])
    mids = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    X = np.concatenate([X, [(X[a] + X[b]) / 2 for a, b in mids]])
    tets, parent = vm.linear_tets(np.arange(10)[None])
    v = vm.signed_volumes(X, tets) / 6
    assert np.all(v > 0) and v.sum() == pytest.approx(8 / 6, abs=1e-12)
    assert np.all(parent == 0)


def test_quality_of_a_regular_and_a_flat_tetrahedron():
    X = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1.0]])
    t = vm.oriented(X, np.array([[0, 1, 2, 3], [1, 0, 2, 3]]))
    assert vm.scaled_jacobian(X, t) == pytest.approx([1.0, 1.0], abs=1e-12)
    flat = X.copy()
    flat[3] = (X[0] + X[1] + X[2]) / 3
    assert abs(vm.scaled_jacobian(flat, t[:1])[0]) < 1e-12


def test_inversion_reach_is_where_the_first_tetrahedron_turns(cube):
    X, tets = cube
    rng = np.random.default_rng(2)
    for _ in range(5):
        field = rng.normal(size=X.shape)
        lo, hi = vm.inversion_reach(X, tets, field)
        s0 = np.sign(vm.signed_volumes(X, tets))
        for end in (lo, hi):
            inside = np.sign(vm.signed_volumes(X + 0.999 * end * field, tets))
            beyond = np.sign(vm.signed_volumes(X + 1.001 * end * field, tets))
            assert np.all(inside == s0) and np.any(beyond != s0)


def test_extension_keeps_a_translation_and_the_maximum_principle(cube):
    X, tets = cube
    B = np.unique(vm.boundary_triangles(X, tets))
    ext = vm.Extension(X, tets, B)
    f = ext.field(np.tile([0.3, -0.2, 0.1], (len(B), 1)))
    assert np.abs(f - [0.3, -0.2, 0.1]).max() < 1e-12
    bump = np.zeros((len(B), 3))
    bump[:, 2] = np.sin(3 * X[B, 0]) * X[B, 1]
    f = ext.field(bump)
    assert f[:, 2].max() <= bump[:, 2].max() + 1e-12
    assert f[:, 2].min() >= bump[:, 2].min() - 1e-12
    assert np.array_equal(f[B], bump)
