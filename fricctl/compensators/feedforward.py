r"""Model-based feedforward: the identified static friction curve (Stribeck inverse)
evaluated at the velocity the loop has.

.. math::
    \hat T_{at} = \operatorname{sign}(w)\,\bigl(F_c + (F_s - F_c)\,e^{-(|w|/w_s)^\delta}\bigr) + b\,w,

per direction, with the friction scale applied; ``w`` is the measured velocity
``omega_hat_k`` (default) or the reference velocity ``(r_k - r_{k-1})/Ts`` (``velocity=
"reference"``: the friction of the motion the loop is asked for, free of the encoder's
quantisation and of the loop's own error; its state is ``r_{k-1}``).

Provenance of the parameters: every one is the identified model's
(:class:`~fricctl.plant.JointModel` ``friction``: ``coulomb_pos/neg`` = Fc,
``stribeck_pos/neg`` = Fs - Fc, ``stribeck_velocity`` = ws, ``stribeck_exponent`` = delta
(2 in the paper's model), ``viscous_pos/neg`` = b), times its ``scale``.  Nothing is tuned.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .._jit import jit
from .base import CCode, Compensator, CompiledCompensator, Entry, friction_of, static_curve

__all__ = ["StaticFeedforward", "ENTRY", "VELOCITIES"]

#: Kind id in the compiled loop.
KIND = 3
#: The velocities the curve can be evaluated at.
VELOCITIES = ("measured", "reference")
# parameter layout
(P_FC_POS, P_FC_NEG, P_DS_POS, P_DS_NEG, P_B_POS, P_B_NEG, P_WS, P_EXPONENT, P_DEADBAND,
 P_REFERENCE) = range(10)
# state layout: previous reference, 1 once it is known
X_R_PREV, X_STARTED = range(2)


@dataclass(frozen=True, kw_only=True)
class StaticFeedforward(Compensator):
    """Static-model friction feedforward (Coulomb + Stribeck + viscous), per direction.

    Parameters
    ----------
    coulomb_pos, coulomb_neg : float
        Fc per direction, positive magnitudes [N*m].
    stribeck_pos, stribeck_neg : float
        Fs - Fc per direction (the Stribeck excess at rest) [N*m].
    viscous_pos, viscous_neg : float
        b per direction [N*m*s/rad].
    stribeck_velocity : float
        ws [rad/s] (> 0).
    stribeck_exponent : float
        delta [-] (> 0; 2 is the Gaussian curve).
    deadband : float
        ``|w|`` at or below it gives 0 [rad/s] (0: only ``w = 0`` exactly).
    velocity : {"measured", "reference"}
        Evaluate at ``omega_hat_k`` or at ``(r_k - r_{k-1})/Ts``.
    scale : float
        Compensation scale s [-].

    Notes
    -----
    Static curve only: no presliding (see the LuGre observer), no static excess beyond the
    Stribeck peak, no drag, load-dependent or position terms.  At rest (``w = 0``) it gives 0:
    it does not help a joint break away; with ``velocity="reference"`` it gives the friction
    of the planned motion, before the joint moves.
    """

    coulomb_pos: float
    """Fc for positive velocity [N*m]."""
    coulomb_neg: float
    """Magnitude of Fc for negative velocity [N*m]."""
    stribeck_pos: float = 0.0
    """Fs - Fc for positive velocity [N*m]."""
    stribeck_neg: float = 0.0
    """Fs - Fc for negative velocity [N*m]."""
    viscous_pos: float = 0.0
    """b for positive velocity [N*m*s/rad]."""
    viscous_neg: float = 0.0
    """b for negative velocity [N*m*s/rad]."""
    stribeck_velocity: float = 1.0
    """ws [rad/s]."""
    stribeck_exponent: float = 2.0
    """delta [-]."""
    deadband: float = 0.0
    """Velocity dead band [rad/s]."""
    velocity: str = "measured"
    """``"measured"`` or ``"reference"``."""
    scale: float = 1.0
    """Compensation scale s [-]."""
    name: str = "feedforward"
    """Label in results and plots."""

    def __post_init__(self):
        for name in ("coulomb_pos", "coulomb_neg", "stribeck_pos", "stribeck_neg", "viscous_pos",
                     "viscous_neg", "deadband", "scale"):
            v.real(name, getattr(self, name), nonneg=True)
        v.real("stribeck_velocity", self.stribeck_velocity, positive=True, unit="rad/s")
        v.real("stribeck_exponent", self.stribeck_exponent, positive=True)
        v.choice("velocity", self.velocity, VELOCITIES)
        v.text("name", self.name)

    @property
    def stateful(self) -> bool:
        return self.velocity == "reference"

    @classmethod
    def from_model(cls, model, *, velocity: str = "measured", deadband: float = 0.0,
                   scale: float = 1.0) -> "StaticFeedforward":
        """The curve of an identified model (JointModel, ActuatorParams, FrictionModel or law).

        Examples
        --------
        >>> from fricctl.params import paper_actuator
        >>> ff = StaticFeedforward.from_model(paper_actuator())
        >>> round(float(ff(0.0, 0.02)), 6)       # Fc + (Fs-Fc)/e + b*ws at w = ws
        0.157582
        """
        fr = friction_of(model)
        fcp, dsp, bp, ws, ex = static_curve(fr, 1)
        fcn, dsn, bn, _, _ = static_curve(fr, -1)
        if fcp + dsp + bp <= 0.0 and fcn + dsn + bn <= 0.0:
            raise ValueError("the model has no Coulomb, Stribeck or viscous friction: the "
                             "feedforward would add nothing")
        return cls(coulomb_pos=fcp, coulomb_neg=fcn, stribeck_pos=dsp, stribeck_neg=dsn,
                   viscous_pos=bp, viscous_neg=bn, stribeck_velocity=ws, stribeck_exponent=ex,
                   deadband=deadband, velocity=velocity, scale=scale,
                   name="feedforward" if velocity == "measured" else "feedforward (reference)")

    def _params(self) -> np.ndarray:
        return np.array([self.coulomb_pos, self.coulomb_neg, self.stribeck_pos, self.stribeck_neg,
                         self.viscous_pos, self.viscous_neg, self.stribeck_velocity,
                         self.stribeck_exponent, self.deadband,
                         1.0 if self.velocity == "reference" else 0.0])

    def __call__(self, tm, omega_hat):
        """The curve at ``omega_hat`` [rad/s] (``velocity="measured"`` only) [N*m]."""
        if self.stateful:
            return super().__call__(tm, omega_hat)
        p = self._params()
        w, _ = np.broadcast_arrays(np.asarray(omega_hat, dtype=float), np.asarray(tm, dtype=float))
        return np.vectorize(lambda x: curve(p, x))(w).astype(float)

    def compiled(self):
        return CompiledCompensator(kind=KIND, params=self._params(), state=np.zeros(2))


@jit
def curve(p, w):
    """The static curve of parameter vector ``p`` at velocity ``w`` [N*m]."""
    if w > p[P_DEADBAND]:
        s, fc, ds, b = 1.0, p[P_FC_POS], p[P_DS_POS], p[P_B_POS]
    elif w < -p[P_DEADBAND]:
        s, fc, ds, b = -1.0, p[P_FC_NEG], p[P_DS_NEG], p[P_B_NEG]
    else:
        return 0.0
    u = abs(w) / p[P_WS]
    dip = math.exp(-u * u) if p[P_EXPONENT] == 2.0 else math.exp(-(u ** p[P_EXPONENT]))
    return b * w + s * (fc + ds * dip)


def step(p, x, wh, r, ts):
    """The curve at ``omega_hat_k``, or at ``(r_k - r_{k-1})/Ts`` (0 at the first sample)."""
    w = wh
    if p[P_REFERENCE] != 0.0:
        w = (r - x[X_R_PREV]) / ts if x[X_STARTED] != 0.0 else 0.0
        x[X_R_PREV] = r
        x[X_STARTED] = 1.0
    return curve(p, w)


def c_code(comp: StaticFeedforward) -> CCode:
    p = comp._params()
    names = ("fc_pos", "fc_neg", "ds_pos", "ds_neg", "b_pos", "b_neg", "ws", "exponent",
             "deadband", "reference")
    docs = ("Fc, w > 0 [N*m]", "Fc, w < 0 [N*m]", "Fs - Fc, w > 0 [N*m]", "Fs - Fc, w < 0 [N*m]",
            "b, w > 0 [N*m*s/rad]", "b, w < 0 [N*m*s/rad]", "Stribeck velocity ws [rad/s]",
            "Stribeck exponent [-]", "velocity dead band [rad/s]",
            "1: at the reference velocity, 0: at omega_hat")
    return CCode(
        params=tuple(zip(names, p, docs)),
        state=(("r_prev", "previous reference r [rad]"),
               ("started", "1 once r_prev is known")),
        init="    st->r_prev = 0.0;\n    st->started = 0.0;\n",
        step="""    double w = omega_hat, s, fc, ds, b, u, dip;
    (void)tm; (void)y; (void)tc;
    if (P_reference != 0.0) {
        w = st->started != 0.0 ? (r - st->r_prev) / st->ts : 0.0;
        st->r_prev = r;
        st->started = 1.0;
    }
    if (w > P_deadband) { s = 1.0; fc = P_fc_pos; ds = P_ds_pos; b = P_b_pos; }
    else if (w < -P_deadband) { s = -1.0; fc = P_fc_neg; ds = P_ds_neg; b = P_b_neg; }
    else return 0.0;
    u = fabs(w) / P_ws;
    dip = P_exponent == 2.0 ? exp(-u * u) : exp(-pow(u, P_exponent));
    return b * w + s * (fc + ds * dip);
""")


def _make(model, design, sample_time, *, velocity: str = "measured", deadband: float = 0.0,
          scale: float = 1.0):
    return StaticFeedforward.from_model(model, velocity=velocity, deadband=deadband, scale=scale)


ENTRY = Entry(name="feedforward", kind=KIND, cls=StaticFeedforward, make=_make, step=step,
              c_code=c_code,
              description="the identified static curve Fc + (Fs-Fc) exp(-(w/ws)^2) + b w at the "
                          "loop's velocity (or the reference's)")
