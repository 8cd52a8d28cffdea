"""Entry point of the `lpnn` console command.

Subcommands live in `lpnn/cli/<name>_cmd.py`, each exposing `register(subparsers)`; they are found
by name so adding a command never edits this file. Heavy libraries (TensorFlow, Embree) are imported
inside the command functions, so `lpnn --help` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from .. import __version__
from ..errors import LpnnError

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_CANCELLED = 130


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lpnn",
        description="LPNN Probes: captures, OpenArena scenes, placement quality, training and ONNX export.",
    )
    parser.add_argument("--version", action="version", version=f"lpnn {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    package = importlib.import_module(__package__)
    for module in sorted(m.name for m in pkgutil.iter_modules(package.__path__) if m.name.endswith("_cmd")):
        importlib.import_module(f"{__package__}.{module}").register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        result = args.handler(args)
    except LpnnError as exc:  # every error raised on purpose: its message says what to do (lpnn/errors.py)
        print(f"lpnn {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except OSError as exc:
        # A file-system failure no command anticipated (a folder it creates, a file it reads): the path
        # and the system's reason, not a traceback.
        where = f" ({exc.filename})" if exc.filename else ""
        print(f"lpnn {args.command}: error: {exc.strerror or exc}{where}; check the path and its permissions",
              file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print(f"lpnn {args.command}: cancelled; nothing partial was written", file=sys.stderr)
        return EXIT_CANCELLED
    return EXIT_OK if result is None else int(result)


if __name__ == "__main__":
    sys.exit(main())
