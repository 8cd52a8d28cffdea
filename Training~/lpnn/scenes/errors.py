"""The one error type of the scene importer."""

from __future__ import annotations

from ..errors import InvalidInputError


class BspError(InvalidInputError):
    """A level file cannot be used; the message names the file, the lump or record, and the value."""
