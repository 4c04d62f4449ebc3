"""Plane and cylinder fits against the parameters that generated the points."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from freecad_deform.geometry.mesh.fits import fit_cylinder, fit_plane


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_plane_fit_recovers_the_plane_and_orientation(seed):
    rng = np.random.default_rng(seed)
    n = Rotation.random(random_state=seed).apply([0, 0, 1])
    d = rng.uniform(-50, 50)
    u = np.cross(n, [1, 0, 0] if abs(n[0]) < 0.9 else [0, 1, 0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    ab = rng.uniform(-20, 20, (30, 2))
    pts = d * n + ab[:, :1] * u + ab[:, 1:] * w
    fit = fit_plane(pts, -n[None])
    assert np.allclose(fit.normal, -n, atol=1e-9)
    assert abs(fit.offset + d) < 1e-9 and fit.rms < 1e-9


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_cylinder_fit_recovers_axis_point_and_radius(seed):
    rng = np.random.default_rng(seed)
    R = Rotation.random(random_state=seed)
    a = R.apply([0, 0, 1])
    r = rng.uniform(0.5, 40)
    centre = rng.uniform(-50, 50, 3)
    phi = rng.uniform(0, 2 * np.pi, 60)
    z = rng.uniform(-10, 10, 60)
    radial = R.apply(np.column_stack([np.cos(phi), np.sin(phi), np.zeros(60)]))
    pts = centre + r * radial + z[:, None] * a
    fit = fit_cylinder(pts, radial)
    assert abs(fit.radius - r) < 1e-8 * max(1, r)
    assert np.linalg.norm(np.cross(fit.axis, a)) < 1e-9
    off = fit.point - centre
    assert np.linalg.norm(off - (off @ a) * a) < 1e-8 * max(1, r)
    assert fit.rms < 1e-8


def test_arc_of_a_cylinder_and_the_plane_is_not_one():
    """A 60-degree arc (a fillet) still fits; a plane fits a cylinder badly."""
    phi = np.linspace(0, np.pi / 3, 12)
    z = np.repeat([0.0, 5.0], 12)
    radial = np.column_stack([np.cos(np.tile(phi, 2)), np.sin(np.tile(phi, 2)), np.zeros(24)])
    pts = 3.0 * radial + np.column_stack([np.zeros((24, 2)), z]) + [1, 2, 0]
    fit = fit_cylinder(pts, radial)
    assert abs(fit.radius - 3.0) < 1e-9
    assert fit_plane(pts).rms > 0.05
