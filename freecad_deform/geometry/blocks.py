"""Passes over large arrays, shared by the mesh and point kernels: most go BLOCK rows at a
time, so the temporaries of a block stay in the CPU cache (about twice as fast as
whole-array passes on a million rows)."""
import os
import threading
from concurrent.futures import ThreadPoolExecutor, wait

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
_pool_lock = threading.Lock()
if hasattr(os, "register_at_fork"):           # a forked child has the pool but no threads
    os.register_at_fork(after_in_child=_pool.clear)


def in_parallel(fn, n):
    """fn(start, stop) over [0, n) split at BLOCK boundaries into one range per core, the
    last in this thread and the others in worker threads; returns the results in order.
    numpy releases the GIL inside its loops, so a blocked pass of many numpy calls runs on
    all cores (1.5 to 1.8x on two); ranges under 4 blocks are not split, nor is a call made
    from a worker (it would wait for itself). A worker runs under the caller's numpy error
    state (np.errstate is per thread); an error in any range is raised once every range
    has ended."""
    k = min(_workers(), max(1, n // (4 * BLOCK)))
    if k == 1 or threading.current_thread().name.startswith("freecad_deform"):
        return [fn(0, n)]
    with _pool_lock:
        if not _pool:
            _pool.append(ThreadPoolExecutor(_workers() - 1,
                                            thread_name_prefix="freecad_deform"))
    state = np.geterr()

    def run(start, stop):
        if state == _DEFAULT_ERR:             # (np.errstate costs every ufunc call 4 us)
            return fn(start, stop)
        with np.errstate(**state):
            return fn(start, stop)

    bounds = [BLOCK * round(n * i / k / BLOCK) for i in range(k)] + [n]
    futures = [_pool[0].submit(run, bounds[i], bounds[i + 1]) for i in range(k - 1)]
    try:
        last = fn(bounds[-2], n)
    finally:
        wait(futures)
    return [f.result() for f in futures] + [last]


_DEFAULT_ERR = {"divide": "warn", "over": "warn", "under": "ignore", "invalid": "warn"}
