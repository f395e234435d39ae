"""C identifiers the generated code may use: :func:`check_c_name` (shared by the network's C
export, :mod:`fricctl.nn.c_export`, and the compensators', :mod:`fricctl.compensators.c_export`)."""

from __future__ import annotations

from . import _validate as v

__all__ = ["check_c_name", "C_KEYWORDS", "C_LIBRARY_NAMES"]


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
