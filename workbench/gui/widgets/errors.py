"""Errors as dialogs: the library's one-line message, the traceback only for what is not ours."""

from __future__ import annotations

import traceback

from PySide6.QtWidgets import QMessageBox, QWidget

from workbench.errors import WorkbenchError

__all__ = ["show_error"]


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
