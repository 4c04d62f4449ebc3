"""Test surfaces as numpy arrays: a bicubic canopy (clamped, uniform knots) and a rational
quadratic cylinder patch whose area is known in closed form."""
import numpy as np

from freecad_deform.geometry.bspline_area import Surface


def clamped(n, degree):
    inner = np.linspace(0, 1, n - degree + 1)[1:-1]
    return np.concatenate([np.zeros(degree + 1), inner, np.ones(degree + 1)])


def canopy(n=6, m=None, size=(100.0, 60.0), height=25.0, degree=3):
    """n x m poles over a size[0] x size[1] rectangle, lifted by a sine bump and a slope."""
    m = m or n
    x, y = np.meshgrid(np.linspace(0, size[0], n), np.linspace(0, size[1], m), indexing="ij")
    z = height * np.sin(np.pi * x / size[0]) * np.sin(np.pi * y / size[1]) + 0.1 * x
    poles = np.stack([x, y, z], -1)
    return Surface(poles, np.ones((n, m)), clamped(n, degree), clamped(m, degree), degree,
                   degree)


def cylinder_patch(radius=5.0, height=20.0):
    """A quarter cylinder as a rational quadratic x linear surface: area pi r h / 2."""
    w = np.sqrt(0.5)
    arc = np.array([[radius, 0, 0], [radius, radius, 0], [0, radius, 0]], float)
    poles = np.stack([arc, arc + [0, 0, height]], 1)              # (3, 2, 3)
    weights = np.array([[1, 1], [w, w], [1, 1]], float)
    return Surface(poles, weights, np.array([0, 0, 0, 1, 1, 1.0]), np.array([0, 0, 1, 1.0]),
                   2, 1)
