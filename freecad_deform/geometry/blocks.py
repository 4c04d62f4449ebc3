"""Passes over large arrays, shared by the mesh and point kernels: most go BLOCK rows at a
time, so the temporaries of a block stay in the CPU cache (about twice as fast as
whole-array passes on a million rows)."""
import numpy as np

BLOCK = 16384   # rows a blocked loop takes at a time


def compress_rows(mask, T, out):
    """T's rows where `mask`, written in order into `out`; returns how many. One gather of
    the rows by index straight into `out` (mode "clip": "raise" copies `out` first): 1.4
    to 1.6x faster than np.compress block by block, which was faster than np.compress
    whole or with out=."""
    rows = np.flatnonzero(mask)
    T.take(rows, axis=0, out=out[:len(rows)], mode="clip")
    return len(rows)


def tiled(vector, rows=BLOCK):
    """A (3,) vector repeated for BLOCK rows (fewer when the array has fewer `rows`), flat,
    to add it to a block of rows as one flat operation: numpy broadcasts a (3,) vector over
    rows 3x slower (an inner loop of 3)."""
    return np.tile(np.asarray(vector, float), max(1, min(rows, BLOCK)))


def add_rows(rows, tile):
    """rows (k <= BLOCK, 3), C-contiguous, plus the vector of `tile` (see tiled), in place."""
    flat = rows.reshape(-1)
    np.add(flat, tile[:flat.size], out=flat)
    return rows
