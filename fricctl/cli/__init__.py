"""The ``fricctl`` command.

Each sub-command lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a callable
``func(args) -> int``.  Errors in the user's input (:class:`ValueError`, and
:class:`OSError` such as a missing file or an output path that is a directory)
print one line on stderr and exit with code 2; warnings print one line each, after
the command's output (a call that fails prints its error line only: the warnings that
led to it, e.g. a numpy overflow, add nothing to it).

An interrupt is one line on stderr, never a traceback: Ctrl-C (SIGINT) exits with code
130 and SIGTERM with 143 (128 + the signal's number, what a shell reports for a process
the signal ended, so a script or a scheduler can tell the two apart).  Every output is
written atomically (:mod:`fricctl._atomic`), so an interrupted command leaves each of its
outputs complete or absent (as it was before), and no temporary file.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import os
import re
import signal
import sys
import threading
import warnings

#: Sub-command modules, in the order ``fricctl --help`` lists them.
SUBCOMMANDS = ("simulate", "design", "identify", "patterns", "train", "reproduce", "compare",
               "diagnose", "model")


#: Actions that hold one value: given twice, argparse keeps the last silently
#: (``--inertia 0.003 --inertia 0.005``); ``append`` and ``count`` actions are meant to repeat.
_SINGLE_VALUED = (argparse._StoreAction, argparse._StoreConstAction, argparse.BooleanOptionalAction)


@functools.cache
def _given_once(cls: type) -> type:
    """``cls`` refusing a second occurrence of its option in one command line."""

    class Once(cls):
        def __call__(self, parser, namespace, values, option_string=None):
            first = getattr(self, "_given_as", None)
            if first is not None and option_string == first and self.nargs == 0:
                return  # the same flag twice (--force --force): nothing would win over it
            if first is not None:
                also = "" if option_string == first else f" ({first}, then {option_string})"
                raise argparse.ArgumentError(self, f"given twice{also}; give it once (the last "
                                                   "one would silently win)")
            self._given_as = option_string
            super().__call__(parser, namespace, values, option_string)

    Once.__name__ = Once.__qualname__ = f"Once{cls.__name__}"
    return Once


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line on stderr and exit code 2.

    argparse prints the whole usage block before the message; a wrong option of a
    sub-command then fills the terminal.  The message names the option, suggests the
    nearest one (``did you mean --rise-time?``; argparse does so itself only from Python
    3.14) and points to the help of the sub-command it concerns (``fricctl simulate
    --help``, not ``fricctl --help``).  An option that holds one value is refused when
    given twice (argparse keeps the last); options meant to repeat (``append``) are not.
    """

    def parse_known_args(self, args=None, namespace=None):
        # every option of this parser (its groups' too), whatever added it: one mechanism for
        # all sub-commands; a sub-command's parser runs this again for its own options
        for action in self._actions:
            if action.option_strings and isinstance(action, _SINGLE_VALUED):
                if not type(action).__name__.startswith("Once"):
                    action.__class__ = _given_once(type(action))
                action._given_as = None
        return super().parse_known_args(args, namespace)

    def parse_args(self, args=None, namespace=None):
        # argparse reports a sub-command's unknown options from the top-level parser (after
        # the sub-parser collected them): report them from the sub-command's own parser
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            self._parser_of(parsed).error(f"unrecognized arguments: {' '.join(extras)}")
        return parsed

    def _parser_of(self, parsed) -> argparse.ArgumentParser:
        """The innermost sub-command's parser that ``parsed`` came through (``self`` if
        none; ``fricctl model new`` is two levels down)."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                name = getattr(parsed, action.dest, None)
                if name in action.choices:
                    sub = action.choices[name]
                    return sub._parser_of(parsed) if isinstance(sub, OneLineParser) else sub
        return self

    def _suggestion(self, message: str) -> str:
        """``"; did you mean ...?"`` for an unknown option or choice close to a known one."""
        import difflib

        if message.startswith("unrecognized arguments:"):
            known = [o for a in self._actions for o in a.option_strings]
            words = [w.split("=", 1)[0] for w in message.split(":", 1)[1].split()
                     if w.startswith("-")]
        else:
            m = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
            if m is None:
                return ""
            known, words = re.findall(r"'([^']*)'", m[2]), [m[1]]
        close = [c for w in words for c in difflib.get_close_matches(w, known, n=1, cutoff=0.6)]
        return f"; did you mean {' or '.join(dict.fromkeys(close))}?" if close else ""

    def error(self, message):
        first = message.splitlines()[0] if message else "bad arguments"
        self.exit(2, f"{self.prog}: error: {first}{self._suggestion(first)}"
                     f" (see {self.prog} --help)\n")


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C's KeyboardInterrupt, so that the same
    clean-up runs (temporary files removed, worker processes stopped)."""


#: Exit code and message of each interrupt.
INTERRUPTS = {Terminated: (143, "terminated (SIGTERM)"),
              KeyboardInterrupt: (130, "interrupted (Ctrl-C)")}


def _raise_terminated(signum, frame):
    raise Terminated()


@contextlib.contextmanager
def _sigterm_raises():
    """SIGTERM raises :class:`Terminated` while the command runs (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def interrupt_of(exc: BaseException) -> KeyboardInterrupt | None:
    """The Ctrl-C or SIGTERM behind ``exc``, if any: an interrupt that lands in a compiled
    module's initialisation comes out as that module's error (pybind11's ``ImportError:
    initialization failed``), with the interrupt as its cause."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


def _interrupted(exc: KeyboardInterrupt, command: str | None) -> int:
    code, what = next(v for k, v in INTERRUPTS.items() if isinstance(exc, k))
    print(f"fricctl{' ' + command if command else ''}: {what}; outputs not yet complete were "
          "not written", file=sys.stderr)
    return code


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``fricctl`` parser; ``command`` (one of :data:`SUBCOMMANDS`): that sub-command's
    alone, as ``fricctl COMMAND ...`` parses.  Registering a sub-command imports what its
    choices are read from (``train``: the network and its trainers; ``identify``: the
    estimators), which the other commands never use: a ``fricctl diagnose`` built every
    parser in 0.10-0.16 s of CPU time (and without bytecode caches compiled the modules too).
    """
    from .. import __version__

    parser = OneLineParser(
        prog="fricctl",
        description="Friction in a geared robot drive joint: simulate, identify, "
                    "learn with a 2-4-1 network, compensate, diagnose.")
    parser.add_argument("--version", action="version", version=f"fricctl {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    for name in SUBCOMMANDS if command is None else (command,):
        importlib.import_module(f".{name}", __name__).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    command = None
    try:
        with _sigterm_raises():
            return _main(argv)
    except BaseException as error:  # Ctrl-C, or SIGTERM (Terminated), maybe wrapped
        exc = interrupt_of(error)
        if exc is None:
            raise
        words = sys.argv[1:] if argv is None else argv
        if words and words[0] in SUBCOMMANDS:
            command = words[0]
        code = _interrupted(exc, command)
        if argv is None:  # the command itself: exit now, with the code
            # CPython exits by re-raising SIGINT (status -2, not 130) when a KeyboardInterrupt
            # went through an extension's embedded code (an interrupt inside scipy's import
            # does), even when it was handled here; the outputs are settled, so end now.
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)
        return code


def _main(argv: list[str] | None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    # a command named first is parsed by its own parser alone (its usage, help and errors are
    # the same); anything else (--help, --version, a misspelt command) by the whole one
    parser = build_parser(words[0] if words and words[0] in SUBCOMMANDS else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, a usage error: a code, also when called in-process
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    if getattr(args, "func", None) is None:
        print(f"fricctl: error: a command is required, one of {', '.join(SUBCOMMANDS)} "
              "(see fricctl --help)", file=sys.stderr)
        return 2
    shown: list[str] = []

    def one_line_warning(message, category, filename, lineno, file=None, line=None):
        text = str(message).splitlines()[0] if str(message) else category.__name__
        if text not in shown:
            shown.append(text)

    try:
        with warnings.catch_warnings():
            warnings.showwarning = one_line_warning
            code = int(args.func(args) or 0)
        for text in shown:
            print(f"fricctl {args.command}: warning: {text}", file=sys.stderr)
        return code
    except ValueError as exc:
        if interrupt_of(exc) is not None:
            raise
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"fricctl {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # the reader of stdout closed it (`fricctl simulate ... | head -3`): not an error of the
        # command; end quietly as a program stopped by SIGPIPE does (128 + 13), with stdout
        # pointed at /dev/null so that the interpreter's last flush does not fail again
        with contextlib.suppress(OSError, ValueError):
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        for text in shown:  # stderr is still the user's
            print(f"fricctl {args.command}: warning: {text}", file=sys.stderr)
        return 141
    except OSError as exc:  # missing input, output path that is a directory, no permission, ...
        if interrupt_of(exc) is not None:
            raise
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"fricctl {args.command}: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
