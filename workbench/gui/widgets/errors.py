"""Errors as dialogs: the library's one-line message, the traceback only for what is not ours."""

from __future__ import annotations

import re
import traceback

from PySide6.QtWidgets import QMessageBox, QWidget

from workbench.errors import SeedKeyError, WorkbenchError, XcpCommandError

__all__ = ["seed_and_key_failure", "seed_and_key_text", "show_error"]

_RESOURCES = {"CAL/PAG": "calibration", "DAQ": "measurement", "PGM": "flashing"}


def show_error(parent: QWidget | None, exc: BaseException, title: str = "Workbench") -> QMessageBox:
    """Show ``exc`` (non-modal, so a test or a running measurement is not blocked); returns the box."""
    box = QMessageBox(parent)
    box.setIcon(QMessageBox.Warning if isinstance(exc, WorkbenchError) else QMessageBox.Critical)
    box.setWindowTitle(title)
    box.setText(str(exc) or type(exc).__name__)
    if not isinstance(exc, WorkbenchError):
        box.setInformativeText(f"unexpected {type(exc).__name__}")
        box.setDetailedText("".join(traceback.format_exception(exc)))
    box.setObjectName("error-dialog")
    box.setModal(False)
    box.show()
    return box


def seed_and_key_failure(exc: BaseException) -> bool:
    """Whether ``exc`` says a resource could not be unlocked: no key, the key function failed, the ECU refused
    the key."""
    return isinstance(exc, SeedKeyError) or (isinstance(exc, XcpCommandError) and exc.command == "UNLOCK")


def seed_and_key_text(details: str) -> str:
    """The one line a seed & key dialog leads with: which resources stay locked (as ``details``, the failures'
    lines, name them) and where the key function is set."""
    locked = [f"{name} ({use})" for name, use in _RESOURCES.items() if re.search(rf"\b{re.escape(name)}\b", details)]
    return (f"Seed & key failed: {', '.join(locked) or 'a resource'} of the ECU stay{'s' if len(locked) < 2 else ''} "
            "locked. Check the key function (ECU > Connection…, seed & key), then connect again.")
