"""One BLAS thread around fricctl's own small dense products.

The trainers' products are small: Levenberg-Marquardt's normal matrix ``jt @ jt.T`` is
17 x N with N ~4000 patterns (``fricctl/nn/train/lm.py``), the others smaller.  OpenBLAS
splits such a product over every core it sees; on two cores the second thread doubled the
CPU of a training at load ~5 and, on a loaded machine, its waiting thread spins (one
training took 1.1 s in one run and 68.8 s in the next; benchmarks/README.md, "Chapter 4 and
reproduce: one BLAS thread per process").  One thread gave the same networks and claims
bit for bit there and in the measurements of this change (same section); a BLAS whose
threads split an entry's sum could differ in the last bits, which was not seen here.

:func:`one_blas_thread` limits the BLAS libraries loaded in the process (NumPy's and
SciPy's OpenBLAS, MKL, BLIS) to one thread for the duration of a ``with`` block and
restores each library's previous setting on exit, with threadpoolctl (scikit-learn's
library for this; it acts after NumPy is imported, where ``OPENBLAS_NUM_THREADS`` must be
set before).  A library does not change its user's thread settings for good: the limit
lives only around fricctl's own work (:meth:`fricctl.nn.train.core.Trainer.train`), and a
user's BLAS outside it keeps its threads.  OpenMP pools are left alone (``user_api="blas"``):
numba's parallel simulation loop (``fricctl/simulate/loop.py``, one run per thread) keeps
its threads.

Notes
-----
The limit is process-wide while a block runs (BLAS has one setting per library, not per
thread): another thread of the same process doing its own large products at that moment
also gets one BLAS thread.  Blocks entered by several threads at once (trainers in a
thread pool) or nested share one limit: the first to enter sets it, the last to leave
restores the setting found by the first (a counter under a lock); plain
``threadpool_limits`` blocks left in another order than entered would restore each other's
settings and could leave the process at one thread for good.

Examples
--------
>>> import numpy as np
>>> with one_blas_thread():
...     float((np.ones((17, 4000)) @ np.ones((4000, 17)))[0, 0])
4000.0
"""

from __future__ import annotations

import contextlib
import threading

from threadpoolctl import threadpool_limits

__all__ = ["one_blas_thread"]

_LOCK = threading.Lock()
_inside = 0  # blocks running now, in any thread
_limiter = None  # the threadpool_limits of the first of them: holds the settings to restore


@contextlib.contextmanager
def one_blas_thread():
    """A context under which the loaded BLAS libraries use one thread each.

    ``with one_blas_thread(): ...``; when the last block running in the process leaves,
    every BLAS library gets back the number of threads it had when the first entered
    (also when the block raises).
    """
    global _inside, _limiter
    with _LOCK:
        if _inside == 0:
            _limiter = threadpool_limits(limits=1, user_api="blas")
        _inside += 1
    try:
        yield
    finally:
        with _LOCK:
            _inside -= 1
            if _inside == 0:
                _limiter.restore_original_limits()
                _limiter = None
