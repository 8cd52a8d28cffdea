"""Errors a user can act on: printed as one line by the CLI, without a traceback."""


class UserError(Exception):
    """A problem with the user's input or environment; the message says what to do."""
