r"""Standard errors that hold for a coloured residual: the score summed over blocks.

Every fit of :mod:`fricctl.identify` is, at its optimum, a linearised least squares
``y = J theta + e``.  The textbook covariance ``sigma^2 (J^T J)^-1`` assumes white
``e``; a filtered equation error (parallel filtering) or a simulation error (a position
integrates every torque error) is coloured, and the textbook std is then optimistic
(36 times on a seeded 1 kHz open-loop DIDIM record).  Here the residual is cut into
contiguous blocks longer than its correlation, and

.. math::

    \operatorname{cov}\hat\theta = (J^T J)^{-1}
        \Big(\tfrac{K}{K-1}\sum_{b=1}^{K} s_b s_b^T\Big) (J^T J)^{-1},
    \qquad s_b = \sum_{t \in b} J_t\, e_t ,

the covariance a block bootstrap of the linearised fit converges to (the batch-means,
or Bartlett, estimate of the score's long-run covariance; Kuensch 1989).  The block
length is read off the residual: twice its integrated correlation time
(``1 + 2 sum_l rho_l`` up to the first lag where ``rho`` falls below zero), at least one
sample; at most a twentieth of the record, so that at least twenty blocks estimate the
covariance -- a residual correlated for longer makes the std a lower bound, and
:func:`block_covariance` says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v

__all__ = ["BlockCovariance", "block_covariance", "correlation_time", "MIN_BLOCKS"]

#: Fewest blocks the covariance is estimated from [-] (caps the block length at N/20).
MIN_BLOCKS = 20


def correlation_time(e) -> float:
    """Integrated correlation time of ``e`` [samples]: ``1 + 2 sum_{l>=1} rho_l`` summed up to
    the first lag whose autocorrelation ``rho_l`` is not positive (1 for a white residual)."""
    e = v.array("e", e, min_size=2)
    e = e - e.mean()
    n = e.size
    denom = float(e @ e)
    if denom == 0.0:
        return 1.0
    nfft = 1 << (2 * n - 1).bit_length()
    f = np.fft.rfft(e, nfft)
    acf = np.fft.irfft(f * np.conj(f), nfft)[:n] / denom
    neg = np.flatnonzero(acf[1:] <= 0.0)
    last = int(neg[0]) if neg.size else n - 1  # lags 1 .. last are positive
    return float(1.0 + 2.0 * np.sum(acf[1:last + 1]))


@dataclass(frozen=True, kw_only=True)
class BlockCovariance:
    """The covariance of a linearised fit from its residual summed over blocks."""

    cov: np.ndarray
    """Covariance of the estimate (parameter units squared)."""
    block: int
    """Block length [samples]."""
    blocks: int
    """Number of blocks [-]."""
    correlation: float
    """Integrated correlation time of the residual [samples]."""
    capped: bool
    """The residual is correlated over more than a block can hold (``N / MIN_BLOCKS``): the
    std is a lower bound."""

    @property
    def std(self) -> np.ndarray:
        """Standard errors (square roots of the diagonal)."""
        return np.sqrt(np.maximum(np.diag(self.cov), 0.0))

    def describe(self) -> str:
        """One phrase for reports and model files."""
        return (f"block covariance of the score over {self.blocks} blocks of {self.block} "
                f"samples (residual correlation time {self.correlation:.3g} samples"
                + ("; capped: the std is a lower bound)" if self.capped else ")"))


def block_covariance(J, e, *, block: int | None = None) -> BlockCovariance:
    """Covariance of the least-squares estimate for ``y = J theta + e`` with coloured ``e``.

    Parameters
    ----------
    J : array_like, shape (N, p)
        Jacobian (observation matrix) at the optimum, rows in time order.
    e : array_like, shape (N,)
        Residual at the optimum, same rows.
    block : int, optional
        Block length [samples]; default twice the residual's correlation time
        (:func:`correlation_time`), capped at ``N // MIN_BLOCKS``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> J = np.column_stack([np.ones(4000), np.sin(np.arange(4000) / 50)])
    >>> e = rng.normal(size=4000)                          # white: blocks of ~1 sample
    >>> bc = block_covariance(J, e)
    >>> white = np.sqrt(np.diag(np.linalg.inv(J.T @ J)))   # sigma = 1
    >>> bool(np.all(np.abs(bc.std / white - 1) < 0.1))
    True
    """
    J = np.asarray(J, dtype=float)
    e = v.array("e", e, min_size=2)
    if J.ndim != 2 or J.shape[0] != e.size:
        raise ValueError(f"J: expected shape ({e.size}, p), got {J.shape}")
    n = e.size
    tau = correlation_time(e)
    cap = max(n // MIN_BLOCKS, 1)
    if block is None:
        want = max(int(math.ceil(2.0 * tau)), 1)
        length, capped = min(want, cap), want > cap
    else:
        length, capped = v.integer("block", block, low=1, high=n), False
    k = n // length
    if k < 2:
        raise ValueError(f"block: {length} samples leave fewer than 2 blocks of {n}")
    g = J[: k * length] * e[: k * length, None]
    s = g.reshape(k, length, -1).sum(axis=1)
    meat = (k / (k - 1)) * (s.T @ s) * (n / (k * length))
    bread = np.linalg.pinv(J.T @ J)
    return BlockCovariance(cov=bread @ meat @ bread, block=length, blocks=k, correlation=tau,
                           capped=capped)
