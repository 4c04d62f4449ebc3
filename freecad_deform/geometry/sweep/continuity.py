"""Lemma 1 of Wu & Ilies: the continuity a deformation reaches where a face crosses a joint."""
import numpy as np


def joint_continuity(normals, tangents, tol=1e-6):
    """"G1" if every surface normal is perpendicular to the trajectory tangent at its point, else "C0".

    normals, tangents: (N, 3) arrays sampled along one face's joint curve; `tol` bounds
    |cos| of the angle between them.
    """
    nrm = np.asarray(normals, float).reshape(-1, 3)
    tan = np.asarray(tangents, float).reshape(-1, 3)
    tan = np.broadcast_to(tan, nrm.shape)
    cos = np.einsum("ij,ij->i", nrm, tan) / (
        np.linalg.norm(nrm, axis=1) * np.linalg.norm(tan, axis=1))
    return "G1" if np.all(np.abs(cos) <= tol) else "C0"


def report(entries):
    """One line 'Face3: G1; Face7: C0' from (face name, continuity) pairs, in face order."""
    return "; ".join(f"{name}: {kind}" for name, kind in entries)
