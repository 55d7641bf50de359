"""XCP/A2L calibration and measurement workbench.

``from workbench import Session`` is the way in for scripts (see :class:`workbench.session.Session`),
``ImageCalibration`` for calibrations in an s19/hex without an ECU (:mod:`workbench.sync.offline`), and
``detect_slaves`` for the XCP on CAN slaves on a bus (:mod:`workbench.session.detect`); they are imported on
first use, so ``import workbench`` stays light. The core library never imports Qt; the GUI lives in
:mod:`workbench.gui` and is loaded only by the ``gui``/``demo`` commands.
"""

from workbench.errors import (
    A2lParseError,
    Cancelled,
    ConnectionLostError,
    ConversionError,
    EcuSilentError,
    EpkMismatchError,
    InputError,
    LimitsError,
    PageError,
    PartialWriteError,
    UnknownSymbolError,
    WorkbenchError,
    XcpCommandError,
    XcpTimeoutError,
)
from workbench.lazy_exports import lazy_exports

__version__ = "0.1.0"

_ERRORS = ["A2lParseError", "Cancelled", "ConnectionLostError", "ConversionError", "EcuSilentError",
           "EpkMismatchError", "InputError", "LimitsError", "PageError", "PartialWriteError", "UnknownSymbolError",
           "WorkbenchError", "XcpCommandError", "XcpTimeoutError"]
_lazy, __getattr__, _dir = lazy_exports(__name__, {"workbench.session": ("Session",),
                                                    "workbench.session.detect": ("detect_slaves",),
                                                    "workbench.sync.offline": ("ImageCalibration",)})
__all__ = sorted(_ERRORS + _lazy + ["__version__"])


def __dir__() -> list[str]:
    return sorted(set(_dir()) | set(__all__))
