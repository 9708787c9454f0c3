"""The ``nonideal`` command line.

One module per command, each with ``add_parser(subparsers, ctx)`` and ``run(args) -> int``;
:data:`COMMANDS` lists them in the order of ``nonideal --help``.  To add a command, write its
module and add its name here.

Exit codes: 0 success; 2 bad input (the message names the file, the key and the fix);
3 the mechanics has no consistent or no unique answer; 130 / 143 stopped by Ctrl-C / SIGTERM
(:mod:`nonideal.cli.terminal`).  Nothing is written to an output path
unless the run succeeded (:mod:`nonideal.cli.outputs`).
"""

from __future__ import annotations

import argparse
import importlib
import errno
import sys
from pathlib import Path

from ..errors import MechanicsError, ModelError, NonidealError

__all__ = ["main", "build_parser", "COMMANDS"]

#: the commands, each a module of this package
COMMANDS = ("check", "derive", "evaluate", "simulate", "realizability", "friction_law", "stability",
            "frequencies", "sweep", "examples")


def version() -> str:
    """The installed version (the package metadata), or the source tree's."""
    try:
        from importlib.metadata import PackageNotFoundError, version as _version

        return _version("nonideal")
    except (ImportError, PackageNotFoundError):   # pragma: no cover - a source checkout
        from .. import __version__

        return __version__


class _Version(argparse.Action):
    """``--version``: the version is looked up only when asked for (the package metadata
    costs a tenth of a second to read)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"nonideal {version()}")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    from .common import ParserContext

    p = argparse.ArgumentParser(
        prog="nonideal",
        description="Analytical dynamics of systems with ideal and non-ideal constraints.",
        epilog="Exit codes: 0 success, 2 bad input, 3 mechanics without a consistent or unique answer.")
    p.add_argument("--version", action=_Version, help="show the version and exit")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    ctx = ParserContext()
    for name in COMMANDS:
        importlib.import_module(f"{__name__}.{name}").add_parser(sub, ctx)
    return p


def _bare_json(argv: list[str]) -> list[str]:
    """``--json MODEL.toml`` (a bare ``--json`` before the model) means JSON on standard output
    for that model -- not JSON written over the model file, which is what argparse's optional
    value would make of it.  A value ending in ``.toml`` is never a JSON output."""
    out = list(argv)
    for i, item in enumerate(out[:-1]):
        if (item == "--json" and out[i + 1].endswith(".toml")
                and not any(a.endswith(".toml") for a in out[1:i])):   # no model before it
            out[i] = "--json=-"
    return out


def main(argv: list[str] | None = None) -> int:
    from .common import numerical_warnings
    from .terminal import Terminated, escaped_output, output_failed, printable, signals, stopped

    parser = build_parser()
    try:
        args = parser.parse_args(_bare_json(sys.argv[1:] if argv is None else list(argv)))
    except SystemExit as exc:   # --help (0) or a usage error (2): return, do not exit
        return int(exc.code or 0)
    try:
        with signals(), numerical_warnings(), escaped_output():
            code = args.func(args)
            sys.stdout.flush()  # a full device fails here, not in the interpreter's exit
            return code
    except ModelError as exc:
        model = getattr(args, "model", None)
        if (exc.source is None and isinstance(model, str) and Path(model).is_file()
                and not all(str(pr).startswith("--") for pr in exc.problems)):
            exc = exc.with_source(model)  # an error found past the file's parsing names it too
        print(printable(f"error: {exc}"), file=sys.stderr)
        return exc.exit_code
    except MechanicsError as exc:
        print(printable(f"mechanics: {exc}"), file=sys.stderr)
        return exc.exit_code
    except NonidealError as exc:
        print(printable(f"error: {exc}"), file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        return stopped("interrupted")
    except Terminated:
        return stopped("terminated")
    except BrokenPipeError:  # pragma: no cover
        return 0
    except OSError as exc:  # the standard output cannot be written (a full device)
        if exc.filename is not None or exc.errno not in (errno.ENOSPC, errno.EIO, errno.EFBIG,
                                                         errno.EDQUOT):
            raise
        return output_failed(exc)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
