"""Signal names dragged between views (variable browser -> plots, tables, editors)."""

from __future__ import annotations

from PySide6.QtCore import QMimeData

__all__ = ["MIME_SIGNALS", "SignalDropTarget", "names_from_mime", "signals_mime"]

MIME_SIGNALS = "application/x-workbench-names"


def signals_mime(names: list[str]) -> QMimeData:
    mime = QMimeData()
    text = "\n".join(names)
    mime.setData(MIME_SIGNALS, text.encode("utf-8"))
    mime.setText(text)
    return mime


def names_from_mime(mime: QMimeData) -> list[str]:
    """The names a drop carries (ours, or plain text with one name a line)."""
    if mime.hasFormat(MIME_SIGNALS):
        text = bytes(mime.data(MIME_SIGNALS)).decode("utf-8")
    elif mime.hasText():
        text = mime.text()
    else:
        return []
    return [line.strip() for line in text.splitlines() if line.strip()]


class SignalDropTarget:
    """Mixed into a view with ``hub`` and ``add_signals(names)``: names dropped on it are added (the ones
    the hub knows)."""

    def dragEnterEvent(self, event) -> None:
        if names_from_mime(event.mimeData()):
            event.acceptProposedAction()

    def dragMoveEvent(self, event) -> None:
        event.acceptProposedAction()

    def dropEvent(self, event) -> None:
        names = [n for n in names_from_mime(event.mimeData()) if self.hub.known(n)]
        if names:
            self.add_signals(names)
            event.acceptProposedAction()
