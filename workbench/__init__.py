"""XCP/A2L calibration and measurement workbench.

The core library never imports Qt; the GUI lives in :mod:`workbench.gui` and is
loaded only by the ``gui``/``demo`` commands.
"""

import logging

from workbench.errors import (
    A2lParseError,
    Cancelled,
    EpkMismatchError,
    InputError,
    UnknownSymbolError,
    WorkbenchError,
    XcpCommandError,
    XcpTimeoutError,
)

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "A2lParseError",
    "Cancelled",
    "EpkMismatchError",
    "InputError",
    "UnknownSymbolError",
    "WorkbenchError",
    "XcpCommandError",
    "XcpTimeoutError",
    "__version__",
]
