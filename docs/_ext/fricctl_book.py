"""What the book adds to Sphinx + myst-nb (``docs/book_authoring.md`` is the author's side).

* :func:`read_chapter` reads a jupytext percent-format chapter into a notebook (myst-nb's
  ``nb_custom_formats`` entry for ``.py``) and turns the house's two semantic cell tags into
  myst-nb's: ``solution`` -> ``hide-cell`` with the prompts "Show the solution" / "Hide the
  solution" (+ " to exercise N" when its first line is ``# Exercise N...``; the cell runs,
  input and output collapsed), ``widget`` -> ``remove-cell``
  (the cell runs; the book shows the static fallback that follows it instead).
* At ``builder-inited``, ``fricctl reproduce`` starts into ``fricctl_reproduce_dir`` (the
  command a reader runs, not a re-implementation of it; a failure fails the build), and the
  page holding the line :data:`PLACEHOLDER` gets its ``claims.md`` there (the summary table
  first, every detail section folded: :func:`fold_details`) and the PNGs of the
  representative seeds at :data:`FIGURES_PLACEHOLDER`.  ``fricctl reproduce --bench NAME``
  runs on every other bench too (:func:`bench_dirs`): the summary table shows every bench's
  verdicts side by side (:func:`claims_markdown`).
* The chapters and ``fricctl reproduce`` run side by side, ``fricctl_book_jobs`` at a time
  (default: the CPUs available), each chapter in its own kernel started the way myst-nb's
  ``force`` mode starts it (:mod:`fricctl_execute`); myst-nb then renders the notebooks as
  executed (:func:`start_execution`).  A cell error still fails the build.
* ``fricctl_book_only = "01,05"`` executes only those chapters (:func:`execute_only`);
  ``fricctl_executed_notebooks = <folder>`` (with ``nb_execution_mode = "off"``: the PDF of
  ``make book-pdf``) takes each chapter's notebook as an earlier build executed it
  (:func:`read_chapter`), if that build ran the same chapter code on the same fricctl
  (:func:`package_digest`).
* A ``docs/*.md`` page written as a README section (its first heading is ``##``, e.g.
  ``your_own_actuator.md``) is read one heading level up, so that it has a title.
* Each chapter's page offers its executed notebook (``.ipynb``, what myst-nb executed at this
  build, outputs included, its markdown as plain Jupyter renders it: :mod:`fricctl_jupyter`)
  beside its jupytext ``.py`` in the theme's download menu (:func:`notebook_download`).
* With ``math_number_all``, every display equation of a page gets its number, also those
  written as ``$$ ... $$`` (MyST's dollarmath, which the ``math`` directive's numbering does not
  reach): :func:`number_equations`.
* Numbering: the chapters are the numbered sections of the book (``index.md``'s ``:numbered: 1``
  toctree; ``numfig``), so a chapter's figures and equations read "Fig. 5.2", "Eq. (5.3)"; its
  title drops its own "Chapter 5 --", which the number now shows (:func:`chapter_titles`), and
  the PDF numbers its chapters as the HTML does, not one LaTeX chapter per page
  (:func:`latex_numbering`).
* In the API reference, the reST sections of a *module* docstring (``Notes``, ``Modules``)
  become rubrics: a page's sections are its modules, and two modules' ``Notes`` must not
  collide as labels.
"""

from __future__ import annotations

import ast
import functools
import importlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

import jupytext
from fricctl_jupyter import ADDED
from fricctl_tables import COEFFICIENTS_BEGIN, render_coefficients
from sphinx.errors import ExtensionError
from sphinx.util import logging

logger = logging.getLogger(__name__)

# -- chapters --------------------------------------------------------------------------------

#: Semantic cell tag -> (myst-nb tags added, myst-nb cell options added).
TAGS = {
    "solution": (("hide-cell",), {"code_prompt_show": "Show the solution",
                                  "code_prompt_hide": "Hide the solution"}),
    "widget": (("remove-cell",), {}),
}


#: A solution cell whose first line names its exercise ("# Exercise 2. ...") says so in its prompt.
_EXERCISE = re.compile(r"#\s*Exercise\s+(\d+[a-z]?)\b", re.I)


#: An anchor on the line before a display equation, ``<a id="eq-motion"></a>``: in Jupyter an
#: invisible link target; in the book the equation's MyST label (``$$ ... $$ (eq-motion)``).
_EQ_ANCHOR = re.compile(r'<a id="(eq-[\w-]+)"></a>[ \t]*\n(?:[ \t]*\n)?(\$\$.*?\$\$)', re.S)
#: A Markdown link to a labelled equation or figure, ``[the equation of motion](#eq-motion)``.
_NUMBERED_LINK = re.compile(r"\[[^\]]*\]\(#((eq|fig)-[\w-]+)\)")  # its words may wrap


#: The chapters this build does not execute (``nb_execution_mode = "off"``, or not in
#: ``fricctl_book_only``), by their text: their figures do not exist, and a link to one stays
#: its words instead of an unresolvable ``{numref}``.  Set by :func:`execute_only`.
UNEXECUTED: set[str] = set()


def cross_references(source: str, *, figures: bool = True) -> str:
    """A markdown cell's links to its chapter's equations and figures made numbered
    cross-references: Jupyter shows the link's words ("the equation of motion"), the book
    the number ("Eq. (2)", "Fig. 3") by MyST's ``{eq}`` and ``{numref}`` roles, which Jupyter
    would show raw; an equation is labelled by an anchor before it (:data:`_EQ_ANCHOR`), a
    figure by the ``name`` in its cell's metadata.  An unknown label fails the build."""
    source = _EQ_ANCHOR.sub(lambda m: f"{m.group(2)} ({m.group(1)})", source)

    def numbered(m):
        if m.group(2) == "fig" and not figures:
            return m.group(0)[1:m.group(0).index("](")]
        return ("{eq}" if m.group(2) == "eq" else "{numref}") + f"`{m.group(1)}`"

    return _NUMBERED_LINK.sub(numbered, source)


#: Where the API reference lives, and the line of one of its pages that documents a module.
API = Path(__file__).resolve().parent.parent / "api"
_AUTOMODULE = re.compile(r"^\.\. automodule:: ([\w.]+)\n(?![ \t]+:no-members:)", re.M)


def api_names() -> dict[int, str]:
    """``id`` of every function and class the API reference documents -> its documented name
    (the members in ``__all__`` of each module a ``docs/api`` page gives to ``automodule``)."""
    names: dict[int, str] = {}
    for page in sorted(API.glob("*.md")):
        for module_name in _AUTOMODULE.findall(page.read_text(encoding="utf-8")):
            module = importlib.import_module(module_name)
            for name in getattr(module, "__all__", ()):
                obj = getattr(module, name)
                # functions and classes: a constant's entry exists only if it has a docstring
                if callable(obj) and getattr(obj, "__doc__", None):
                    names.setdefault(id(obj), f"{module_name}.{name}")
    return names


def _resolve(node, scope: dict):
    """The object a ``Name`` or ``a.b.c`` expression names in ``scope``, or None."""
    if isinstance(node, ast.Name):
        return scope.get(node.id)
    if isinstance(node, ast.Attribute):
        base = _resolve(node.value, scope)
        return None if base is None else getattr(base, node.attr, None)
    return None


def api_uses(nb, names: dict[int, str] | None = None) -> list[tuple[int, list[str]]]:
    """For each code cell of ``nb`` that uses a documented fricctl object for the first time
    (and no markdown cell before it links to it): the cell's index and those objects'
    documented names, in order of use.  Cells the book hides or removes (``hide-input``,
    ``remove-cell``, ``remove-input``) do not count as a use: their code is not on the page."""
    names = api_names() if names is None else names
    scope: dict = {}
    linked: set[str] = set()
    out = []
    for index, cell in enumerate(nb.cells):
        if cell.cell_type == "markdown":
            linked.update(re.findall(r"\]\(#(fricctl[\w.]*)\)", cell.source))
            continue
        if cell.cell_type != "code":
            continue
        try:
            tree = ast.parse(cell.source)
        except SyntaxError:
            continue
        new: list[str] = []
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fricctl"):
                module = importlib.import_module(node.module)
                for alias in node.names:
                    if hasattr(module, alias.name):
                        scope[alias.asname or alias.name] = getattr(module, alias.name)
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.startswith("fricctl"):
                        module = importlib.import_module(alias.name)
                        scope[alias.asname or alias.name.split(".")[0]] = (
                            module if alias.asname else importlib.import_module("fricctl"))
        hidden = {"hide-input", "remove-cell", "remove-input"} & set(cell.metadata.get("tags", []))
        if hidden:
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.Name, ast.Attribute)):
                obj = _resolve(node, scope)
                name = names.get(id(obj)) if obj is not None else None
                if name and name not in linked and name not in new:
                    new.append(name)
        if new:
            # in source order, not ast.walk's
            new.sort(key=lambda n: min((m.start() for m in re.finditer(
                rf"\b{re.escape(n.rsplit('.', 1)[1])}\b", cell.source)), default=0))
            linked.update(new)
            out.append((index, new))
    return out


def api_links(nb) -> None:
    """Before each code cell that uses a documented fricctl object first (:func:`api_uses`), a
    line linking each to its API page: every function a chapter calls is one click from its
    reference where it is first used, without the chapter's prose having to name them all."""
    import nbformat

    for index, used in reversed(api_uses(nb)):
        links = ", ".join(f"[`{n.rsplit('.', 1)[1]}`](#{n})" for n in used)
        cell = nbformat.v4.new_markdown_cell(f"<small>fricctl used below: {links}</small>")
        cell.metadata["tags"] = ["fricctl-api"]
        nb.cells.insert(index, cell)


#: ``fricctl_executed_notebooks``: a chapter's text -> the notebook an earlier build executed
#: from it (``_sources/chapters/<chapter>.ipynb`` of the HTML book).  Set by :func:`execute_only`.
EXECUTED: dict[str, Path] = {}


#: The notebook metadata in which a chapter records the :func:`package_digest` it ran with.
DIGEST_KEY = "fricctl_package_digest"


def package_digest(root: Path | None = None) -> str:
    """SHA-256 of every file of the fricctl package a chapter runs (``root``; default the
    package this build imports): its Python sources and the data they read (the paper's
    actuator, the benches' JSON), not the bytecode caches.  A notebook executed with another
    digest ran other code than the chapter would run now, even if the chapter's own cells are
    the same."""
    from fricctl._cache import PACKAGE_ROOT, source_digest

    root = PACKAGE_ROOT if root is None else Path(root)
    return source_digest(f for f in root.rglob("*") if f.is_file()
                         and "__pycache__" not in f.relative_to(root).parts and f.suffix != ".pyc")


def read_chapter(text: str):
    """The notebook of a jupytext percent-format chapter, house tags mapped to myst-nb's,
    links to its equations and figures made numbered cross-references -- and, given
    ``fricctl_executed_notebooks`` (the PDF of ``make book-pdf``), the outputs the HTML build
    computed from this very code, so that no chapter runs twice: a notebook executed from
    another version of its chapter's code, or with other fricctl sources
    (:func:`package_digest`, which the notebook's metadata records), is refused."""
    running = RUNNING.get(text)
    if running is not None:  # executed by start_execution's pool: wait for it here
        return _executed(running)
    nb = _read_chapter(text)
    executed = EXECUTED.get(text)
    if executed is None:
        return nb
    import nbformat

    done = nbformat.read(executed, as_version=4)
    # the cells the download adds for Jupyter (captions, works cited): not the chapter's
    done.cells = [c for c in done.cells if ADDED not in c.metadata.get("tags", [])]
    code = [[(c.cell_type, c.source if c.cell_type == "code" else "") for c in n.cells]
            for n in (done, nb)]
    if code[0] != code[1]:
        raise ExtensionError(f"{executed} was executed from another version of its chapter's "
                             f"code: build the HTML book again (make book) before the PDF")
    if done.metadata.get(DIGEST_KEY) != nb.metadata[DIGEST_KEY]:
        raise ExtensionError(f"{executed} was executed with other fricctl sources than the "
                             f"package's now (or records none): build the HTML book again "
                             f"(make book) before the PDF")
    # the outputs of the code as executed, the prose as the chapter reads now
    for fresh, old in zip(nb.cells, done.cells):
        if fresh.cell_type == "code":
            fresh.outputs = old.outputs
            fresh.execution_count = old.get("execution_count")
    nb.metadata = done.metadata
    return nb


def _read_chapter(text: str):
    nb = jupytext.reads(text, fmt="py:percent")
    # the kernel fills this in when it runs; set here so that a build without execution
    # (nb_execution_mode=off, an author's quick look) still highlights the code
    nb.metadata.setdefault("language_info", {"name": "python"})
    # what the chapter runs besides its cells, kept in the executed notebook (read_chapter)
    nb.metadata[DIGEST_KEY] = _package_digest()
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source = cross_references(cell.source, figures=text not in UNEXECUTED)
        tags = list(cell.metadata.get("tags", []))
        for tag in [t for t in tags if t in TAGS]:
            extra_tags, options = TAGS[tag]
            tags += [t for t in extra_tags if t not in tags]
            if options:
                cell.metadata.setdefault("mystnb", {}).update(options)
            named = _EXERCISE.match(cell.source)
            if tag == "solution" and named:  # "Show the solution to exercise 2"
                which = f" to exercise {named.group(1)}"
                cell.metadata["mystnb"].update({k: v + which for k, v in options.items()})
        if tags:
            cell.metadata["tags"] = tags
        _alt_from_caption(cell.metadata)
    api_links(nb)
    return nb


@functools.lru_cache(maxsize=1)
def _package_digest() -> str:
    """:func:`package_digest` of the package this build imports, read once per build."""
    return package_digest()


#: TeX commands an alt text spells as the character a reader sees.
_TEX_TEXT = {"alpha": "α", "beta": "β", "omega": "ω", "Omega": "Ω", "zeta": "ζ", "Delta": "Δ",
             "delta": "δ", "tau": "τ", "mu": "μ", "sigma": "σ", "theta": "θ", "pi": "π",
             "pm": "±", "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥", "approx": "≈",
             "times": "×", "cdot": "·", "infty": "∞", "to": "→"}


def _math_text(tex: str) -> str:
    """Inline TeX as plain text: ``\\hat T_{at}`` -> ``T̂_at``, ``z^{-1}`` -> ``z^-1``."""
    tex = re.sub(r"\\(operatorname|mathrm|text)\s*\{([^{}]*)\}", r"\2", tex)
    tex = re.sub(r"\\frac\s*\{([^{}]*)\}\s*\{([^{}]*)\}", r"(\1)/(\2)", tex)
    tex = re.sub(r"\\(left|right|big|Big|bigg|Bigg)\b", "", tex)  # sizes of delimiters
    tex = re.sub(r"\\[,;:! ]", " ", tex)
    # an accent on a letter or a command: the combining circumflex after it
    tex = re.sub(r"\\hat\s*\{?(\\[a-zA-Z]+|[^\s{}_^\\])\}?", "\\1\u0302", tex)
    # a command spelled as its character, an unknown one dropped (\\dot q reads "q")
    tex = re.sub(r"\\([a-zA-Z]+)", lambda m: _TEX_TEXT.get(m.group(1), ""), tex)
    return re.sub(r"\s+", " ", re.sub(r"[{}]", "", tex)).strip()


def _alt_from_caption(metadata) -> None:
    """A figure's caption is also its image's alt text (unless the cell gives one): what a
    screen reader says, and what a reader sees when the image cannot load -- not a hash."""
    caption = metadata.get("mystnb", {}).get("figure", {}).get("caption")
    if not caption:
        return
    image = metadata["mystnb"].setdefault("image", {})
    if "alt" not in image:
        text = re.sub(r"\$([^$]+)\$", lambda m: _math_text(m.group(1)), caption)
        image["alt"] = re.sub(r"[`*]", "", text).strip()


def execute_only(app, config) -> None:
    """``config-inited``: with ``fricctl_book_only = "01,05"`` only those chapters are executed
    (the others are rendered without outputs): an author's quick look at one chapter.  (Also
    notes the chapters that are not executed: :data:`UNEXECUTED`.)"""
    only = [n.strip() for n in config.fricctl_book_only.split(",") if n.strip()]
    chapters = sorted(Path(app.srcdir, "chapters").glob("[0-9][0-9]_*.py"))
    EXECUTED.clear()
    if config.fricctl_executed_notebooks:
        folder = Path(config.fricctl_executed_notebooks)
        missing = [c.stem for c in chapters if not (folder / f"{c.stem}.ipynb").is_file()]
        if missing:
            raise ExtensionError(f"fricctl_executed_notebooks: no {missing[0]}.ipynb in {folder} "
                                 f"(build the HTML book first: make book)")
        EXECUTED.update({c.read_text(encoding="utf-8"): folder / f"{c.stem}.ipynb" for c in chapters})
    UNEXECUTED.clear()
    UNEXECUTED.update(c.read_text(encoding="utf-8") for c in chapters
                      if not EXECUTED and (config.nb_execution_mode == "off"
                      or (only and not c.name.startswith(tuple(f"{n}_" for n in only)))))
    if not only:
        return
    unknown = [n for n in only if not any(c.name.startswith(f"{n}_") for c in chapters)]
    if unknown:
        raise ExtensionError(f"fricctl_book_only: no chapter numbered {unknown[0]!r}")
    config.nb_execution_excludepatterns = [f"chapters/{c.name}" for c in chapters
                                           if not c.name.startswith(tuple(f"{n}_" for n in only))]


# -- the paper reproduced --------------------------------------------------------------------

#: The line of a page that is replaced by the claims table and the figures (the figures go to
#: :data:`FIGURES_PLACEHOLDER` instead when the page has that line too).
PLACEHOLDER = "<!-- fricctl-reproduce: claims.md and the figures are inserted here -->"
FIGURES_PLACEHOLDER = "<!-- fricctl-reproduce: the figures are inserted here -->"
_SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def _fast() -> bool:
    return os.environ.get("FRICCTL_FAST") == "1"


def reproduce_dir(app) -> Path:
    """Where ``fricctl reproduce`` writes: ``fricctl_reproduce_dir``, or ``_reproduce`` in the site."""
    folder = app.config.fricctl_reproduce_dir
    return Path(folder).resolve() if folder else Path(app.outdir) / "_reproduce"


def bench_dirs(app) -> dict[str, Path]:
    """Every bench of :data:`fricctl.paper.benches.BENCHES` -> where ``fricctl reproduce
    --bench NAME`` writes for the book, the default bench first: :func:`reproduce_dir` for
    the default (its claims and figures are the page's), ``<that folder>-<name>`` beside it
    for each other (its claims are a column of the summary table, issue 22)."""
    from fricctl.paper.benches import BENCHES, DEFAULT_BENCH

    out = reproduce_dir(app)
    names = [DEFAULT_BENCH] + [b for b in BENCHES if b != DEFAULT_BENCH]
    return {b: out if b == DEFAULT_BENCH else out.with_name(f"{out.name}-{b}") for b in names}


def reproduce_commands(app) -> list[list[str]]:
    """``fricctl reproduce --bench NAME --seeds N --force [--fast]`` (``--fast`` when
    FRICCTL_FAST=1) for each bench (:func:`bench_dirs`), but those whose folder an earlier build
    wrote when ``fricctl_reproduce = "reuse"`` keeps it (for an author who is rebuilding a
    chapter, not the claims)."""
    seeds = app.config.fricctl_reproduce_seeds or ("2" if _fast() else "10")
    cmds = []
    for bench, out in bench_dirs(app).items():
        if app.config.fricctl_reproduce == "reuse" and (out / "claims.md").is_file():
            logger.info("fricctl reproduce: reusing %s", out)
            continue
        cmds.append([sys.executable, "-m", "fricctl", "reproduce", "--bench", bench, "--out", str(out),
                     "--seeds", str(seeds), "--force"] + (["--fast"] if _fast() else []))
    return cmds


def _reproduce(cmd: list[str]) -> tuple[float, float | None, str]:
    """Run ``fricctl reproduce`` (:func:`reproduce_commands`) through :mod:`fricctl_execute`:
    its wall and CPU time [s] and last lines; a failure fails the build."""
    t0 = time.perf_counter()
    proc = _run([sys.executable, str(RUNNER), "--run"] + cmd, what=" ".join(["fricctl"] + cmd[3:6]),
                env=dict(os.environ, MPLBACKEND="Agg"))
    cpu, stdout = _cpu(proc.stdout)
    if proc.returncode != 0:
        raise ExtensionError(f"`fricctl reproduce` exited with {proc.returncode}:\n"
                             f"{stdout[-3000:]}\n{proc.stderr[-5000:]}")
    return time.perf_counter() - t0, cpu, "\n".join(stdout.strip().splitlines()[-3:])


def _cpu(stdout: str) -> tuple[float | None, str]:
    """The CPU time :mod:`fricctl_execute` reports on its last line [s], and the rest."""
    head, _, last = stdout.rstrip().rpartition("\n")
    if last.startswith("fricctl-execute cpu_s="):
        return float(last.split("=", 1)[1]), head
    return None, stdout


def _took(wall: float, cpu: float | None) -> str:
    return f"{wall:.0f} s" + ("" if cpu is None else f" ({cpu:.0f} s of CPU)")


def wait_for_reproduce() -> None:
    """The claims are needed now: wait for ``fricctl reproduce`` if it is running in the pool."""
    while REPRODUCING:
        name, future = REPRODUCING.pop(0)
        wall, cpu, tail = _result(future)
        if name:
            TIMES[name] = wall
        logger.info("fricctl reproduce took %s:\n%s", _took(wall, cpu), tail)


# -- executing the chapters and the claims side by side ---------------------------------------

#: A chapter's text -> (its name, the Future of (its executed notebook, wall and CPU
#: seconds)), for the chapters :func:`start_execution` gave to its pool.
RUNNING: dict[str, tuple[str, Future]] = {}
#: (its name in :data:`TIMES`, or "" for the default bench's, which runs first anyway; the
#: Future) of each ``fricctl reproduce`` while it runs in the pool.
REPRODUCING: list[tuple[str, Future]] = []
_POOL: list[ThreadPoolExecutor] = []
_PROCS: set[subprocess.Popen] = set()
_PROCS_LOCK = threading.Lock()
_STOP = threading.Event()
#: The script that runs a chapter's notebook, or ``fricctl reproduce``, in a process of its own.
RUNNER = Path(__file__).resolve().with_name("fricctl_execute.py")
#: A chapter's name -> its wall time [s] in this build; kept in doctreedir (:data:`SECONDS`) to
#: start the longest chapters first next time (a short one last does not wait alone).
TIMES: dict[str, float] = {}
SECONDS = "fricctl-chapter-seconds.json"
#: Where the pool writes each chapter's notebook before and after execution (under doctreedir).
EXECUTING = "fricctl-executing"


def book_jobs(config) -> int:
    """``fricctl_book_jobs``: how many chapters (and ``fricctl reproduce``) run at once; default
    the CPUs this process may use."""
    value = str(config.fricctl_book_jobs).strip()
    if not value:
        return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if not value.isdigit() or int(value) < 1:
        raise ExtensionError(f"fricctl_book_jobs: a whole number of processes >= 1, not {value!r}")
    return int(value)


#: The thread pools of the BLAS and OpenMP libraries each process of the pool may start: one
#: (unless the environment sets them).  The pool already runs as many processes as there are
#: CPUs; a BLAS pool on top only oversubscribes them, and fricctl's matrices are small (the
#: Levenberg-Marquardt trainer's ``J J'`` is 17 x ~4000): OpenBLAS's second thread doubled that
#: trainer's CPU for no gain at load ~5 on 2 cores, and at higher load its waiting threads
#: spun for whole time slices (Chapter 4's fast run 151-256 s of CPU instead of 29, reproduce's
#: 249-270 s instead of 67; ``benchmarks/README.md``, "The book").  The results are the
#: same bit for bit (every network of Chapter 4 and of the fast reproduce compared).
ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def _run(cmd: list[str], *, what: str, env=None) -> subprocess.CompletedProcess:
    """``cmd`` run to its end in a session of its own, so that :func:`stop_execution` can end
    it with its children (``fricctl reproduce``'s workers) when the build stops early; BLAS and
    OpenMP in one thread each unless ``env`` says otherwise (:data:`ONE_THREAD`)."""
    env = {**ONE_THREAD, **(os.environ if env is None else env)}
    with _PROCS_LOCK:
        if _STOP.is_set():
            raise ExtensionError(f"{what}: not started, the build is stopping")
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True)
        _PROCS.add(proc)
    try:
        out, err = proc.communicate()
    finally:
        with _PROCS_LOCK:
            _PROCS.discard(proc)
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def _execute_chapter(name: str, nb, folder: Path, timeout: int, cwd: str):
    """``nb`` executed in a kernel of its own (:mod:`fricctl_execute`): (the executed
    notebook, wall seconds, CPU seconds).  A cell error raises, with the cell and its
    traceback."""
    import nbformat

    src, dest = folder / f"{name}.ipynb", folder / f"{name}.executed.ipynb"
    src.write_text(json.dumps(nb, ensure_ascii=False), encoding="utf-8")  # key order kept
    t0 = time.perf_counter()
    proc = _run([sys.executable, str(RUNNER), str(src), str(dest), str(timeout), cwd],
                what=f"chapters/{name}.py")
    if proc.returncode != 0:
        raise ExtensionError(f"chapters/{name}.py: its execution failed (exit {proc.returncode}):\n"
                             f"{proc.stderr[-8000:]}")
    executed = nbformat.from_dict(json.loads(dest.read_text(encoding="utf-8")))
    return executed, time.perf_counter() - t0, _cpu(proc.stdout)[0]


def _result(future: Future):
    """``future``'s result; when it failed, everything else still running is stopped first."""
    try:
        return future.result()
    except BaseException:
        stop_execution()
        raise


def _executed(running: tuple[str, Future]):
    name, future = running
    t0 = time.perf_counter()
    nb, wall, cpu = _result(future)
    TIMES[name] = wall
    logger.info("chapters/%s.py: executed in %s; waited %.0f s for it here", name,
                _took(wall, cpu), time.perf_counter() - t0)
    return nb


def start_execution(app) -> None:
    """``builder-inited``: ``fricctl reproduce`` and every chapter this build executes start in
    a pool of :func:`book_jobs` threads, each running its own process: reproduce first (its
    networks are the ones Chapters 4-7 and 10 train again, read back from the disk cache,
    :mod:`fricctl.nn.cache`, which makes a process wait while another trains the same one),
    then the chapters and reproduce on the other benches (:func:`bench_dirs`; no chapter
    waits for those), the longest of the previous build first (its times are kept in the
    doctree folder; one without a time first, in file order).  Sphinx reads the other pages
    meanwhile; a chapter's
    page waits for its notebook (:func:`read_chapter`), the claims' page for reproduce
    (:func:`wait_for_reproduce`).

    The chapters run as myst-nb's ``force`` mode runs them (:mod:`fricctl_execute`): a fresh
    kernel each, in a temporary folder (``nb_execution_in_temp``), the cell timeout
    ``nb_execution_timeout``, a cell error an error of the build.  myst-nb then only renders
    (:func:`hand_over_execution`).  One job, ``sphinx -j N`` (whose forked readers could not
    wait for this pool), or another execution mode: reproduce runs first and myst-nb executes
    the chapters one after the other, as it would without this extension.
    """
    cmds = reproduce_commands(app)
    config = app.config
    jobs = book_jobs(config)
    chapters = []
    if (jobs > 1 and app.parallel <= 1 and config.nb_execution_mode == "force" and not EXECUTED
            and config.nb_execution_raise_on_error and not config.nb_execution_allow_errors):
        chapters = [c for c in sorted(Path(app.srcdir, "chapters").glob("[0-9][0-9]_*.py"))
                    if c.read_text(encoding="utf-8") not in UNEXECUTED]
    if not chapters:
        for cmd in cmds:
            logger.info("running fricctl %s", " ".join(cmd[3:]))
            wall, cpu, tail = _reproduce(cmd)
            logger.info("fricctl %s took %s:\n%s", " ".join(cmd[3:6]), _took(wall, cpu), tail)
        return
    try:
        last = json.loads((Path(app.doctreedir) / SECONDS).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        last = {}
    folder = Path(app.doctreedir) / EXECUTING
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    cwd = "-" if config.nb_execution_in_temp else str(Path(app.srcdir, "chapters"))  # as myst-nb
    _STOP.clear()
    pool = ThreadPoolExecutor(jobs, thread_name_prefix="fricctl-book")
    _POOL.append(pool)
    # the default bench's first (the chapters read its networks back from the disk cache);
    # then the chapters and the other benches' runs (which no chapter waits for), the longest
    # of the previous build first, as the chapters alone were
    default = [c for c in cmds if c[5] == next(iter(bench_dirs(app)))]
    queue = [(c.stem, c) for c in chapters] + [(f"reproduce-{c[5]}", c) for c in cmds
                                               if c not in default]
    queue.sort(key=lambda j: -float(last.get(j[0], math.inf)))  # stable: file order otherwise
    logger.info("executing %d chapters%s, %d at a time: %s", len(chapters),
                f" and running fricctl reproduce ({len(cmds)} benches)" if cmds else "", jobs,
                ", ".join([f"reproduce {c[5]}" for c in default]
                          + [n[:2] if isinstance(j, Path) else n for n, j in queue]))
    for cmd in default:
        REPRODUCING.append(("", pool.submit(_reproduce, cmd)))
    for name, job in queue:
        if isinstance(job, Path):
            text = job.read_text(encoding="utf-8")
            RUNNING[text] = (name, pool.submit(_execute_chapter, name, _read_chapter(text), folder,
                                               config.nb_execution_timeout, cwd))
        else:
            REPRODUCING.append((name, pool.submit(_reproduce, job)))


def hand_over_execution(app) -> None:
    """``builder-inited``, after myst-nb made its configuration: the chapters the pool runs
    are not executed by myst-nb again (its ``execution_mode`` "off" for this build only)."""
    if RUNNING:
        app.env.mystnb_config = app.env.mystnb_config.copy(execution_mode="off")


def stop_execution(app=None, exception=None) -> None:
    """``build-finished`` (or a failed chapter): nothing left running -- queued work cancelled,
    running processes (and their process groups) sent SIGTERM.  A chapter's Jupyter kernel runs
    in a session of its own (jupyter_client starts it so) and is not in that group: it ends
    when it sees its parent gone (ipykernel's parent poller, about a second later)."""
    if exception is None and TIMES and app is not None:  # a complete build: its times
        path = Path(app.doctreedir) / SECONDS
        try:
            last = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            last = {}
        from fricctl._atomic import write_text  # a build stopped mid-write leaves the old record

        write_text(path, json.dumps({**last, **{k: round(v, 1) for k, v in TIMES.items()}},
                                    indent=1, sort_keys=True))
    TIMES.clear()
    _STOP.set()
    for pool in _POOL:
        pool.shutdown(wait=False, cancel_futures=True)
    with _PROCS_LOCK:
        for proc in list(_PROCS):
            try:
                if hasattr(os, "killpg"):
                    os.killpg(proc.pid, signal.SIGTERM)  # the process and its workers
                else:  # Windows: no process groups
                    proc.terminate()
            except OSError:
                pass
    for pool in _POOL:
        pool.shutdown(wait=True)
    _POOL.clear()
    RUNNING.clear()
    REPRODUCING.clear()


def shift_headings(text: str, by: int) -> str:
    """``text`` with every Markdown heading outside code fences ``by`` levels deeper (< 0: higher)."""
    out, fence = [], False
    for line in text.splitlines():
        if line.lstrip().startswith(("```", "~~~")):
            fence = not fence
        elif not fence and re.match(r"#{1,6} ", line):
            level = len(line) - len(line.lstrip("#"))
            line = "#" * min(6, max(1, level + by)) + line[level:]
        out.append(line)
    return "\n".join(out)


def _repo_links(text: str, srcdir: Path, here: Path) -> str:
    """Links written relative to the repository's root (``docs/x.md``) made relative to ``here``
    when they point into the book; any other link is left as it is."""
    root = srcdir.parent

    def fix(m):
        target = m.group(1)
        path = (root / target).resolve()
        if _SCHEME.match(target) or not path.is_file() or srcdir not in path.parents:
            return m.group(0)
        return f"]({Path(os.path.relpath(path, here)).as_posix()}{m.group(2)})"

    return re.sub(r"\]\(([^)#\s]+)([^)]*)\)", fix, text)


def fold_details(text: str, level: int, keep: tuple[str, ...] = ()) -> str:
    """MyST text whose sections of heading ``level`` (but those titled in ``keep``) are each
    folded into a collapsed ``<details>`` under their title; a deeper heading inside becomes a
    bold line (a section cannot start inside raw HTML).  On paper (LaTeX, which drops the raw
    HTML) everything is shown, each title as a bold line."""
    out, fence, open_ = [], False, False
    for line in text.splitlines():
        if line.lstrip().startswith(("```", "~~~")):
            fence = not fence
        heading = None if fence else re.match(r"(#{1,6}) (.*)", line)
        if heading and len(heading.group(1)) <= level and open_:
            out += ["", "</details>", ""]
            open_ = False
        if heading and len(heading.group(1)) == level and heading.group(2).strip() not in keep:
            title = heading.group(2).strip()
            out += [f'<details class="fricctl-details"><summary>{title}</summary>', "",
                    "```{only} latex", f"**{title}**", "```", ""]
            open_ = True
        elif heading and open_:
            out += [f"**{heading.group(2).strip()}**", ""]
        else:
            out.append(line)
    if open_:
        out += ["", "</details>", ""]
    return "\n".join(out)


def claims_markdown(out: Path, srcdir: Path, here: Path, benches: dict | None = None) -> str:
    """MyST text: ``claims.md`` of ``out``, headings one level down, every section after the
    at-a-glance table folded (:func:`fold_details`): the table is what a reader reads first,
    the details are one click away (issue 24).  Given ``benches`` (bench -> the folder of its
    ``fricctl reproduce``, ``out``'s bench first: :func:`bench_dirs`), the at-a-glance table
    is every bench's side by side (:func:`fricctl.paper.benches_glance`, from each folder's
    ``claims.json``; issue 22)."""
    claims = out / "claims.md"
    if not claims.is_file():
        raise ExtensionError(f"no {claims}: `fricctl reproduce` did not run (see the build log)")
    text = shift_headings(claims.read_text(encoding="utf-8"), 1)
    if benches and len(benches) > 1:
        text = _glance_of_benches(text, benches)
    return fold_details(_repo_links(text, srcdir, here), 3, keep=("At a glance",)) + "\n"


#: The at-a-glance section of ``claims.md`` (headings one level down): its heading, its table.
_GLANCE = re.compile(r"^(### At a glance\n\n)((?:\|.*\n)+)", re.M)


def _glance_of_benches(text: str, benches: dict) -> str:
    """``text`` (a ``claims.md``) with its at-a-glance table replaced by every bench's
    (:func:`claims_markdown`)."""
    from fricctl.paper import benches_glance

    rows = {}
    for bench, folder in benches.items():
        path = folder / "claims.json"
        if not path.is_file():
            raise ExtensionError(f"no {path}: `fricctl reproduce --bench {bench}` did not run "
                                 f"(see the build log)")
        rows[bench] = json.loads(path.read_text(encoding="utf-8"))
    try:
        table = benches_glance(rows)
    except ValueError as exc:
        raise ExtensionError(f"the claims of the benches side by side: {exc}") from None
    first, *others = benches
    intro = (f"Every bench side by side, each rated by its own `fricctl reproduce --bench NAME` "
             f"(the same method); the sections below are the **{first}** bench's (the "
             f"default); the details of " + ", ".join(f"**{b}**" for b in others) + " are in the "
             f"`claims.md` that " + ", ".join(f"`fricctl reproduce --bench {b}`" for b in others)
             + " writes.")
    m = _GLANCE.search(text)
    if m is None:
        raise ExtensionError("claims.md has no \"At a glance\" table to put the benches' beside")
    return text[:m.start()] + m.group(1) + intro + "\n\n" + table + "\n" + text[m.end():]


def figures_markdown(out: Path, here: Path) -> str:
    """MyST text: every figure of ``out``, one section per pipeline, in the order of the
    claims table; ``figures/<pipeline>-seed<K>/*.png``, paths relative to ``here`` (the folder
    of the page)."""
    text = (out / "claims.md").read_text(encoding="utf-8")
    rel = Path(os.path.relpath(out, here)).as_posix()
    lines = []

    def first_mention(folder):  # the pipelines in the order of the claims table
        at = text.find(f"{folder.name.rsplit('-seed', 1)[0]} pipeline")
        return (at < 0, at, folder.name)

    for folder in sorted((p for p in (out / "figures").iterdir() if p.is_dir()), key=first_mention):
        pipeline, seed = folder.name.rsplit("-seed", 1)
        lines += [f"## Figures: {pipeline} pipeline, seed {seed}", ""]
        # the paper's figures in their order, then the extras (coast test, sweep)
        for png in sorted(folder.glob("*.png"), key=lambda f: (not f.stem.startswith("fig"), f.stem)):
            lines += ["```{image} " + f"{rel}/figures/{folder.name}/{png.name}",
                      f":alt: {png.stem}, {pipeline} pipeline, seed {seed}", "```", ""]
    return "\n".join(lines)


def reproduce_markdown(out: Path, srcdir: Path, here: Path) -> str:
    """MyST text: the claims (:func:`claims_markdown`), then every figure (:func:`figures_markdown`)."""
    return claims_markdown(out, srcdir, here) + "\n" + figures_markdown(out, here)


# -- source-read and autodoc hooks -----------------------------------------------------------

def on_source_read(app, docname, source) -> None:
    """The placeholders become the claims and figures (top level, so that their headings are
    sections of the page) and the friction coefficients' table; a page that starts at ``##``
    is read one level up."""
    text = source[0]
    if COEFFICIENTS_BEGIN in text:  # the registry's table, also when the page's copy is stale
        text = render_coefficients(text)
    if PLACEHOLDER in text:
        wait_for_reproduce()
        here = Path(app.env.doc2path(docname)).parent
        out = reproduce_dir(app)
        if FIGURES_PLACEHOLDER in text:
            text = text.replace(PLACEHOLDER, claims_markdown(out, Path(app.srcdir), here,
                                                             bench_dirs(app)))
            text = text.replace(FIGURES_PLACEHOLDER, figures_markdown(out, here))
        else:
            text = text.replace(PLACEHOLDER, reproduce_markdown(out, Path(app.srcdir), here))
    if str(app.env.doc2path(docname)).endswith(".md"):
        first = next((ln for ln in text.splitlines() if re.match(r"#{1,6} ", ln)), "")
        if first.startswith("## "):
            text = shift_headings(text, -1)
    source[0] = text


_UNDERLINE = re.compile(r"""^([-=~^"'`#*+])\1{2,}\s*$""")


def module_sections_as_rubrics(app, what, name, obj, options, lines) -> None:
    """``autodoc-process-docstring``: a module docstring's reST section titles become rubrics."""
    if what != "module":
        return
    out, i = [], 0
    while i < len(lines):
        title = lines[i]
        if (i + 1 < len(lines) and title.strip() and not title[0].isspace()
                and _UNDERLINE.match(lines[i + 1]) and len(lines[i + 1].strip()) >= len(title.strip())):
            out += [f".. rubric:: {title.strip()}", ""]
            i += 2
        else:
            out.append(title)
            i += 1
    lines[:] = out


def notebook_download(app, pagename, templatename, context, doctree) -> None:
    """``html-page-context``, before the theme's download menu (which runs at priority 501;
    this at 500): a chapter's
    executed notebook, written by myst-nb into its output folder, is written beside the page's
    source in ``_sources/`` as plain Jupyter shows it (:func:`fricctl_jupyter.jupyter_notebook`:
    the equations and figures numbered as on the page, citations and references in Markdown,
    no MyST markup left; :func:`jupyter_numbers` gathers the numbers) and named in
    ``ipynb_source``, which sphinx-book-theme offers as ".ipynb".  A chapter without its
    notebook fails the build (the reader would get a dead link)."""
    import nbformat
    from fricctl_jupyter import jupyter_notebook

    if not pagename.startswith("chapters/") or context.get("page_source_suffix") != ".py":
        return
    src = Path(app.env.mystnb_config.output_folder) / f"{pagename}.ipynb"
    if not src.is_file():
        raise ExtensionError(f"{pagename}: myst-nb wrote no notebook ({src}); the page's "
                             f".ipynb download would be a dead link")
    dest = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
    dest.parent.mkdir(parents=True, exist_ok=True)
    numbers, equations, figures = jupyter_numbers(app.env, pagename, doctree)
    try:
        nb = jupyter_notebook(nbformat.read(src, as_version=4), numbers=numbers,
                              equations=equations, figures=figures, cites=_citations(app))
    except ValueError as exc:
        raise ExtensionError(f"{pagename}: its notebook for Jupyter: {exc}") from None
    nbformat.write(nb, dest)
    context["ipynb_source"] = f"{pagename}.ipynb"


def _citations(app) -> dict:
    """:func:`fricctl_jupyter.citations` of the book's ``bibtex_bibfiles``, read once per build."""
    from fricctl_jupyter import citations

    files = tuple(str(Path(app.srcdir, f)) for f in app.config.bibtex_bibfiles)
    if _CITES.get("files") != files:
        _CITES.clear()
        _CITES.update(files=files, cites=citations(files))
    return _CITES["cites"]


_CITES: dict = {}


def jupyter_numbers(env, docname: str, doctree):
    """The numbers :func:`fricctl_jupyter.jupyter_notebook` gives a notebook, as the book
    shows them (numfig's, ``env.toc_fignumbers``): every labelled equation's and figure's
    (``"eq-motion" -> "Eq. (5.3)"``, ``"fig-loop" -> "Fig. 5.2"``), this page's display
    equations in page order (those of the markdown, not of cell outputs; None for one
    without a number) and, for each code cell, the numbers of its captioned figures."""
    from docutils import nodes

    def number(doc, kind, node_id):
        n = env.toc_fignumbers.get(doc, {}).get(kind, {}).get(node_id)
        return ".".join(map(str, n)) if n else None

    numbers = {}
    for label, (doc, _) in env.get_domain("math").data["objects"].items():
        n = number(doc, "displaymath", nodes.make_id(f"equation-{label}"))
        if n:
            numbers[label] = env.config.math_eqref_format.format(number=n)
    for label, (doc, label_id, _) in env.get_domain("std").labels.items():
        n = number(doc, "figure", label_id)
        if n:
            numbers[label] = env.config.numfig_format["figure"] % n

    def in_output(node):
        parent = node.parent
        while parent is not None:
            if parent.get("nb_element") == "cell_code_output":
                return True
            parent = parent.parent
        return False

    equations = [next((number(docname, "displaymath", i) for i in node["ids"]
                       if number(docname, "displaymath", i)), None)
                 for node in doctree.findall(nodes.math_block) if not in_output(node)]
    figures = {}
    for cell in doctree.findall(lambda n: isinstance(n, nodes.container)
                                and n.get("nb_element") == "cell_code"):
        shown = [n for fig in cell.findall(nodes.figure) for i in fig["ids"]
                 if (n := number(docname, "figure", i))]
        if shown:
            figures[cell["cell_index"]] = shown
    return numbers, equations, figures


def number_equations(app, doctree) -> None:
    """``doctree-read``: an unlabelled display equation gets a label and its number, as
    Sphinx's ``math`` directive does under ``math_number_all`` (a reader can cite "Eq. (5.3)");
    equations written with their own environment (``nowrap``) are left as they are.  (With
    ``numfig`` and ``math_numfig``, the number shown and cited is numfig's: the chapter's number
    and the equation's place in it, the labelled equations, ``$$ ... $$ (eq-x)``, among them.)"""
    from docutils import nodes

    # a bare % in TeX starts a comment, in LaTeX and MathJax alike: "(0-100 % rise time)" in a
    # docstring's equation would swallow the rest of its line (and break the PDF)
    for node in list(doctree.findall(lambda n: isinstance(n, (nodes.math, nodes.math_block)))):
        text = node.astext()
        if re.search(r"(?<!\\)%", text):
            node.clear()
            node += nodes.Text(re.sub(r"(?<!\\)%", r"\\%", text))
    if not app.config.math_number_all:
        return
    env = app.env
    docname = env.docname
    domain = env.get_domain("math")
    for node in list(doctree.findall(nodes.math_block)):
        node.setdefault("docname", docname)  # the LaTeX writer labels an equation by it
        if node.get("label") or node.get("nowrap"):
            continue
        node["label"] = f"{docname}:{env.new_serialno('sphinx.ext.math#equations')}"
        domain.note_equation(docname, node["label"], location=node)
        node["number"] = domain.get_equation_number_for(node["label"])
        # the id on the equation itself (the directive's target is moved onto it by a
        # transform that has run by now): numfig numbers equations by their ids
        node_id = nodes.make_id(f"equation-{node['label']}")
        node["ids"].append(node_id)
        doctree.ids[node_id] = node


#: A chapter's title as its source writes it, "Chapter 5 -- Open-loop ..." (``--`` typeset as an
#: en dash by then, or an em dash).
_CHAPTER_TITLE = re.compile(r"Chapter\s+(\d+)\s*(?:--|\u2013|\u2014|:)\s*")


def chapter_titles(app, doctree) -> None:
    """``doctree-read``, before Sphinx collects the titles: a chapter's title loses its
    "Chapter 5 --", which its section number shows in the book ("5. Open-loop compensation
    ..." in the navigation and on the page; "Chapter 5" above the title in the PDF).  Jupyter
    shows the source's title as it is.  A title whose number is not its file's (``05_...``)
    fails the build: the number cited would not be the chapter's."""
    from docutils import nodes

    m = re.fullmatch(r"chapters/(\d\d)_\w+", app.env.docname)
    section = next(iter(doctree.findall(nodes.section)), None)
    if m is None or section is None or not section.children:
        return
    title = section[0]
    text = next(iter(title.findall(nodes.Text)), None)
    head = _CHAPTER_TITLE.match(str(text)) if text is not None else None
    if head is None:
        return
    if int(head.group(1)) != int(m.group(1)):
        raise ExtensionError(f"{app.env.docname}: its title says Chapter {head.group(1)}, its "
                             f"file chapter {int(m.group(1))}")
    text.parent.replace(text, nodes.Text(str(text)[head.end():]))


#: numfig's kinds of numbered things -> the LaTeX counter that numbers them in the PDF.
_LATEX_COUNTERS = {"figure": "figure", "table": "table", "code-block": "literalblock",
                   "displaymath": "equation"}


def latex_numbering(app, doctree, docname) -> None:
    """``doctree-resolved`` of the PDF's one document: LaTeX numbers every page of the root
    toctrees as a chapter, so the chapters' numbers (and "Fig. 3.1" with them) would count the
    pages before them (the chapters' introduction, "Run it yourself").  Before each page, a
    line of LaTeX makes the PDF number it as the HTML does: a page of the numbered toctree gets
    its HTML number (``\\setcounter{chapter}``) and its sections are numbered to the toctree's
    depth; any other page is unnumbered (``secnumdepth`` -1), its figures and equations
    numbered without a chapter and on from where the HTML's numbers of such pages stand
    (``Eq. (3)`` on the notation page in both)."""
    from docutils import nodes
    from sphinx import addnodes

    if app.builder.format != "latex" or docname != app.config.root_doc:
        return
    env = app.env
    top = set(env.toctree_includes.get(app.config.root_doc, ()))
    for start in list(doctree.findall(addnodes.start_of_file)):
        doc = start["docname"]
        if doc not in top:
            continue  # a page under another page: numbered as its section, by LaTeX
        numbers = env.toc_secnumbers.get(doc, {})
        if numbers.get(""):
            depth = max(len(n) for n in numbers.values()) - 1  # 0: the chapter's number only
            tex = (f"\\setcounter{{secnumdepth}}{{{depth}}}"
                   f"\\setcounter{{chapter}}{{{numbers[''][0] - 1}}}")
        else:
            tex = "\\setcounter{secnumdepth}{-1}\\setcounter{chapter}{0}"
            # the first number of each kind on this page and the pages under it, as the HTML
            # has it: the counter starts one below
            docs = [s["docname"] for s in start.findall(addnodes.start_of_file)]
            for kind, counter in _LATEX_COUNTERS.items():
                first = [n[-1] for d in docs
                         for n in env.toc_fignumbers.get(d, {}).get(kind, {}).values() if len(n) == 1]
                if first:
                    tex += f"\\setcounter{{{counter}}}{{{min(first) - 1}}}"
        start.parent.insert(start.parent.index(start), nodes.raw("", tex, format="latex"))


def setup(app):
    app.add_config_value("fricctl_reproduce_dir", "", "env", types=[str])
    app.add_config_value("fricctl_reproduce_seeds", "", "env", types=[str])
    app.add_config_value("fricctl_reproduce", "run", "env", types=[str])
    app.add_config_value("fricctl_book_only", "", "env", types=[str])
    app.add_config_value("fricctl_executed_notebooks", "", "env", types=[str])
    app.add_config_value("fricctl_book_jobs", "", "env", types=[str, int])
    app.connect("config-inited", execute_only, priority=400)  # before myst-nb reads its config
    app.connect("builder-inited", start_execution, priority=400)  # before myst-nb's config
    app.connect("builder-inited", hand_over_execution, priority=600)  # after it
    app.connect("build-finished", stop_execution)
    app.connect("source-read", on_source_read)
    app.connect("autodoc-process-docstring", module_sections_as_rubrics)
    app.connect("html-page-context", notebook_download, priority=500)
    app.connect("doctree-read", number_equations)
    app.connect("doctree-read", chapter_titles, priority=400)  # before the title collector
    app.connect("doctree-resolved", latex_numbering)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
