"""The errors of the `lpnn` package: one hierarchy, in a leaf module every layer may import.

Every error the package raises on purpose derives from `LpnnError`; its message names the bad value and
says what to do, so the command line prints it as one line, without a traceback (`cli/main.py` catches
this base once). Errors about a value that cannot be used also derive from `ValueError`, as Python's own
do, so callers that catch `ValueError` keep working.

    LpnnError
    +-- UserError          an option, file or environment the user has to change
    +-- InvalidInputError  (also a ValueError) data a step cannot use: each domain module derives its own
                           (GridError, CaptureError, SpreadError, MetricError, BspError, RigError, ...)
"""

from __future__ import annotations


class LpnnError(Exception):
    """Base of every error the package raises on purpose; the message says what to do."""


class UserError(LpnnError):
    """A problem with the user's options, files or environment; the message says what to change."""


class InvalidInputError(LpnnError, ValueError):
    """Data a step cannot use (a value out of range, a malformed file); the message names the value."""
