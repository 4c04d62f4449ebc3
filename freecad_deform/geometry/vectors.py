"""Unit vectors and the cross-product matrix, shared by every kernel domain."""
import numpy as np

from .errors import DeformError


def unit(v, prop=None, what="direction"):
    """`v` (..., 3) scaled to length 1 along its last axis.

    With `prop`, a zero (below 1e-12) or non-finite vector is bad input for that property
    ("The {what} of {prop} has zero length"); without, zero vectors stay zero."""
    v = np.asarray(v, dtype=float)
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    if prop is not None:
        if not np.all(np.isfinite(length)) or np.any(length < 1e-12):
            raise DeformError(f"The {what} of {prop} has zero length; give {prop} a direction.",
                              prop)
        return v / length
    return v / np.maximum(length, 1e-300)


def skew(k):
    """[k]x, the matrix of the cross product k x ., for k (..., 3)."""
    k = np.asarray(k, float)
    z = np.zeros(k.shape[:-1])
    return np.stack([np.stack([z, -k[..., 2], k[..., 1]], -1),
                     np.stack([k[..., 2], z, -k[..., 0]], -1),
                     np.stack([-k[..., 1], k[..., 0], z], -1)], -2)
