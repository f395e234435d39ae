"""What every sub-command checks before it writes, and how it prints JSON (issue 15).

:func:`check_outputs`: an output that is one of the call's inputs, or the same file
as another output of the call (by name, through a symbolic link, or by inode: a hard
link), is refused; an existing output is refused unless ``--force``; a folder is never
an output file; the folder an output goes into must exist and be writable.  Checked
before any work is done, so a refused call writes nothing.  The outputs themselves are
written atomically (:mod:`fricctl._atomic`): complete or not at all, and without
``--force`` a file another run created meanwhile is refused, not replaced.

:func:`json_text`: the one way a sub-command prints or writes JSON.  Standard JSON
only (``allow_nan=False``): a value that is not a finite number is written as
``null`` and its reason is listed under the key ``"undefined"``.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
from pathlib import Path

from .._json import json_safe

__all__ = ["check_outputs", "check_figure", "json_text", "about", "save_figure", "check_new_folder",
           "check_replaceable_folder",
           "FIGURE_FORMATS"]

#: File name endings ``--figure`` accepts (matplotlib picks the format from it).
FIGURE_FORMATS = (".png", ".pdf", ".svg")


def check_outputs(outputs: dict, inputs=(), *, force: bool = False) -> None:
    """Refuse outputs that would clobber an input, each other, or an existing file,
    or that cannot be written.

    Parameters
    ----------
    outputs : dict
        Option name (``"--out"``) -> path, or None when the option is not given.
    inputs : iterable of path
        The files the call reads.
    force : bool
        Allow overwriting an existing output file (never an input).

    Raises
    ------
    ValueError
        One line naming the option and the file.
    """
    ins = {Path(p).resolve(): Path(p) for p in inputs if p is not None}
    in_ids = {_file_id(p): Path(p) for p in inputs if p is not None}
    in_ids.pop(None, None)
    seen: dict[Path, str] = {}
    seen_ids: dict[tuple, str] = {}
    for option, path in outputs.items():
        if path is None:
            continue
        p = Path(path)
        if not str(path).strip():
            raise ValueError(f"{option}: empty file name")
        key = p.resolve()
        if key in ins:
            raise ValueError(f"{option}: {p} is an input of this command; refusing to overwrite it")
        if key in seen:
            raise ValueError(f"{option} and {seen[key]} name the same file {p}")
        seen[key] = option
        fid = _file_id(p)
        if fid is not None:  # the same file under another name: a hard link
            if fid in in_ids:
                raise ValueError(f"{option}: {p} is the same file as the input {in_ids[fid]} "
                                 "(a hard link); refusing to overwrite it")
            if fid in seen_ids:
                raise ValueError(f"{option} and {seen_ids[fid]} name the same file {p} "
                                 "(a hard link)")
            seen_ids[fid] = option
        if p.is_dir():
            raise ValueError(f"{option}: {p} is a folder, not a file")
        folder = key.parent
        if not folder.is_dir():
            if p.is_symlink():  # a dangling link: the missing folder is its target's, not p's
                raise ValueError(f"{option}: {p} is a symbolic link into the folder {folder}, "
                                 "which does not exist")
            raise ValueError(f"{option}: the folder {p.parent} does not exist")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise ValueError(f"{option}: the folder {p.parent} is not writable")
        if p.exists():
            if not force:
                raise ValueError(f"{option}: {p} exists (use --force to overwrite)")
            if not os.access(p, os.W_OK):
                raise ValueError(f"{option}: {p} exists and is not writable")


def save_figure(fig, path, *, overwrite: bool, dpi: int = 110) -> None:
    """``fig.savefig`` to ``path`` atomically (:mod:`fricctl._atomic`), then close it (a
    pyplot figure; a bare :class:`~matplotlib.figure.Figure` is freed with its last
    reference).  PNGs are compressed at zlib level 1: 5-10 % larger files, a third less
    time than the default level 6 on a diagnosis report's four figures."""
    from .._atomic import atomic_path

    kwargs = {"pil_kwargs": {"compress_level": 1}} if Path(path).suffix.lower() == ".png" else {}
    try:
        with atomic_path(path, overwrite=overwrite) as tmp:
            fig.savefig(tmp, dpi=dpi, **kwargs)
    finally:
        if "matplotlib.pyplot" in sys.modules:
            sys.modules["matplotlib.pyplot"].close(fig)


def check_new_folder(option: str, path) -> None:
    """Refuse a folder to be made at ``path`` when the folder it goes into does not exist (it
    is not made, as no output file's folder is: a typo in a path became a new tree) or is not
    writable (checked before any work: the command would fail only when it writes)."""
    if os.path.islink(path) and not os.path.exists(path):
        # a dangling link: the folder is made where it points; say which folder is missing
        target = Path(os.path.realpath(path))
        if not target.parent.is_dir():
            raise ValueError(f"{option}: {path} is a symbolic link into the folder "
                             f"{target.parent}, which does not exist")
        path = target
    above = Path(os.path.abspath(path)).parent
    if not above.exists():
        raise ValueError(f"{option}: the folder {Path(path).parent} does not exist")
    if not above.is_dir():
        raise ValueError(f"{option}: {above} is not a folder; cannot make {path} inside it")
    if not os.access(above, os.W_OK | os.X_OK):
        raise ValueError(f"{option}: the folder {above} is not writable; cannot make {path}")


def check_replaceable_folder(option: str, path, when: str) -> None:
    """Refuse, before any work, an existing folder that will be replaced as a whole (``when``:
    on what, for the message) but should not or cannot be: one holding the working folder (the
    swap would leave the shell of whoever ran the command in a removed folder), a mount point,
    or one holding a mount point (:func:`fricctl._atomic.check_replaceable`;
    :func:`~fricctl._atomic.replace_folder` would refuse those only when it swaps, after the
    run)."""
    from .._atomic import check_replaceable

    here, there = Path.cwd().resolve(), Path(path).resolve()
    if here == there or there in here.parents:
        raise ValueError(f"{option}: {path} holds the working folder, and is replaced as a whole "
                         f"{when}: run from another folder")
    try:
        check_replaceable(path)
    except ValueError as exc:
        raise ValueError(f"{option}: {exc}") from None


def _file_id(path) -> tuple | None:
    """(device, inode) of an existing file, or None."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


def check_figure(option: str, path) -> None:
    """Refuse a figure path whose ending names no image format.

    matplotlib would append ``.png`` to such a name and write a file other than the
    one checked (``--figure results`` would write ``results.png``); a folder is
    refused by :func:`check_outputs`.
    """
    if path is None:
        return
    p = Path(path)
    if p.suffix.lower() not in FIGURE_FORMATS:
        where = " (a folder: give a file inside it, e.g. " + str(p / "run.png") + ")" if p.is_dir() else ""
        raise ValueError(f"{option}: {p} must end in {', '.join(FIGURE_FORMATS)}{where}")


@contextlib.contextmanager
def about(*paths):
    """Name the input file(s) in a :class:`ValueError` raised inside (issue 15: "acceleration
    holds NaN" says nothing about which of the user's files did it)."""
    try:
        yield
    except ValueError as exc:
        names = ", ".join(Path(p).name for p in paths if p is not None)
        msg = str(exc)
        if not names or any(Path(p).name in msg for p in paths if p is not None):
            raise
        raise ValueError(f"{names}: {msg}") from exc


def json_text(obj: dict, *, reasons: dict | None = None, indent: int | None = 2) -> str:
    """``obj`` as standard JSON: non-finite numbers become null with a reason.

    Parameters
    ----------
    obj : dict
        The summary (nested dicts, lists, numbers, strings, None; NumPy scalars and
        arrays are converted).
    reasons : dict, optional
        Key path (``"a.b"``, ``"a[0]"``) -> why that value is undefined, for values the
        command sets to None or that may come out non-finite.  A non-finite value
        without a reason is reported as ``"not a finite number (inf)"``.
    indent : int or None
        As for :func:`json.dumps`.

    Returns
    -------
    str
        JSON with an ``"undefined": {path: reason}`` entry when any value is null for a
        reason (never ``NaN`` or ``Infinity``).

    Examples
    --------
    >>> json_text({"a": 1.0, "b": float("nan")}, indent=None)
    '{"a": 1.0, "b": null, "undefined": {"b": "not a finite number (nan)"}}'
    """
    undefined: dict = {}
    reasons = dict(reasons or {})

    def note(path: str, x: float | None) -> None:
        if x is not None:
            undefined[path] = reasons.get(path, f"not a finite number ({x!r})")
        elif path in reasons:
            undefined[path] = reasons[path]

    out = json_safe(obj, note)
    if undefined:
        if "undefined" in out:  # pragma: no cover - a summary never uses the key itself
            raise RuntimeError("a summary uses the key 'undefined' that json_text adds")
        out["undefined"] = undefined
    return json.dumps(out, indent=indent, allow_nan=False)
