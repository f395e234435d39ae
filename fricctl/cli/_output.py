"""What every sub-command checks before it writes a file (issue 15): no clobbered input.

An output that is one of the call's inputs, or the same file as another output of
the call, is refused; an existing output is refused unless ``--force``; a folder
is never an output file.  Checked before any work is done, so a refused call
writes nothing.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["check_outputs"]


def check_outputs(outputs: dict, inputs=(), *, force: bool = False) -> None:
    """Refuse outputs that would clobber an input, each other, or an existing file.

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
    seen: dict[Path, str] = {}
    for option, path in outputs.items():
        if path is None:
            continue
        p = Path(path)
        key = p.resolve()
        if key in ins:
            raise ValueError(f"{option}: {p} is an input of this command; refusing to overwrite it")
        if key in seen:
            raise ValueError(f"{option} and {seen[key]} name the same file {p}")
        seen[key] = option
        if p.is_dir():
            raise ValueError(f"{option}: {p} is a folder, not a file")
        if p.exists() and not force:
            raise ValueError(f"{option}: {p} exists (use --force to overwrite)")
