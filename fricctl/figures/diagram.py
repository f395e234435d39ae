"""Block diagram of the compensated loop of paper Eq. (3), drawn with patches and arrows.

The crux of Chapters 5 and 6 is a feedback the paper's Fig. 3 hides: the motor
torque the compensator commands, ``Tm(k+1) = Tc(k) + s*T^at(k)``, is itself an
input of the net that computes ``T^at(k) = net(Tm(k), omega_hat(k))`` -- through a
one-sample delay ``z^-1``.  While the joint is stuck the encoder is still,
``omega_hat = 0``, and that inner loop alone sets the motor torque.
"""

from __future__ import annotations

from matplotlib.patches import Circle, FancyBboxPatch

from .. import _validate as v
from ._common import get_ax

__all__ = ["plot_compensation_loop"]

_BOX = {"boxstyle": "round,pad=0.02,rounding_size=0.08", "facecolor": "white", "edgecolor": "0.15",
        "linewidth": 1.2}
_ARROW = {"arrowstyle": "-|>", "color": "0.15", "linewidth": 1.1, "shrinkA": 0, "shrinkB": 0,
          "mutation_scale": 11}


def _box(ax, x, y, w, h, text, *, fontsize=9, highlight=False):
    """A labelled block centred at (x, y); returns its (left, right, bottom, top)."""
    style = dict(_BOX, facecolor="#fde9c8" if highlight else "white")
    ax.add_patch(FancyBboxPatch((x - w / 2, y - h / 2), w, h, **style))
    ax.text(x, y, text, ha="center", va="center", fontsize=fontsize)
    return x - w / 2, x + w / 2, y - h / 2, y + h / 2


def _sum(ax, x, y, r=0.16, signs=()):
    """A summing junction at (x, y); ``signs`` are (text, dx, dy) placed beside it."""
    ax.add_patch(Circle((x, y), r, facecolor="white", edgecolor="0.15", linewidth=1.2))
    for text, dx, dy in signs:
        ax.text(x + dx, y + dy, text, ha="center", va="center", fontsize=9)
    return r


def _path(ax, points, *, arrow=True):
    """A polyline through ``points``, with an arrowhead on its last segment."""
    for (x0, y0), (x1, y1) in zip(points[:-2], points[1:-1]):
        ax.plot([x0, x1], [y0, y1], color="0.15", lw=1.1, solid_capstyle="butt")
    (x0, y0), (x1, y1) = points[-2], points[-1]
    if arrow:
        ax.annotate("", xy=(x1, y1), xytext=(x0, y0), arrowprops=_ARROW)
    else:
        ax.plot([x0, x1], [y0, y1], color="0.15", lw=1.1)


def _dot(ax, x, y):
    ax.plot([x], [y], "o", color="0.15", ms=3.5)


def plot_compensation_loop(ax=None, *, closed: bool = False):
    """Draw the NN-compensated loop of paper Eq. (3) as a block diagram.

    ``Tc(k) + s*T^at(k)`` -> ZOH -> joint ``I q'' = Tm - Tat`` -> encoder ->
    velocity estimate ``omega_hat`` -> the net ``T^at(Tm, omega_hat)`` -> ``s`` ->
    back to the sum; the commanded ``Tm`` enters the net through a one-sample delay
    ``z^-1`` (highlighted: the inner loop that sets ``Tm`` while the joint is stuck).

    Parameters
    ----------
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (a new figure if omitted); its frame and ticks are removed.
    closed : bool
        Also draw the position controller ``Tc = Kp (r - q_hat) - Kd omega_hat``
        (P: ``Kd = 0``) that closes the outer loop (Chapter 6); default the open
        loop of Figs. 9 and 10.

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    Only the signal flow is drawn: the saturation of ``Tm`` at Tmax, the optional
    clipping of the net's inputs to its envelope and the encoder's quantisation are
    left out (each is a property of the named block).
    """
    closed = v.flag("closed", closed)
    ax = get_ax(ax)
    y_fwd, y_fb, y_delay = 2.0, 0.0, 1.0
    h = 0.62
    # forward path: sum -> ZOH -> joint -> encoder
    xs = 1.3
    _sum(ax, xs, y_fwd, signs=(("+", -0.28, 0.16), ("+", 0.16, -0.3)))
    zl, zr, _, _ = _box(ax, 3.0, y_fwd, 0.8, h, "ZOH\n$T_s$")
    jl, jr, _, _ = _box(ax, 5.0, y_fwd, 1.9, h, "joint\n$I\\,\\ddot q = T_m - T_{at}$")
    el, er, _, _ = _box(ax, 7.3, y_fwd, 1.1, h, "encoder\n$\\hat q(k)$")
    _path(ax, [(xs + 0.16, y_fwd), (zl, y_fwd)])
    ax.text(1.95, y_fwd + 0.12, "$T_m(k{+}1)$", ha="center", va="bottom", fontsize=8)
    _path(ax, [(zr, y_fwd), (jl, y_fwd)])
    ax.text((zr + jl) / 2, y_fwd + 0.08, "$T_m(t)$", ha="center", va="bottom", fontsize=8)
    _path(ax, [(jr, y_fwd), (el, y_fwd)])
    ax.text((jr + el) / 2, y_fwd + 0.08, "$q(t)$", ha="center", va="bottom", fontsize=8)
    # feedback path: encoder -> velocity estimate -> net -> s -> sum
    vl, vr, vb, vt = _box(ax, 7.3, y_fb, 1.75, h, "velocity estimate\n$\\hat\\omega(k)$",
                          fontsize=8)
    _path(ax, [(7.3, y_fwd - h / 2), (7.3, vt)])
    nl, nr, nb, nt = _box(ax, 4.4, y_fb, 1.8, h, "net\n$\\hat T_{at}(T_m, \\hat\\omega)$")
    _path(ax, [(vl, y_fb), (nr, y_fb)])
    ax.text((vl + nr) / 2, y_fb + 0.08, "$\\hat\\omega(k)$", ha="center", va="bottom", fontsize=8)
    # a gain, written as one: a block labelled "s" alone reads as a differentiator
    sl, sr, sb, st = _box(ax, xs, y_fb, 0.7, 0.5, "$\\times s$")
    _path(ax, [(nl, y_fb), (sr, y_fb)])
    ax.text((nl + sr) / 2, y_fb + 0.08, "$\\hat T_{at}(k)$", ha="center", va="bottom", fontsize=8)
    _path(ax, [(xs, st), (xs, y_fwd - 0.16)])
    # the crux: Tm back into the net through one sample of delay
    xb = 2.15
    _dot(ax, xb, y_fwd)
    dl, dr, db, dt = _box(ax, 3.2, y_delay, 0.7, 0.46, "$z^{-1}$", fontsize=10, highlight=True)
    _path(ax, [(xb, y_fwd), (xb, y_delay), (dl, y_delay)])
    _path(ax, [(dr, y_delay), (4.0, y_delay), (4.0, nt)])
    ax.text(4.07, (y_delay + nt) / 2, "$T_m(k)$", ha="left", va="center", fontsize=8)
    # the output, and the controller of the outer loop
    xo = 8.5
    _path(ax, [(er, y_fwd), (xo, y_fwd)])
    ax.text(xo + 0.05, y_fwd, "$\\hat q$", ha="left", va="center", fontsize=9)
    if closed:
        xc, xr = -0.55, -2.1
        cl, cr, cb, ct = _box(ax, xc, y_fwd, 1.75, h + 0.1,
                              "P / PD\n$K_p(r - \\hat q) - K_d\\hat\\omega$", fontsize=8)
        _sum(ax, xr, y_fwd, signs=(("+", -0.28, 0.16), ("$-$", 0.17, 0.3)))
        ax.text(xr - 0.75, y_fwd, "$r$", ha="center", va="center", fontsize=10)
        _path(ax, [(xr - 0.6, y_fwd), (xr - 0.16, y_fwd)])
        _path(ax, [(xr + 0.16, y_fwd), (cl, y_fwd)])
        _path(ax, [(cr, y_fwd), (xs - 0.16, y_fwd)])
        ax.text(cr + 0.3, y_fwd + 0.08, "$T_c(k)$", ha="center", va="bottom", fontsize=8)
        _dot(ax, 8.2, y_fwd)
        _path(ax, [(8.2, y_fwd), (8.2, 3.0), (xr, 3.0), (xr, y_fwd + 0.16)])
        _dot(ax, 7.3, -0.75 + 0.44)
        _path(ax, [(7.3, vb), (7.3, -0.75), (xc, -0.75), (xc, cb)])
        ax.text(2.5, -0.83, "$\\hat\\omega(k)$ to the D term", ha="center", va="top", fontsize=8)
        ax.set_xlim(-3.1, 9.1)
    else:
        ax.text(xs - 0.75, y_fwd, "$T_c(k)$", ha="center", va="center", fontsize=9)
        _path(ax, [(xs - 0.5, y_fwd), (xs - 0.16, y_fwd)])
        ax.set_xlim(0.2, 9.1)
    ax.set_ylim(-1.1 if closed else -0.5, 3.3 if closed else 2.6)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax
