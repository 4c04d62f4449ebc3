"""Passes over large arrays, shared by the mesh and point kernels: most go BLOCK rows at a
time, so the temporaries of a block stay in the CPU cache (about twice as fast as
whole-array passes on a million rows)."""
import os
from concurrent.futures import ThreadPoolExecutor

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


def _workers():
    """The threads a blocked pass may use: the cores this process may run on, at most 4
    (the passes are bound by memory beyond that)."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                    # (not on Linux)
        cores = os.cpu_count() or 1
    return max(1, min(cores, 4))


_pool = []


def in_parallel(fn, n):
    """fn(start, stop) over [0, n) split at BLOCK boundaries into one range per core, the
    last in this thread and the others in worker threads; returns the results in order.
    numpy releases the GIL inside its loops, so a blocked pass of many numpy calls runs on
    all cores (1.5 to 1.8x on two); ranges under 4 blocks are not split. fn sees numpy's
    default error state in a worker (np.errstate is per thread)."""
    k = min(_workers(), max(1, n // (4 * BLOCK)))
    if k == 1:
        return [fn(0, n)]
    if not _pool:
        _pool.append(ThreadPoolExecutor(_workers() - 1, thread_name_prefix="freecad_deform"))
    bounds = [BLOCK * round(n * i / k / BLOCK) for i in range(k)] + [n]
    futures = [_pool[0].submit(fn, bounds[i], bounds[i + 1]) for i in range(k - 1)]
    last = fn(bounds[-2], n)
    return [f.result() for f in futures] + [last]
