"""The friction network as C99, ready to drop into a controller: :func:`c_source`, :func:`c_header`.

For the embedded controller of the paper's drive (2 ms sample time): the
generated function costs tens of nanoseconds per call (``benchmarks/bench_nn.py``).
The source is self-contained (only ``<math.h>``, link with ``-lm``); the header
declares its functions, with the units of the axis (rotary N*m, rad/s or linear
N, m/s) in the comments.  The compensator a controller calls once per sample is
``NAME_compensation(tm, omega_hat, s, clip)``: ``s * T^at(Tm, omega_hat)``, the
term added to the control torque, ``Tm(k+1) = Tc(k) + s*T^at(k)`` (paper Eq. 3).
"""

from __future__ import annotations

import json

import numpy as np

from .. import _validate as v
from ..units import units as units_of
from .net import FrictionNet

__all__ = ["c_source", "c_header", "check_c_name", "C_KEYWORDS", "C_LIBRARY_NAMES"]


def _c(x: float) -> str:
    return format(float(x), ".17g")


#: C99 keywords (ISO/IEC 9899:1999, 6.4.1).
C_KEYWORDS = frozenset("""
    auto break case char const continue default do double else enum extern float for goto if
    inline int long register restrict return short signed sizeof static struct switch typedef
    union unsigned void volatile while _Bool _Complex _Imaginary""".split())

#: Functions and macros of the C99 headers a controller including the generated code also
#: includes: <math.h> (which the source includes), <stdlib.h> and <stdio.h> (7.12, 7.20, 7.19).
C_LIBRARY_NAMES = frozenset("""
    acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1
    fabs fdim floor fma fmax fmin fmod frexp hypot ilogb ldexp lgamma llrint llround log log10
    log1p log2 logb lrint lround modf nan nearbyint nextafter nexttoward pow remainder remquo
    rint round scalbln scalbn sin sinh sqrt tan tanh tgamma trunc fpclassify isfinite isinf
    isnan isnormal signbit isgreater isgreaterequal isless islessequal islessgreater
    isunordered HUGE_VAL HUGE_VALF HUGE_VALL INFINITY NAN FP_INFINITE FP_NAN FP_NORMAL
    FP_SUBNORMAL FP_ZERO FP_ILOGB0 FP_ILOGBNAN MATH_ERRNO MATH_ERREXCEPT math_errhandling
    float_t double_t
    abort abs atexit atof atoi atol atoll bsearch calloc div exit free getenv labs ldiv llabs
    lldiv malloc mblen mbstowcs mbtowc qsort rand realloc srand strtod strtof strtol strtold
    strtoll strtoul strtoull system wcstombs wctomb _Exit div_t ldiv_t lldiv_t size_t wchar_t
    EXIT_FAILURE EXIT_SUCCESS MB_CUR_MAX NULL RAND_MAX
    clearerr fclose feof ferror fflush fgetc fgetpos fgets fopen fprintf fputc fputs fread
    freopen fscanf fseek fsetpos ftell fwrite getc getchar gets perror printf putc putchar puts
    remove rename rewind scanf setbuf setvbuf snprintf sprintf sscanf tmpfile tmpnam ungetc
    vfprintf vfscanf vprintf vscanf vsnprintf vsprintf vsscanf stdin stdout stderr FILE fpos_t
    EOF BUFSIZ FILENAME_MAX FOPEN_MAX L_tmpnam SEEK_CUR SEEK_END SEEK_SET TMP_MAX errno
    main""".split())


def check_c_name(name) -> str:
    """``name`` if the generated code can use it as its function name (and prefix), else a
    ValueError saying why: not an ASCII identifier, a C keyword, a name of the C library
    (``tanh``: "conflicting types for 'tanh'"), or reserved to the implementation (a
    leading underscore followed by a capital or another underscore)."""
    if not (v.text("name", name).isidentifier() and name.isascii()):
        raise ValueError(f"name must be a C identifier, got {name!r}")
    if name in C_KEYWORDS:
        raise ValueError(f"name {name!r} is a C keyword; the generated function could not be "
                         "compiled: choose another name")
    if name in C_LIBRARY_NAMES:
        raise ValueError(f"name {name!r} is a name of the C standard library (<math.h>, "
                         "<stdlib.h>, <stdio.h>); the generated function would conflict with "
                         "it: choose another name")
    if name[:1] == "_" and (name[1:2] == "_" or name[1:2].isupper()):
        raise ValueError(f"name {name!r} is reserved to the C implementation (a leading "
                         "underscore then a capital or an underscore): choose another name")
    return name


def _checked(net, name, units):
    v.instance("net", net, FrictionNet)
    check_c_name(name)
    return units_of(units)


def c_header(net: FrictionNet, *, name: str = "fricctl_friction_net", units: str = "rotary") -> str:
    """The C header of :func:`c_source`: prototypes, units and the envelope in comments.

    Parameters
    ----------
    net : FrictionNet
        The network.
    name : str
        C identifier prefix, as given to :func:`c_source`.
    units : {"rotary", "linear"}
        Axis kind of the net's inputs and output (comments only).

    Examples
    --------
    >>> net = FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0,
    ...                   input_offset=[0, 0], input_scale=[1, 1], output_offset=0.0,
    ...                   output_scale=1.0, envelope_low=[-1, -1], envelope_high=[1, 1])
    >>> h = c_header(net, name="axis", units="linear")
    >>> "double axis_compensation(double tm, double omega_hat, double s, int clip);" in h
    True
    >>> "friction force estimate [N]" in h
    True
    """
    u = _checked(net, name, units)
    what = "torque" if u.kind == "rotary" else "force"
    guard = f"{name.upper()}_H"
    lo, hi = net.envelope_low, net.envelope_high
    return f"""/* Generated by fricctl.nn.c_header: the 2-{net.hidden}-1 friction network of {name}.c.
 * {u.kind} axis, load side, SI: motor {what} tm [{u.torque}], velocity omega [{u.velocity}],
 * friction {what} estimate [{u.torque}] (sign of the velocity: I*a = Tm - Tat).
 * Training envelope: tm in [{_c(lo[0])}, {_c(hi[0])}] {u.torque},
 *                    omega in [{_c(lo[1])}, {_c(hi[1])}] {u.velocity}.
 */
#ifndef {guard}
#define {guard}

#ifdef __cplusplus
extern "C" {{
#endif

/* Friction estimate T^at(tm, omega) [{u.torque}]; clip != 0 clips the inputs to the envelope. */
double {name}(double tm, double omega, int clip);

/* The compensation term of one controller sample, s * T^at(tm, omega_hat) [{u.torque}]:
 * tm the {what} applied over the current sample [{u.torque}], omega_hat the measured velocity
 * [{u.velocity}], s the compensation scale [-] (1; below 1 for an aged actuator).
 * Command Tm(k+1) = Tc(k) + NAME_compensation(Tm(k), omega_hat(k), s, 1), then saturate. */
double {name}_compensation(double tm, double omega_hat, double s, int clip);

/* out[i] = {name}(tm[i], omega[i], clip) for i < n. */
void {name}_batch(const double *tm, const double *omega, double *out, long n, int clip);

/* 1 where (tm, omega) lies outside the training envelope, else 0. */
int {name}_outside(double tm, double omega);

#ifdef __cplusplus
}}
#endif

#endif /* {guard} */
""".replace("NAME_compensation", f"{name}_compensation")


def c_source(net: FrictionNet, *, name: str = "fricctl_friction_net", units: str = "rotary") -> str:
    """A self-contained C99 translation unit evaluating ``net``.

    It defines (only ``<math.h>`` needed, link with ``-lm``; prototypes in :func:`c_header`)::

        double NAME(double tm, double omega, int clip);
        double NAME_compensation(double tm, double omega_hat, double s, int clip);
        void NAME_batch(const double *tm, const double *omega, double *out,
                        long n, int clip);
        int NAME_outside(double tm, double omega);

    with the weights printed with 17 significant digits (exact round trip of
    IEEE doubles), so the result matches :meth:`FrictionNet.__call__` to the
    rounding of ``tanh`` and of the summation order (about 1e-16 relative).

    Parameters
    ----------
    net : FrictionNet
        The network.
    name : str
        C identifier of the function.
    units : {"rotary", "linear"}
        Axis kind of the inputs and output (comments only).

    Examples
    --------
    >>> net = FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0,
    ...                   input_offset=[0, 0], input_scale=[1, 1], output_offset=0.0,
    ...                   output_scale=1.0, envelope_low=[-1, -1], envelope_high=[1, 1])
    >>> "double fricctl_friction_net(double tm, double omega, int clip)" in c_source(net)
    True
    """
    u = _checked(net, name, units)
    h = net.hidden
    arr = lambda a: "{" + ", ".join(_c(x) for x in np.ravel(a)) + "}"  # noqa: E731
    meta = json.dumps({k: net.metadata[k] for k in ("trainer", "hidden", "fit_percent")
                       if k in net.metadata})
    what = "torque" if u.kind == "rotary" else "force"
    return f"""/* Generated by fricctl.nn.c_source: a 2-{h}-1 friction network, load side, SI.
 * inputs: tm [{u.torque}], omega [{u.velocity}]; output: friction {what} estimate [{u.torque}].
 * {meta.replace('*/', '* /')}
 * xn = (x - IN_OFF) / IN_SCALE; h = tanh(W1 xn + B1); y = (W2 . h + B2) * OUT_SCALE + OUT_OFF
 */
#include <math.h>

#define {name.upper()}_HIDDEN {h}

static const double {name}_w1[{h}][2] = {{{", ".join(arr(r) for r in net.w1)}}};
static const double {name}_b1[{h}] = {arr(net.b1)};
static const double {name}_w2[{h}] = {arr(net.w2)};
static const double {name}_b2 = {_c(net.b2)};
static const double {name}_in_off[2] = {arr(net.input_offset)};
static const double {name}_in_scale[2] = {arr(net.input_scale)};
static const double {name}_out_off = {_c(net.output_offset)};
static const double {name}_out_scale = {_c(net.output_scale)};
static const double {name}_env_low[2] = {arr(net.envelope_low)};
static const double {name}_env_high[2] = {arr(net.envelope_high)};

int {name}_outside(double tm, double omega)
{{
    return tm < {name}_env_low[0] || tm > {name}_env_high[0]
        || omega < {name}_env_low[1] || omega > {name}_env_high[1];
}}

double {name}(double tm, double omega, int clip)
{{
    if (clip) {{
        if (tm < {name}_env_low[0]) tm = {name}_env_low[0];
        if (tm > {name}_env_high[0]) tm = {name}_env_high[0];
        if (omega < {name}_env_low[1]) omega = {name}_env_low[1];
        if (omega > {name}_env_high[1]) omega = {name}_env_high[1];
    }}
    const double x0 = (tm - {name}_in_off[0]) / {name}_in_scale[0];
    const double x1 = (omega - {name}_in_off[1]) / {name}_in_scale[1];
    double yn = 0.0;
    for (int j = 0; j < {h}; ++j) {{
        yn += {name}_w2[j] * tanh({name}_w1[j][0] * x0 + {name}_w1[j][1] * x1 + {name}_b1[j]);
    }}
    return (yn + {name}_b2) * {name}_out_scale + {name}_out_off;
}}

double {name}_compensation(double tm, double omega_hat, double s, int clip)
{{
    return s * {name}(tm, omega_hat, clip);
}}

void {name}_batch(const double *tm, const double *omega, double *out, long n, int clip)
{{
    for (long i = 0; i < n; ++i) out[i] = {name}(tm[i], omega[i], clip);
}}
"""
