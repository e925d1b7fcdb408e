"""Errors worded for whoever made the mistake.

A library function names its Python arguments (``resume=True``, ``out``), the command line
its options (``--resume``, ``--out``): a ``UsageError`` carries both wordings, ``str(exc)``
the Python one and ``exc.cli`` the command line's (``dart-reach`` prints that one).
"""

from __future__ import annotations


class UsageError(ValueError):
    """A bad argument. ``str(exc)`` names Python arguments; ``cli`` says the same with the
    command line's options (default: the same text, for messages that name neither)."""

    def __init__(self, message: str, cli: str | None = None):
        super().__init__(message)
        self.cli = cli if cli is not None else message
