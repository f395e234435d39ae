"""The network's parameter vectors and the two compiled forward passes that read them.

Two flat float vectors carry a 2-H-1 network into compiled code:

**theta**, the trainable parameters (what the trainers optimise), ``4H + 1`` entries::

    theta = [ w1 row-major (2H) | b1 (H) | w2 (H) | b2 ]
              0                   2H       3H       4H

:func:`pack` / :func:`unpack` convert; :func:`forward_theta` is the numba forward
pass on scaled inputs that the training kernels use.

**p**, the *compiled-loop vector* that :meth:`fricctl.compensators.NNCompensator.compiled`
hands to the closed-loop kernel, ``P_W1 + 4H`` entries with the named offsets
below (the tail from :data:`P_W1` on is ``theta`` without ``b2``)::

    P_HIDDEN        H (a float)
    P_INPUT_OFFSET  Tm [N*m], omega [rad/s]          (2 entries)
    P_INPUT_SCALE   Tm [N*m], omega [rad/s]          (2 entries)
    P_OUTPUT_OFFSET [N*m]
    P_OUTPUT_SCALE  [N*m]
    P_CLIP          1.0: clip the inputs to the envelope first, 0.0: do not
    P_ENVELOPE_LOW  Tm [N*m], omega [rad/s]          (2 entries)
    P_ENVELOPE_HIGH Tm [N*m], omega [rad/s]          (2 entries)
    P_B2            output bias
    P_W1            w1 row-major (2H), then b1 (H), then w2 (H)

:func:`pack_compiled` builds it; :func:`forward_packed` evaluates it, with the
arithmetic of the simulator's compensator kernel (bit for bit).

This module needs numpy and numba only (no CasADi, no matplotlib) and sits below the
sampled loop (:mod:`fricctl.compensators` and :mod:`fricctl.simulate` read it), while the
network package :mod:`fricctl.nn` (the network, its trainers, files and C export) sits above
it; ``fricctl.nn.layout`` is the same module under the network's name.

Examples
--------
>>> theta = pack([[1.0, 2.0]], [3.0], [4.0], 5.0)
>>> theta.tolist()
[1.0, 2.0, 3.0, 4.0, 5.0]
>>> unpack(theta, 1).w2.tolist(), compiled_size(1)
([4.0], 17)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._jit import jit
from . import _validate as v

__all__ = ["Weights", "theta_size", "pack", "unpack", "forward_theta",
           "NET_ATTRIBUTES", "P_HIDDEN", "P_INPUT_OFFSET", "P_INPUT_SCALE", "P_OUTPUT_OFFSET",
           "P_OUTPUT_SCALE", "P_CLIP", "P_ENVELOPE_LOW", "P_ENVELOPE_HIGH", "P_B2", "P_W1",
           "compiled_size", "pack_compiled", "forward_packed"]

# -- theta: the trainable parameters ----------------------------------------------


@dataclass(frozen=True, kw_only=True, eq=False)
class Weights:
    """The trainable weights of a 2-H-1 net, unpacked from ``theta`` (views, not copies)."""

    w1: np.ndarray
    """Input-to-hidden weights, shape (H, 2) [-]."""
    b1: np.ndarray
    """Hidden biases, shape (H,) [-]."""
    w2: np.ndarray
    """Hidden-to-output weights, shape (H,) [-]."""
    b2: float
    """Output bias [-]."""


def theta_size(hidden: int) -> int:
    """Length of ``theta`` for ``hidden`` units: ``4*H + 1``."""
    return 4 * v.integer("hidden", hidden, low=1) + 1


def pack(w1, b1, w2, b2) -> np.ndarray:
    """``theta = [w1 row-major (2H), b1 (H), w2 (H), b2]`` as a new float array."""
    return np.concatenate([np.ravel(w1), b1, w2, [b2]]).astype(float)


def unpack(theta, hidden: int) -> Weights:
    """Inverse of :func:`pack` (``w1``, ``b1``, ``w2`` are views of ``theta``)."""
    h = v.integer("hidden", hidden, low=1)
    theta = v.array("theta", theta, size=4 * h + 1)
    return Weights(w1=theta[:2 * h].reshape(h, 2), b1=theta[2 * h:3 * h],
                   w2=theta[3 * h:4 * h], b2=float(theta[4 * h]))


@jit
def forward_theta(theta, h, x0, x1, hid):
    """Scaled output ``yn`` of the net ``theta`` with ``h`` hidden units at the scaled inputs
    ``(x0, x1)``; writes the hidden activations into ``hid`` (length >= h).

    The one forward pass of the training kernels (back-propagation reads ``hid``).
    """
    yn = theta[4 * h]
    for j in range(h):
        hid[j] = math.tanh(theta[2 * j] * x0 + theta[2 * j + 1] * x1 + theta[2 * h + j])
        yn += theta[3 * h + j] * hid[j]
    return yn


# -- p: the compiled-loop vector ----------------------------------------------------
P_HIDDEN = 0
P_INPUT_OFFSET = 1
P_INPUT_SCALE = 3
P_OUTPUT_OFFSET = 5
P_OUTPUT_SCALE = 6
P_CLIP = 7
P_ENVELOPE_LOW = 8
P_ENVELOPE_HIGH = 10
P_B2 = 12
P_W1 = 13

#: What an estimator needs to run in the compiled loop: a
#: :class:`~fricctl.nn.net.FrictionNet`, or any object with these attributes of
#: the same meaning and shapes (``w1`` (H, 2), ``b1``, ``w2`` (H,), the rest as in
#: FrictionNet).
NET_ATTRIBUTES = ("w1", "b1", "w2", "b2", "input_offset", "input_scale", "output_offset",
                  "output_scale", "envelope_low", "envelope_high")


def compiled_size(hidden: int) -> int:
    """Length of the compiled-loop vector for ``hidden`` units: ``P_W1 + 4*H``."""
    return P_W1 + 4 * v.integer("hidden", hidden, low=1)


def pack_compiled(net, clip: bool) -> np.ndarray:
    """The compiled-loop vector ``p`` of ``net`` (layout in the module docstring).

    Parameters
    ----------
    net : FrictionNet or object with :data:`NET_ATTRIBUTES`
        The network.
    clip : bool
        Whether :func:`forward_packed` clips the inputs to the net's envelope.

    Returns
    -------
    numpy.ndarray
        ``compiled_size(H)`` floats; ``forward_packed(p, tm, omega)`` equals
        ``net(tm, omega, clip=clip)`` to rounding.
    """
    missing = [a for a in NET_ATTRIBUTES if not hasattr(net, a)]
    if missing:
        raise ValueError(f"net must have the attributes of a FrictionNet; missing "
                         f"{', '.join(missing)}")
    clip = v.flag("clip", clip)
    w1 = v.array("net.w1", net.w1, ndim=2)
    if w1.shape[1] != 2 or w1.shape[0] < 1:
        raise ValueError(f"net.w1 must have shape (H, 2) with H >= 1, got {w1.shape}")
    h = w1.shape[0]
    p = np.empty(compiled_size(h))
    p[P_HIDDEN] = h
    for name, at in (("input_offset", P_INPUT_OFFSET), ("input_scale", P_INPUT_SCALE),
                     ("envelope_low", P_ENVELOPE_LOW), ("envelope_high", P_ENVELOPE_HIGH)):
        p[at:at + 2] = v.array(f"net.{name}", getattr(net, name), size=2)
    p[P_OUTPUT_OFFSET] = v.real("net.output_offset", net.output_offset)
    p[P_OUTPUT_SCALE] = v.real("net.output_scale", net.output_scale)
    p[P_CLIP] = 1.0 if clip else 0.0
    p[P_B2] = v.real("net.b2", net.b2)
    p[P_W1:P_W1 + 2 * h] = w1.ravel()
    p[P_W1 + 2 * h:P_W1 + 3 * h] = v.array("net.b1", net.b1, size=h)
    p[P_W1 + 3 * h:] = v.array("net.w2", net.w2, size=h)
    return p


@jit
def forward_packed(p, tm, omega):
    """Friction estimate [N*m] of the compiled-loop vector ``p`` at ``(tm [N*m], omega [rad/s])``.

    Scalar inputs, scalar output; clips the inputs first when ``p[P_CLIP] != 0``.
    The arithmetic (and its order) is the simulator's compensator kernel's, so a
    call from that kernel gives the same bits.
    """
    h = int(p[P_HIDDEN])
    x0 = tm
    x1 = omega
    if p[P_CLIP] != 0.0:
        x0 = min(max(x0, p[P_ENVELOPE_LOW]), p[P_ENVELOPE_HIGH])
        x1 = min(max(x1, p[P_ENVELOPE_LOW + 1]), p[P_ENVELOPE_HIGH + 1])
    x0 = (x0 - p[P_INPUT_OFFSET]) / p[P_INPUT_SCALE]
    x1 = (x1 - p[P_INPUT_OFFSET + 1]) / p[P_INPUT_SCALE + 1]
    y = p[P_B2]
    w1 = P_W1
    b1 = P_W1 + 2 * h
    w2 = b1 + h
    for j in range(h):
        y += p[w2 + j] * math.tanh(p[w1 + 2 * j] * x0 + p[w1 + 2 * j + 1] * x1 + p[b1 + j])
    return y * p[P_OUTPUT_SCALE] + p[P_OUTPUT_OFFSET]
