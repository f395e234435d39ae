"""One BLAS thread around fricctl's own small dense products.

The trainers' products are small: Levenberg-Marquardt's normal matrix ``jt @ jt.T`` is
17 x N with N ~4000 patterns (``fricctl/nn/train/lm.py``), the others smaller.  OpenBLAS
splits such a product over every core it sees; on two cores the second thread doubled the
CPU of a training at load ~5 and, on a loaded machine, its waiting thread spins (one
training took 1.1 s in one run and 68.8 s in the next; benchmarks/README.md, "Chapter 4 and
reproduce: one BLAS thread per process").  One thread gave the same networks and claims
bit for bit there (OpenBLAS's threaded ``dgemm`` splits the rows and columns of the
product between threads, not the sums); a BLAS that splits the sums (MKL may) could
differ in the last bits.

:func:`one_blas_thread` limits the BLAS libraries loaded in the process (NumPy's and
SciPy's OpenBLAS, MKL, BLIS) to one thread for the duration of a ``with`` block and
restores each library's previous setting on exit, with threadpoolctl (scikit-learn's
library for this; it acts after NumPy is imported, where ``OPENBLAS_NUM_THREADS`` must be
set before).  A library does not change its user's thread settings for good: the limit
lives only around fricctl's own work (:meth:`fricctl.nn.train.core.Trainer.train`), and a
user's BLAS outside it keeps its threads.  OpenMP pools (numba's threading layer among
them) are left alone: fricctl's compiled kernels run serially.

Notes
-----
The limit is process-wide while the block runs (BLAS has one setting per library, not
per thread): another thread of the same process doing its own large products at that
moment also gets one BLAS thread.  Nested blocks restore in reverse order; two threads
entering and leaving blocks interleaved can restore each other's settings out of order
(fricctl's parallel runs are processes, each with its own setting).

Examples
--------
>>> import numpy as np
>>> with one_blas_thread():
...     float((np.ones((17, 4000)) @ np.ones((4000, 17)))[0, 0])
4000.0
"""

from __future__ import annotations

from threadpoolctl import threadpool_limits

__all__ = ["one_blas_thread"]


def one_blas_thread() -> threadpool_limits:
    """A context manager under which the loaded BLAS libraries use one thread each.

    Returns
    -------
    threadpoolctl.threadpool_limits
        Use it as ``with one_blas_thread(): ...``; on exit every BLAS library gets back
        the number of threads it had on entry.
    """
    return threadpool_limits(limits=1, user_api="blas")
