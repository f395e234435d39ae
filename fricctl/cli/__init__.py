"""The ``fricctl`` command.

Each sub-command lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a callable
``func(args) -> int``.  Errors in the user's input (:class:`ValueError`, and
:class:`OSError` such as a missing file or an output path that is a directory)
print one line on stderr and exit with code 2; warnings print one line each, after
the command's output (a call that fails prints its error line only: the warnings that
led to it, e.g. a numpy overflow, add nothing to it).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import warnings

#: Sub-command modules, in the order ``fricctl --help`` lists them.
SUBCOMMANDS = ("simulate", "design", "identify", "patterns", "train", "reproduce", "diagnose",
               "model")


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line on stderr and exit code 2.

    argparse prints the whole usage block before the message; a wrong option of a
    sub-command then fills the terminal.  The message names the option and the
    sub-command; ``fricctl COMMAND --help`` gives the usage.
    """

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message.splitlines()[0] if message else 'bad arguments'}"
                     f" (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = OneLineParser(
        prog="fricctl",
        description="Friction in a geared robot drive joint: simulate, identify, "
                    "learn with a 2-4-1 network, compensate, diagnose.")
    parser.add_argument("--version", action="version", version=f"fricctl {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    for name in SUBCOMMANDS:
        importlib.import_module(f".{name}", __name__).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
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
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"fricctl {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except OSError as exc:  # missing input, output path that is a directory, no permission, ...
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"fricctl {args.command}: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
