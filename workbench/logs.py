"""The package's loggers: ``log = logger(__name__)`` in a module.

Importing this module gives the package's top logger a :class:`logging.NullHandler`, as logging's
documentation advises a library to do: an application that has not configured logging hears nothing
from us. A module on the A2L tool chain's path asks for its logger only when it has something to say,
so that a batch ``a2l`` command never imports :mod:`logging` (4-10 ms of a small update).
"""

from __future__ import annotations

import logging

__all__ = ["logger"]

logging.getLogger("workbench").addHandler(logging.NullHandler())


def logger(name: str) -> logging.Logger:
    """The logger of module ``name`` (its ``__name__``)."""
    return logging.getLogger(name)
