"""Execute one notebook exactly as myst-nb's ``force`` mode does, in a process of its own.

``python fricctl_execute.py IN.ipynb OUT.ipynb TIMEOUT CWD`` runs ``IN`` in a fresh kernel
with the function myst-nb calls (``jupyter_cache``'s ``single_nb_execution``, errors not
allowed, the notebook's own ``execution`` metadata overriding the timeout), in ``CWD`` (``-``:
a new temporary folder, myst-nb's ``nb_execution_in_temp``), and writes the executed notebook
to ``OUT`` (JSON as nbclient left it: what myst-nb would render had it executed it).  A cell error or timeout exits with 1 and prints myst-nb's traceback text (the
failing cell and its error) on stderr.  :mod:`fricctl_book` runs one such process per chapter,
several at a time (``fricctl_book_jobs``).

``python fricctl_execute.py --run CMD...`` runs ``CMD`` (``fricctl reproduce``) and exits
with its code.  Either way the last line on stdout is ``fricctl-execute cpu_s=<s>``: the CPU
time (user + system) of this process and everything it waited for (the kernel, reproduce's
workers), which the build log reports beside the wall time: on a shared machine the wall
time says little.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import tempfile
from contextlib import nullcontext


def cpu_seconds() -> float:
    """User + system CPU time of this process and of its children waited for [s]."""
    own, children = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main(argv: list[str]) -> int:
    if argv[:1] == ["--run"]:
        code = subprocess.run(argv[1:]).returncode
        sys.stdout.flush()
        print(f"fricctl-execute cpu_s={cpu_seconds():.1f}", flush=True)
        return code
    import nbformat
    from jupyter_cache.executors.utils import single_nb_execution

    src, dest, timeout, cwd = argv
    with open(src, encoding="utf-8") as f:
        nb = nbformat.from_dict(json.load(f))
    with (tempfile.TemporaryDirectory() if cwd == "-" else nullcontext(cwd)) as folder:
        result = single_nb_execution(nb, cwd=folder, timeout=int(timeout), allow_errors=False,
                                     meta_override=True)
    if result.err is not None:
        print(f"{type(result.err).__name__} in {src}:\n{result.exc_string}", file=sys.stderr)
        return 1
    # the notebook as nbclient left it, keys in their order (nbformat.write would sort them)
    with open(dest, "w", encoding="utf-8") as f:
        json.dump(nb, f, ensure_ascii=False)
    print(f"fricctl-execute cpu_s={cpu_seconds():.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
