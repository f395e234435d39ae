"""Every file fricctl writes, written atomically: complete, or not there at all (issue 26).

Package-private and at the bottom of the layers.  A writer writes into a temporary file in
the destination's own folder (``.NAME.XXXXXXXX.fricctl-tmp.EXT``: hidden, and keeping the
ending, so matplotlib picks the format from it), flushes and fsyncs it, then moves it into
place in one step:

* ``overwrite=True``: :func:`os.replace` -- a reader sees the old file or the new one, never a
  mix; two writers that both overwrite never interleave (the last one wins, whole);
* ``overwrite=False``: :func:`os.link` of the temporary file to the destination, which fails
  when the destination exists -- so of two runs racing to create the same file, the second is
  refused (:class:`FileExistsError`) instead of silently replacing the first one's file.

A write that fails or is interrupted (an exception, Ctrl-C, SIGTERM turned into an exception
by the command line, a full disk, ``ulimit -f``) leaves the destination as it was and removes
its temporary file.  SIGINT, SIGTERM and SIGHUP are held while a temporary file is created,
moved into place or removed, so an interrupt cannot fall between the move and the clean-up.
Only ``kill -9`` (or a power cut) can leave a temporary file behind: never a partial
destination.  A folder (``fricctl diagnose --report DIR``) is built beside its destination and
renamed into place (:func:`atomic_folder`); a folder that replaces an earlier one as a whole
(``fricctl reproduce --out DIR --force``) is built beside it and swapped with it
(:func:`replace_folder`).

Notes
-----
A destination that is a device or a named pipe (``--csv /dev/null --force``) is written
into directly: replacing it with a file would destroy it (as root, ``/dev/null`` itself).
A destination that is a symbolic link is followed: the file it points to is replaced, the link
kept (what writing through the link did before).  An existing file's permission bits are kept;
a new file gets ``0o666`` less the umask, as :func:`open` would give it.  On a file system
without hard links the exclusive move falls back to a check then :func:`os.replace` (a race of
microseconds, not of a whole run).
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import shutil
import signal
import stat
from pathlib import Path
from typing import Iterator

__all__ = ["TEMP_MARK", "atomic_path", "atomic_write", "atomic_folder", "replace_folder",
           "write_text"]

#: What every temporary file or folder name holds (tests look for leftovers by it).
TEMP_MARK = ".fricctl-tmp"

_HELD = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Delay SIGINT/SIGTERM/SIGHUP for the duration (their handlers run right after)."""
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - Windows
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _destination(path) -> Path:
    """The file a write to ``path`` lands in (a symbolic link followed)."""
    return Path(os.path.realpath(os.fspath(path)))


def _special(dest: Path) -> bool:
    """True for an existing destination that is neither a regular file nor a folder (a
    device such as ``/dev/null``, a named pipe): it is written into, not replaced."""
    try:
        mode = os.stat(dest).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _temp_name(dest: Path, suffix: str) -> Path:
    return dest.parent / f".{dest.stem[:100]}.{secrets.token_hex(4)}{TEMP_MARK}{suffix}"


def _reserve(dest: Path) -> Path:
    """Create an empty temporary file beside ``dest`` (mode 0o666 less the umask)."""
    for _ in range(100):
        tmp = _temp_name(dest, dest.suffix)
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return tmp
        except FileExistsError:  # pragma: no cover - 32 random bits collided
            continue
    raise FileExistsError(errno.EEXIST, "no free temporary name", str(dest))  # pragma: no cover


def _fsync(path: Path, *, folder: bool = False) -> None:
    try:
        fd = os.open(path, os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if folder else 0))
    except OSError:  # pragma: no cover - a folder that cannot be opened: durability only
        if folder:
            return
        raise
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - some file systems cannot fsync a folder
        if not folder:
            raise
    finally:
        os.close(fd)


def _temp_folder(dest: Path) -> Path:
    """Make an empty temporary folder beside ``dest`` (signals held by the caller); an error
    names ``dest``'s folder, never the temporary name."""
    tmp = _temp_name(dest, "")
    try:
        tmp.mkdir()
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(dest.parent)) from None
    return tmp


def _exists_error(dest: Path) -> FileExistsError:
    return FileExistsError(errno.EEXIST, "exists (another process wrote it meanwhile); not "
                                         "overwritten", str(dest))


def _commit(tmp: Path, dest: Path, overwrite: bool) -> None:
    """Move the complete ``tmp`` to ``dest`` (signals held by the caller)."""
    if overwrite:
        with contextlib.suppress(FileNotFoundError):
            os.chmod(tmp, stat.S_IMODE(os.stat(dest).st_mode))
        os.replace(tmp, dest)
    else:
        try:
            os.link(tmp, dest)
        except FileExistsError:
            raise _exists_error(dest) from None
        except OSError as exc:  # no hard links here (EPERM, ENOTSUP, ...): check, then replace
            if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK,
                                 errno.EACCES):
                raise
            if os.path.lexists(dest):
                raise _exists_error(dest) from None
            os.replace(tmp, dest)
        else:
            os.unlink(tmp)
    _fsync(dest.parent, folder=True)


def _named(exc: OSError, tmp: Path | None, dest: Path) -> OSError:
    """``exc`` naming ``dest`` (a full disk's error names no file; never name a temporary file)."""
    if exc.filename is not None and (tmp is None or os.fspath(exc.filename) != os.fspath(tmp)):
        return exc
    return OSError(exc.errno, exc.strerror or str(exc), str(dest))


def _outside(exc: OSError, tmp: Path, dest: Path) -> OSError:
    """``exc`` naming the file of ``dest`` where it names one in the temporary folder ``tmp``
    (a full disk while a report is written names the report's file, not a hidden name)."""
    name = None if exc.filename is None else os.fspath(exc.filename)
    if not isinstance(name, str) or not (name == str(tmp) or name.startswith(str(tmp) + os.sep)):
        return exc
    return OSError(exc.errno, exc.strerror or str(exc), str(dest) + name[len(str(tmp)):])


@contextlib.contextmanager
def _named_outside(tmp: Path, dest: Path) -> Iterator[None]:
    try:
        yield
    except OSError as exc:
        named = _outside(exc, tmp, dest)
        if named is exc:
            raise
        raise named from None


@contextlib.contextmanager
def atomic_path(path, *, overwrite: bool = True) -> Iterator[Path]:
    """A temporary path to write ``path``'s content to; moved into place when the block ends.

    Parameters
    ----------
    path : str or os.PathLike
        The destination.  Its folder must exist.
    overwrite : bool
        True: replace an existing file.  False: refuse (:class:`FileExistsError`) when the
        destination exists when the write completes.

    Yields
    ------
    pathlib.Path
        An empty file beside the destination, with the same ending; write it by name
        (``savefig``, ``np.save``, another writer).

    Raises
    ------
    OSError
        Writing failed (naming the destination, never the temporary file); the destination
        is as it was and the temporary file is gone.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     with atomic_path(pathlib.Path(d) / "a.txt") as tmp:
    ...         _ = tmp.write_text("complete")
    ...     sorted(p.name for p in pathlib.Path(d).iterdir())
    ['a.txt']
    """
    dest = _destination(path)
    if _special(dest):  # /dev/null, a named pipe: written into; replacing it would destroy it
        if not overwrite:
            raise _exists_error(dest)
        yield dest
        return
    tmp = None
    try:
        with _signals_held():
            tmp = _reserve(dest)
        yield tmp
        _fsync(tmp)
        with _signals_held():
            _commit(tmp, dest, overwrite)
            tmp = None
    except OSError as exc:
        named = _named(exc, tmp, dest)
        if named is exc:
            raise
        raise named from None
    finally:
        if tmp is not None:
            with _signals_held(), contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)


@contextlib.contextmanager
def atomic_write(path, *, overwrite: bool = True, encoding: str = "utf-8",
                 newline: str | None = None):
    """A text file object whose content replaces ``path`` when the block ends without error.

    See :func:`atomic_path` for the parameters and guarantees.
    """
    with atomic_path(path, overwrite=overwrite) as tmp:
        with open(tmp, "w", encoding=encoding, newline=newline) as fh:
            yield fh


def write_text(path, text: str, *, overwrite: bool = True, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (:func:`atomic_path`); returns ``Path(path)``."""
    with atomic_write(path, overwrite=overwrite, encoding=encoding) as fh:
        fh.write(text)
    return Path(path)


@contextlib.contextmanager
def atomic_folder(path) -> Iterator[Path]:
    """A folder to fill; ``path`` appears with all of it when the block ends without error.

    A folder that does not exist is built beside its destination and renamed into place (a
    reader sees no folder or the whole of it).  An existing folder (the user's, maybe with
    other files) is yielded as it is: write each file into it with :func:`atomic_path`.
    """
    dest = _destination(path)
    if dest.is_dir():
        yield dest
        return
    tmp = None
    try:
        with _signals_held():
            tmp = _temp_folder(dest)
        with _named_outside(tmp, dest):
            yield tmp
        with _signals_held():
            try:
                os.rename(tmp, dest)  # onto an existing non-empty folder: refused by the OS
            except OSError as exc:
                if exc.errno in (errno.EEXIST, errno.ENOTEMPTY, errno.EISDIR, errno.ENOTDIR):
                    raise _exists_error(dest) from None
                raise
            tmp = None
            _fsync(dest.parent, folder=True)
    finally:
        if tmp is not None:
            with _signals_held():
                shutil.rmtree(tmp, ignore_errors=True)



def _exchange(a: Path, b: Path) -> None:
    """Swap the folders ``a`` and ``b`` (signals held by the caller).

    One ``renameat2(RENAME_EXCHANGE)`` where the C library and the file system have it (a
    reader sees the old folder or the new one); else two renames, between which ``b``'s name
    is absent for microseconds.
    """
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):  # pragma: no cover - no glibc >= 2.28 (macOS, musl)
        renameat2 = None
    if renameat2 is not None:
        at_fdcwd, rename_exchange = -100, 2
        if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
            return
        err = ctypes.get_errno()
        if err not in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP):
            raise OSError(err, os.strerror(err), str(b))
    trash = _temp_name(b, "")  # pragma: no cover - a file system without RENAME_EXCHANGE
    os.rename(b, trash)
    os.rename(a, b)
    os.rename(trash, a)


def check_replaceable(folder) -> None:
    """Refuse (ValueError) an existing folder that :func:`replace_folder` cannot replace: a
    mount point (it cannot be renamed), or one holding a mount point.  Callers check it
    before any work; :func:`replace_folder` checks again when it swaps."""
    folder = Path(os.path.realpath(folder))  # as replace_folder swaps it: a link's target
    if folder.is_dir() and os.path.ismount(folder):
        raise ValueError(f"{folder}: a mount point, which cannot be replaced as a whole (the new "
                         f"folder is built beside it and swapped in): give a folder inside it")
    _no_mount_inside(folder)


def _no_mount_inside(folder: Path) -> None:
    """Refuse a folder holding a mount point: carried into the new folder it would be copied
    file by file (no hard links across devices) and then emptied with the old folder."""
    for top, dirs, _ in os.walk(folder):
        for d in dirs:
            here = os.path.join(top, d)
            if not os.path.islink(here) and os.path.ismount(here):
                raise ValueError(f"{folder}: holds the mount point {here}, which replacing "
                                 f"the folder would copy and then empty: unmount it or "
                                 f"choose another folder")


def _carry(old: Path, new: Path, keep) -> None:
    """Link each entry of ``old`` that ``keep(relative posix path, path)`` accepts into ``new``, at
    the same place, unless ``new`` has something there (hard links: no copy, the same file;
    a copy where the file system has no hard links; a symbolic link as a link)."""
    for top, dirs, files in os.walk(old):
        rel_top = Path(top).relative_to(old)
        for name in sorted(files + [d for d in dirs if os.path.islink(os.path.join(top, d))]):
            rel = (rel_top / name).as_posix()
            src, dst = Path(top) / name, new / rel_top / name
            if os.path.lexists(dst) or not keep(rel, src):
                continue
            _made_folders(old, new, rel_top)
            if src.is_symlink():
                os.symlink(os.readlink(src), dst)
                continue
            try:
                os.link(src, dst, follow_symlinks=False)
            except OSError:  # no hard links here: a copy
                shutil.copy2(src, dst, follow_symlinks=False)
        if not dirs and not files:  # an empty folder of the old tree is kept too
            _made_folders(old, new, rel_top)


def _made_folders(old: Path, new: Path, rel: Path) -> None:
    """``new / rel`` as a folder, each level made with the mode of its ``old`` counterpart."""
    for k in range(1, len(rel.parts) + 1):
        part = Path(*rel.parts[:k])
        here = new / part
        if os.path.lexists(here) and not here.is_dir():
            raise ValueError(f"{old / part}: the new output {part.as_posix()} is a file where "
                             "this folder is; move the folder away and run again")
        if not here.exists():
            here.mkdir()
            shutil.copystat(old / part, here, follow_symlinks=False)


@contextlib.contextmanager
def replace_folder(path, *, keep=None, overwrite: bool = False) -> Iterator[Path]:
    """A new folder to fill; it replaces ``path`` as a whole when the block ends without error.

    The new folder is built beside ``path`` under a temporary name.  When the block ends,
    the entries of the existing ``path`` that ``keep`` accepts (and that the new folder has
    nothing at) are linked into it, and the two folders are swapped in one step; the old one
    is then removed.  An exception or an interrupt inside the block leaves ``path`` as it was
    and removes the new folder.

    Parameters
    ----------
    path : str or os.PathLike
        The destination folder.  The folder it goes into must exist.
    keep : callable, optional
        ``keep(rel, file) -> bool`` for each file or link of the old folder, ``rel`` its path
        relative to the folder with ``/`` separators and ``file`` where it is now: True keeps
        it in the new folder.  The default keeps every one.  Called when the block ends (files
        added meanwhile are seen).
    overwrite : bool
        False: refuse (:class:`FileExistsError`) a ``path`` that is a non-empty folder when
        the block ends.  True: replace it.

    Yields
    ------
    pathlib.Path
        The new, empty folder.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     dest = pathlib.Path(d) / "run"
    ...     dest.mkdir(); _ = (dest / "old.txt").write_text("old")
    ...     _ = (dest / "mine.txt").write_text("mine")
    ...     with replace_folder(dest, keep=lambda rel, _: rel != "old.txt", overwrite=True) as new:
    ...         _ = (new / "new.txt").write_text("new")
    ...     sorted(p.name for p in dest.iterdir()), sorted(p.name for p in pathlib.Path(d).iterdir())
    (['mine.txt', 'new.txt'], ['run'])
    """
    dest = _destination(path)
    keep = (lambda rel, file: True) if keep is None else keep
    tmp = None
    try:
        with _signals_held():
            tmp = _temp_folder(dest)
        with _named_outside(tmp, dest):
            yield tmp
        if not dest.exists():
            with _signals_held():
                try:
                    os.rename(tmp, dest)  # onto a folder filled meanwhile: refused by the OS
                except OSError as exc:
                    if exc.errno in (errno.EEXIST, errno.ENOTEMPTY, errno.EISDIR, errno.ENOTDIR):
                        raise _exists_error(dest) from None
                    raise
                tmp = None
                _fsync(dest.parent, folder=True)
            return
        if not dest.is_dir():
            raise NotADirectoryError(errno.ENOTDIR, "exists and is not a folder", str(dest))
        if not overwrite and any(dest.iterdir()):
            raise _exists_error(dest)
        check_replaceable(dest)
        shutil.copymode(dest, tmp)
        _carry(dest, tmp, keep)
        with _signals_held():
            _exchange(tmp, dest)
            old, tmp = tmp, None  # the new tree is in place; ``old`` holds the previous one
            # what was added to the previous tree while carrying; should this fail, the
            # previous tree stays under its temporary name (never removed with files in it)
            _carry(old, dest, keep)
            shutil.rmtree(old)
            _fsync(dest.parent, folder=True)
    finally:
        if tmp is not None:
            with _signals_held():
                shutil.rmtree(tmp, ignore_errors=True)
