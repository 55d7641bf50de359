"""A label that gives way: a long text is cut with "…" where the space ends (never widening the window),
and its tooltip always holds all of it."""

from __future__ import annotations

from PySide6.QtCore import QSize, Qt
from PySide6.QtWidgets import QLabel, QSizePolicy, QWidget

__all__ = ["ElidedLabel"]


class ElidedLabel(QLabel):
    def __init__(self, text: str = "", parent: QWidget | None = None, *, mode=Qt.ElideMiddle, minimum: int = 40):
        super().__init__(parent)
        self.mode = mode
        self.minimum = minimum
        self.full_text = ""
        self.extra_tip = ""
        self.setSizePolicy(QSizePolicy.Preferred, QSizePolicy.Preferred)  # its whole text if there is room
        self.setText(text)

    def setText(self, text: str, tip: str = "") -> None:  # noqa: N802 - Qt's name
        """``text`` shown (cut to the space), ``tip`` added below it in the tooltip."""
        self.full_text, self.extra_tip = text, tip
        self.setToolTip("\n".join(t for t in (text, tip) if t))
        self._elide()
        self.updateGeometry()

    def text(self) -> str:
        return self.full_text

    def _elide(self) -> None:
        room = max(self.contentsRect().width() - 2 * self.margin(), 0)
        shown = self.fontMetrics().elidedText(self.full_text, self.mode, room)
        super().setText("" if shown == "…" else shown)  # a lone "…" tells nothing (the tooltip does)

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self._elide()

    def sizeHint(self) -> QSize:
        margins = self.contentsMargins()
        width = self.fontMetrics().horizontalAdvance(self.full_text) + margins.left() + margins.right() + 2
        return QSize(width, super().sizeHint().height())

    def minimumSizeHint(self) -> QSize:
        return QSize(self.minimum, super().minimumSizeHint().height())

    @property
    def elided(self) -> bool:
        return super().text() != self.full_text
