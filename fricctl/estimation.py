"""Velocity and acceleration from encoder data.

All estimators are pure functions ``f(t, position, *, ...) -> DerivativeEstimate``
over a uniform time vector ``t`` [s] and a measured position [rad] (or [m]):

* :func:`backward_difference` -- the raw estimate a 500 Hz controller has:
  ``v[k] = (q[k] - q[k-1]) / Ts``, and the same again for the acceleration.
* :func:`polynomial_segments` -- the paper's method (Gervini, Gomes & da Rosa
  2003): backward-difference velocity, split into the segments where it is
  non-zero, least-squares polynomial (6th order) on each segment, long segments
  in overlapping windows, acceleration as the analytic derivative.
* :func:`savitzky_golay` -- local polynomial smoothing/differentiation
  (:func:`scipy.signal.savgol_filter`).
* :func:`butterworth_central` -- the EMPS recipe (Janot, Gautier & Brunot 2019):
  zero-phase Butterworth low-pass, then central differences twice.

plus the signal helpers :func:`central_difference` (MATLAB ``diffcent``),
:func:`zero_phase_filter` (MATLAB ``filtfilt`` end handling) and :func:`decimate`
(MATLAB ``decimate``: order-8 Chebyshev I zero-phase low-pass, then one sample
in ``factor``), which the IDIM-LS recipe in :mod:`fricctl.identify` uses.

Notes
-----
None of these estimators knows the dynamics: no observer or Kalman filter is
provided.  Edge samples are handled by each method's own rule (documented per
function) and are less accurate; callers that need clean data drop a border.
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from . import _validate as v

__all__ = [
    "at_rest",
    "DerivativeEstimate",
    "backward_difference",
    "polynomial_segments",
    "savitzky_golay",
    "butterworth_central",
    "central_difference",
    "zero_phase_filter",
    "ZeroPhaseFilter",
    "decimate",
    "MAX_DECIMATION",
    "MAX_BUTTERWORTH_ORDER",
    "FILTER_RTOL",
    "ESTIMATORS",
    "estimate",
]

_TIME_RTOL = 1e-3


@dataclass(frozen=True, kw_only=True)
class DerivativeEstimate:
    """Velocity and acceleration estimated from a position record.

    Notes
    -----
    ``position`` is the (possibly smoothed) position the method used; for
    :func:`backward_difference` and :func:`polynomial_segments` it is the input.
    """

    t: np.ndarray = field(metadata={"unit": "s"})
    """Sample times [s]."""
    position: np.ndarray = field(metadata={"unit": "rad or m"})
    """Position the derivatives belong to [rad] or [m]."""
    velocity: np.ndarray = field(metadata={"unit": "rad/s or m/s"})
    """Estimated velocity [rad/s] or [m/s]."""
    acceleration: np.ndarray = field(metadata={"unit": "rad/s^2 or m/s^2"})
    """Estimated acceleration [rad/s^2] or [m/s^2]."""
    method: str
    """Name of the estimator, e.g. ``"polynomial_segments"``."""

    def __post_init__(self):
        for name in ("t", "position", "velocity", "acceleration"):
            x = np.array(getattr(self, name), dtype=float)
            bad = np.flatnonzero(~np.isfinite(x))
            if bad.size:  # never hand on a silent NaN: say which estimate failed where
                raise ValueError(f"{self.method}: the {name} estimate is not finite at sample "
                                 f"{int(bad[0])} (the record or the estimator's options overflow "
                                 f"double precision)")
            x.setflags(write=False)
            object.__setattr__(self, name, x)


@dataclass(frozen=True, kw_only=True)
class _Record:
    """A checked position record: uniform times, positions, and the sample time."""

    t: np.ndarray
    q: np.ndarray
    ts: float


def _record(t, position) -> _Record:
    """The record of an estimator's ``(t, position)``: 1-D, finite, same length >= 5, uniform t."""
    t = v.array("t", t, min_size=5)
    q = v.array("position", position, size=t.size)
    dt = np.diff(t)
    ts = (t[-1] - t[0]) / (t.size - 1)
    if np.any(dt <= 0) or np.any(np.abs(dt - ts) > _TIME_RTOL * ts):
        raise ValueError("t: time must be strictly increasing and uniform")
    return _Record(t=t, q=q, ts=float(ts))


#: Largest deviation [-] of a filter's transfer-function (b, a) response from the same
#: design in second-order sections: beyond it the coefficients have lost the filter to
#: round-off (high orders, low cut-offs) and filtering returns garbage or NaN.
FILTER_RTOL = 1e-6


def _ba_accurate(design, *args) -> bool:
    """Whether ``design(*args)`` in (b, a) form is the filter its second-order sections are."""
    b, a = design(*args)
    if not np.all(np.isfinite(a)) or np.max(np.abs(np.roots(a)), initial=0.0) >= 1.0:
        return False
    w = np.linspace(0.0, np.pi, 512)
    _, h_ba = signal.freqz(b, a, w)
    _, h_sos = signal.sosfreqz(design(*args, output="sos"), w)
    return bool(np.max(np.abs(h_ba - h_sos)) <= FILTER_RTOL)


def _determined(fit) -> bool:
    """Whether a least-squares polynomial fit ``fit()`` is determined in double precision
    (no rank deficiency, nothing overflows)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", np.exceptions.RankWarning)
        warnings.simplefilter("error", RuntimeWarning)  # overflow in the powers of the times
        try:
            out = fit()
        except (np.exceptions.RankWarning, RuntimeWarning, ValueError, np.linalg.LinAlgError):
            return False
    return bool(np.all(np.isfinite(np.asarray(out.coef if hasattr(out, "coef") else out))))


def _highest(ok, low: int, high: int) -> int:
    """The largest n in [low, high) with ``ok(n)`` (``ok`` monotone: true up to a limit), or low - 1."""
    if not ok(low):
        return low - 1
    lo, hi = low, high  # ok(lo) holds, ok(hi) does not
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def _backward(x: np.ndarray, ts: float) -> np.ndarray:
    d = np.empty_like(x)
    d[1:] = np.diff(x) / ts
    d[0] = d[1]  # no sample before the first: repeat the first difference
    return d


def central_difference(x, sample_time: float) -> np.ndarray:
    """Central difference with one-sided ends (MATLAB ``diffcent`` of M. Gautier).

    ``[x1-x0, (x2-x0)/2, ..., (x[n-1]-x[n-3])/2, x[n-1]-x[n-2]] / Ts``.

    Parameters
    ----------
    x : array_like, shape (N,)
        Samples.
    sample_time : float
        Sample time Ts [s].

    Examples
    --------
    >>> central_difference([0.0, 1.0, 4.0, 9.0], 1.0).tolist()
    [1.0, 2.0, 4.0, 5.0]
    """
    x = v.array("x", x, min_size=3)
    sample_time = v.real("sample_time", sample_time, positive=True, unit="s")
    with np.errstate(over="ignore", invalid="ignore"):
        d = np.concatenate(([x[1] - x[0]], (x[2:] - x[:-2]) / 2.0, [x[-1] - x[-2]])) / sample_time
    if not np.all(np.isfinite(d)):
        i = int(np.flatnonzero(~np.isfinite(d))[0])
        raise ValueError(f"x: the difference at index {i} over sample_time={sample_time:g} s "
                         f"overflows double precision")
    return d


def zero_phase_filter(b, a, x) -> np.ndarray:
    """Forward-backward IIR filtering with MATLAB ``filtfilt`` end handling.

    Odd (point-reflected) extension of ``3*(max(len(a), len(b)) - 1)`` samples at each
    end, as MATLAB does; SciPy's default pads one sample more, which changes the
    first and last few dozen samples slightly.  :class:`ZeroPhaseFilter` is the same
    filter checked once, for many signals.
    """
    b, a, x = v.array("b", b, min_size=1), v.array("a", a, min_size=1), v.array("x", x)
    return ZeroPhaseFilter(b, a)(x)


class ZeroPhaseFilter:
    """:func:`zero_phase_filter` with the filter ``(b, a)`` checked once: called on a signal,
    it filters it forward and backward, the same numbers as ``zero_phase_filter(b, a, x)``.

    A diagnosis filters a thousand columns of one record through one low-pass; per call
    :func:`scipy.signal.filtfilt` solved for the filter's initial state again, and the
    checks of ``b`` and ``a`` (their roots) ran again: 0.45 of 1.1 ms per 40 000-sample
    column (CPU, loaded 2-core machine).  Here they are done once, and the signal goes
    through the steps :func:`scipy.signal.filtfilt` takes (odd extension, ``lfilter``
    forward from the steady state times the first sample, backward likewise), so the
    result is the same to the bit (``tests/test_estimation.py`` compares them).

    Parameters
    ----------
    b, a : array_like
        Numerator and denominator of the filter (``a[0] != 0``, poles inside the unit
        circle).
    """

    def __init__(self, b, a):
        b = v.array("b", b, min_size=1)
        a = v.array("a", a, min_size=1)
        if a[0] == 0.0:
            raise ValueError("a: the leading denominator coefficient a[0] must not be 0")
        if a.size > 1 and np.max(np.abs(np.roots(a))) >= 1.0:
            raise ValueError(f"a: the filter is unstable (a pole of modulus "
                             f"{np.max(np.abs(np.roots(a))):.6g} >= 1); filtering would diverge")
        self.b, self.a = b, a
        #: samples of the odd extension at each end (3 x the order, MATLAB's)
        self.padlen = 3 * (max(len(a), len(b)) - 1)
        # filtfilt's steady state of the step response (what it solves for on every call),
        # solved on the first call as filtfilt does (it refuses a filter without a state)
        self._zi = None

    def __call__(self, x) -> np.ndarray:
        x = v.array("x", x)
        n = self.padlen
        if x.size <= n:
            raise ValueError(f"the record has {x.size} samples; this zero-phase filter needs more "
                             f"than {n} (3 x its order): record longer")
        if self._zi is None:
            self._zi = signal.lfilter_zi(self.b, self.a)
        b, a, zi = self.b, self.a, self._zi
        with np.errstate(over="ignore", invalid="ignore"):
            if n > 0:  # scipy.signal's odd_ext, then filtfilt's two passes
                ext = np.concatenate((2 * x[:1] - x[n:0:-1], x, 2 * x[-1:] - x[-2:-(n + 2):-1]))
            else:
                ext = x
            y, _ = signal.lfilter(b, a, ext, zi=zi * ext[:1])
            y, _ = signal.lfilter(b, a, y[::-1], zi=zi * y[-1:])
            y = y[::-1]
            if n > 0:
                y = y[n:-n]
        if not np.all(np.isfinite(y)):
            raise ValueError("the filtered record overflows double precision (x or the filter's "
                             "gain too large)")
        return y


#: Largest factor :func:`decimate` accepts: its order-8 Chebyshev low-pass in (b, a) form
#: stays within :data:`FILTER_RTOL` of the second-order-section design up to 17 and not
#: at 18 (``tests/test_reliability_library.py`` checks both; at 100 the "filtered" sine
#: of amplitude 1 came out at -16).
MAX_DECIMATION = 17


def decimate(x, factor: int) -> np.ndarray:
    """Low-pass and keep one sample in ``factor`` (MATLAB ``decimate`` semantics).

    Order-8 Chebyshev type I low-pass (0.05 dB ripple, edge 0.8/factor of Nyquist)
    applied with :func:`zero_phase_filter`, then samples ``nbeg-1, nbeg-1+factor, ...``
    with ``nbeg = factor - (factor*ceil(N/factor) - N)`` (MATLAB's 1-based choice,
    which keeps the last sample).  This is the "parallel filtering + resampling"
    of the IDIM-LS recipe.

    Parameters
    ----------
    x : array_like, shape (N,)
        Samples.
    factor : int
        Decimation factor, 1 to :data:`MAX_DECIMATION` (1 returns a copy).

    Examples
    --------
    >>> y = decimate(np.ones(25), 10)    # keeps samples 4, 14, 24
    >>> len(y), round(float(y[0]), 4)    # DC gain of an even-order Chebyshev I: -0.05 dB twice
    (3, 0.9886)
    """
    factor = v.integer("factor", factor, low=1)
    x = v.array("x", x)
    if factor == 1:
        return x.copy()
    if factor > MAX_DECIMATION:
        raise ValueError(f"factor must be at most {MAX_DECIMATION} (the order-8 Chebyshev filter in "
                         f"transfer-function form loses its accuracy beyond, MATLAB warns above 13); "
                         f"got {factor}: decimate in stages (e.g. 10, then {-(-factor // 10)})")
    if x.size <= 3 * 8:
        raise ValueError(f"x must have more than 24 samples to decimate, got {x.size}")
    b, a = signal.cheby1(8, 0.05, 0.8 / factor)
    y = zero_phase_filter(b, a, x)
    n = x.size
    nout = -(-n // factor)
    nbeg = factor - (factor * nout - n)
    return y[nbeg - 1::factor]


def backward_difference(t, position) -> DerivativeEstimate:
    """Backward-difference velocity and acceleration (what the controller sees).

    ``v[k] = (q[k] - q[k-1]) / Ts``, ``a[k] = (v[k] - v[k-1]) / Ts``; the first
    sample repeats the second.

    Parameters
    ----------
    t : array_like, shape (N,)
        Uniform sample times [s].
    position : array_like, shape (N,)
        Measured position [rad] or [m].

    Notes
    -----
    The estimate lags by half a sample (velocity) and one sample (acceleration),
    and on an encoder grid it jumps by one count per sample time; see
    :func:`polynomial_segments` for the smoothed version.

    Examples
    --------
    >>> est = backward_difference([0, 1, 2, 3, 4], [0.0, 1.0, 3.0, 6.0, 10.0])
    >>> est.velocity.tolist(), est.acceleration.tolist()
    ([1.0, 1.0, 2.0, 3.0, 4.0], [0.0, 0.0, 1.0, 1.0, 1.0])
    """
    rec = _record(t, position)
    vel = _backward(rec.q, rec.ts)
    return DerivativeEstimate(t=rec.t, position=rec.q, velocity=vel,
                              acceleration=_backward(vel, rec.ts), method="backward_difference")


def _segments(moving: np.ndarray) -> list[tuple[int, int]]:
    """Half-open index ranges [start, stop) of the runs of True in ``moving``."""
    m = np.concatenate(([False], moving, [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(m))
    return list(zip(edges[::2], edges[1::2]))


@functools.lru_cache(maxsize=4096)
def _polyfit_determined(n: int, degree: int) -> bool:
    # the times map to [-1, 1] whatever Ts is: the rank depends on n and the degree only
    return _determined(lambda: np.polynomial.Polynomial.fit(np.linspace(-1.0, 1.0, n),
                                                            np.zeros(n), degree))


def _segment_fit(x, y, degree):
    """``Polynomial.fit`` of one window, refused (naming the limit) where it is rank deficient."""
    if not _polyfit_determined(x.size, degree):
        top = _highest(lambda d: _polyfit_determined(x.size, d), 1, degree)
        raise ValueError(f"order {degree} is not determined in double precision on a segment of "
                         f"{x.size} samples (the least-squares fit is rank deficient); order must "
                         f"be at most {top}")
    return np.polynomial.Polynomial.fit(x, y, degree)


def polynomial_segments(t, position, *, order: int = 6, window: int = 200,
                        overlap: int = 100, min_samples: int | None = None) -> DerivativeEstimate:
    """The paper's estimator: piecewise least-squares polynomials on the moving segments.

    1. backward-difference velocity ``vb[k] = (q[k]-q[k-1])/Ts``;
    2. split the record into segments where ``vb != 0`` (the axis moves);
    3. on each segment fit ``vb`` with a least-squares polynomial of degree ``order``
       in time; segments longer than ``window`` samples are covered by windows of
       ``window`` samples overlapping by ``overlap``, blended with triangular weights;
    4. velocity = the polynomial, acceleration = its analytic derivative.

    Outside the segments velocity and acceleration are zero (the axis is at rest).

    Parameters
    ----------
    t : array_like, shape (N,)
        Uniform sample times [s].
    position : array_like, shape (N,)
        Measured (encoder) position [rad] or [m].
    order : int
        Polynomial degree (the paper: 6).
    window : int
        Longest stretch one polynomial covers [samples].
    overlap : int
        Overlap of consecutive windows, ``0 <= overlap < window`` [samples].
    min_samples : int, optional
        Shorter segments get a polynomial of degree ``len - 2`` (at least 1), and
        segments of one or two samples keep the backward difference with zero
        acceleration; default ``order + 2``.

    Notes
    -----
    The backward difference is the velocity at the middle of the sample interval,
    so each polynomial is fitted against the mid-times ``t[k] - Ts/2`` and then
    evaluated at ``t[k]``: this removes the half-sample lag a fit against ``t[k]``
    would keep (a choice of ours; the paper does not say).  The polynomial is not
    constrained at the segment ends (no continuity between windows other than the
    blending), and a stop in the middle of a fast motion is not detected unless the
    encoder count stops changing for a whole sample.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) * 0.002
    >>> q = np.round(np.sin(t) / 1e-4) * 1e-4          # 1e-4 rad encoder grid
    >>> est = polynomial_segments(t, q)
    >>> bool(np.max(np.abs(est.velocity[10:-10] - np.cos(t[10:-10]))) < 5e-3)
    True
    """
    rec = _record(t, position)
    t, q, ts = rec.t, rec.q, rec.ts
    order = v.integer("order", order, low=1)
    window = v.integer("window", window, low=order + 2)
    overlap = v.integer("overlap", overlap, low=0, high=window - 1)
    min_samples = order + 2 if min_samples is None else v.integer("min_samples", min_samples)
    vb = np.empty_like(q)
    vb[1:] = np.diff(q) / ts
    vb[0] = vb[1]
    tm = t - ts / 2.0  # mid-interval times of the backward differences
    vel = np.zeros_like(q)
    acc = np.zeros_like(q)
    for start, stop in _segments(vb != 0.0):
        n = stop - start
        if n <= 2:
            vel[start:stop] = vb[start:stop]
            continue
        deg = order if n >= min_samples else max(1, n - 2)
        if n <= window:
            windows = [(start, stop)]
        else:
            stride = window - overlap
            starts = list(range(start, stop - window + 1, stride))
            if starts[-1] + window < stop:
                starts.append(stop - window)
            windows = [(s, s + window) for s in starts]
        wsum = np.zeros(n)
        vsum = np.zeros(n)
        asum = np.zeros(n)
        for s, e in windows:
            f0 = max(s, 1)  # sample 0 has no backward difference (vb[0] is a copy)
            p = _segment_fit(tm[f0:e], vb[f0:e], min(deg, e - f0 - 1))
            dp = p.deriv()
            m = e - s
            if len(windows) == 1:
                w = np.ones(m)
            else:  # triangular weights: the centre of a window is trusted most
                w = 1.0 - np.abs((np.arange(m) + 0.5) / m * 2.0 - 1.0) + 1e-9
            sl = slice(s - start, e - start)
            wsum[sl] += w
            vsum[sl] += w * p(t[s:e])
            asum[sl] += w * dp(t[s:e])
        vel[start:stop] = vsum / wsum
        acc[start:stop] = asum / wsum
    return DerivativeEstimate(t=t, position=q, velocity=vel, acceleration=acc,
                              method="polynomial_segments")


def savitzky_golay(t, position, *, window_length: int = 51, polyorder: int = 3) -> DerivativeEstimate:
    """Savitzky-Golay smoothing and differentiation (:func:`scipy.signal.savgol_filter`).

    Parameters
    ----------
    t : array_like, shape (N,)
        Uniform sample times [s].
    position : array_like, shape (N,)
        Measured position [rad] or [m].
    window_length : int
        Odd window length [samples].
    polyorder : int
        Local polynomial degree, at least 2 for an acceleration.

    Notes
    -----
    Ends are handled by scipy's ``mode="interp"`` (a polynomial fitted to the last
    window), which is noisier than the interior.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(200) * 0.01
    >>> est = savitzky_golay(t, t**2, window_length=11, polyorder=3)
    >>> bool(np.allclose(est.acceleration, 2.0))
    True
    """
    rec = _record(t, position)
    window_length = v.integer("window_length", window_length, low=3, high=rec.q.size)
    if window_length % 2 != 1:
        raise ValueError(f"window_length must be odd, got {window_length}")
    polyorder = v.integer("polyorder", polyorder, low=2, high=window_length - 1)

    def fits(order):  # the filter itself (interior and the end fits of mode="interp") on zeros
        return _determined(lambda: signal.savgol_filter(np.zeros(window_length), window_length,
                                                        order, deriv=2, mode="interp"))

    if not fits(polyorder):
        raise ValueError(f"polyorder {polyorder} is not determined in double precision on a window "
                         f"of {window_length} samples (the local fit is rank deficient); polyorder "
                         f"must be at most {_highest(fits, 2, polyorder)}")
    kw = dict(window_length=window_length, polyorder=polyorder, delta=rec.ts, mode="interp")
    return DerivativeEstimate(
        t=rec.t, position=signal.savgol_filter(rec.q, deriv=0, **kw),
        velocity=signal.savgol_filter(rec.q, deriv=1, **kw),
        acceleration=signal.savgol_filter(rec.q, deriv=2, **kw), method="savitzky_golay")


#: Largest Butterworth order :func:`butterworth_central` accepts at any cut-off (lower
#: cut-offs allow less: the check is made per call).
MAX_BUTTERWORTH_ORDER = 20


def butterworth_central(t, position, *, cutoff: float, order: int = 4) -> DerivativeEstimate:
    """Zero-phase Butterworth low-pass, then central differences twice (EMPS recipe).

    Parameters
    ----------
    t : array_like, shape (N,)
        Uniform sample times [s].
    position : array_like, shape (N,)
        Measured position [rad] or [m].
    cutoff : float
        Cut-off frequency of the low-pass [Hz]; below the Nyquist frequency.  The
        rule of thumb of the EMPS report is 5x the closed-loop bandwidth (100 Hz there).
    order : int
        Filter order (applied twice, forward and backward), at most
        :data:`MAX_BUTTERWORTH_ORDER` and at most what stays numerically accurate at
        ``cutoff`` (the message of a refusal says how far: 8 at a tenth of Nyquist,
        4 at a hundredth).

    Notes
    -----
    Velocity and acceleration are :func:`central_difference` of the filtered
    position and of the velocity, so the first and last few dozen samples carry
    filter and difference end effects; the EMPS recipe drops the first 49.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(2000) * 0.001
    >>> est = butterworth_central(t, np.sin(2 * np.pi * t), cutoff=100.0)
    >>> bool(np.allclose(est.velocity[100:-100], 2 * np.pi * np.cos(2 * np.pi * t[100:-100]), atol=1e-3))
    True
    """
    rec = _record(t, position)
    nyq = 0.5 / rec.ts
    cutoff = v.real("cutoff", cutoff, unit="Hz")
    if not 0 < cutoff < nyq:
        raise ValueError(f"cutoff must lie in (0, {nyq:g}) Hz (below Nyquist), got {cutoff!r}")
    order = v.integer("order", order, low=1, high=MAX_BUTTERWORTH_ORDER)
    if not _ba_accurate(signal.butter, order, cutoff / nyq):
        top = max((n for n in range(1, order) if _ba_accurate(signal.butter, n, cutoff / nyq)),
                  default=0)
        raise ValueError(f"order {order} at cutoff {cutoff:g} Hz ({cutoff / nyq:.3g} of Nyquist) is "
                         f"numerically unstable (the filter's coefficients lose it to round-off); "
                         f"at this cutoff order must be at most {top}")
    b, a = signal.butter(order, cutoff / nyq)
    qf = zero_phase_filter(b, a, rec.q)
    vel = central_difference(qf, rec.ts)
    return DerivativeEstimate(t=rec.t, position=qf, velocity=vel,
                              acceleration=central_difference(vel, rec.ts),
                              method="butterworth_central")


#: Estimators by name (for the CLI and :func:`estimate`).
def at_rest(position, *, guard: int = 2) -> np.ndarray:
    """True where the encoder reads the same value ``guard`` samples before and after.

    A sample at rest by this test had no motion around it: the friction there is the
    reaction holding the joint (``Tat = Tm``).  A sample whose velocity estimate is 0 but
    whose encoder moves within ``guard`` samples is a breakaway (or a reversal): the
    friction is at its breakaway level, not ``Tm``.  The first and last ``guard`` samples
    are never at rest (their neighbourhood is not recorded).

    Parameters
    ----------
    position : array_like
        Encoder readings [rad] (or [m]).
    guard : int
        Samples on each side, >= 1.

    Examples
    --------
    >>> at_rest([0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1], guard=2).astype(int).tolist()
    [0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0]
    """
    x = v.array("position", position)
    guard = v.integer("guard", guard, low=1)
    n = x.size
    out = np.zeros(n, dtype=bool)
    if n > 2 * guard:
        core = np.ones(n - 2 * guard, dtype=bool)
        mid = x[guard:n - guard]
        for d in range(1, guard + 1):
            core &= (x[guard - d:n - guard - d] == mid) & (x[guard + d:n - guard + d] == mid)
        out[guard:n - guard] = core
    return out


ESTIMATORS = {
    "backward_difference": backward_difference,
    "polynomial_segments": polynomial_segments,
    "savitzky_golay": savitzky_golay,
    "butterworth_central": butterworth_central,
}


def estimate(t, position, method: str = "polynomial_segments", **options) -> DerivativeEstimate:
    """Run the estimator named ``method`` with its keyword ``options``.

    ``butterworth_central`` without a ``cutoff`` uses a fifth of the Nyquist
    frequency (100 Hz at 1 kHz, the EMPS choice).
    """
    v.choice("method", method, ESTIMATORS)
    if method == "butterworth_central" and "cutoff" not in options:
        ts = _record(t, position).ts
        options = dict(options, cutoff=0.1 / ts)
    return ESTIMATORS[method](t, position, **options)
