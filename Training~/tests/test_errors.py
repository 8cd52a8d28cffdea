"""One error hierarchy (lpnn/errors.py): every error the package defines derives from LpnnError, and the
command line prints any of them as one line, without a traceback."""

from __future__ import annotations

import argparse
import importlib
import inspect
import pkgutil

import pytest

import lpnn
from lpnn.cli import main as cli_main
from lpnn.core.spread import SpreadError
from lpnn.errors import InvalidInputError, LpnnError, UserError


def defined_exceptions() -> list[type[BaseException]]:
    found = []
    for module_info in pkgutil.walk_packages(lpnn.__path__, "lpnn."):
        module = importlib.import_module(module_info.name)
        found += [value for _, value in inspect.getmembers(module, inspect.isclass)
                  if issubclass(value, BaseException) and value.__module__ == module.__name__]
    return found


def test_every_error_of_the_package_derives_from_the_one_base() -> None:
    errors = defined_exceptions()
    assert len(errors) >= 15  # the walk found the domain errors (GridError, CaptureError, SpreadError, ...)
    assert [e.__qualname__ for e in errors if not issubclass(e, LpnnError)] == []


def test_input_errors_stay_value_errors() -> None:
    # Callers (and numpy-style code) that catch ValueError keep working.
    assert issubclass(SpreadError, InvalidInputError) and issubclass(SpreadError, ValueError)
    assert not issubclass(UserError, ValueError)


@pytest.mark.parametrize("error", [SpreadError("scores has 3 values for 4 points: give one per point"),
                                   UserError("no such level 'q3dm99': list them with lpnn scene levels")])
def test_the_cli_prints_any_package_error_as_one_line(monkeypatch: pytest.MonkeyPatch,
                                                      capsys: pytest.CaptureFixture[str], error: LpnnError) -> None:
    def failing(args: argparse.Namespace) -> None:
        raise error

    parser = argparse.ArgumentParser(prog="lpnn")
    parser.add_subparsers(dest="command").add_parser("probe").set_defaults(handler=failing)
    monkeypatch.setattr(cli_main, "build_parser", lambda: parser)
    assert cli_main.main(["probe"]) == cli_main.EXIT_FAILED
    err = capsys.readouterr().err
    assert err == f"lpnn probe: error: {error}\n"
