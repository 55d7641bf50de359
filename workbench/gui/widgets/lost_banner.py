"""The bar above the plots that says the connection to the ECU is lost (what, when) while the window
tries to reconnect, with "Reconnect now" and "Stop trying"; it hides when the ECU answers again."""

from __future__ import annotations

from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QPushButton

from workbench.gui import theme
from workbench.gui.widgets.status_bar import clock

__all__ = ["LostBanner"]


class LostBanner(QFrame):
    def __init__(self, controller, parent=None):
        super().__init__(parent)
        self.controller = controller
        self.setObjectName("lost-banner")
        self.setStyleSheet(f"QFrame#lost-banner {{ background: #4a1f22; border-bottom: 1px solid {theme.BAD}; }}")
        layout = QHBoxLayout(self)
        layout.setContentsMargins(10, 4, 6, 4)
        self.label = QLabel()
        self.label.setWordWrap(True)
        self.label.setMinimumWidth(0)
        layout.addWidget(self.label, 1)
        self.now_button = QPushButton("Reconnect now")
        self.now_button.clicked.connect(controller.reconnect)
        self.stop_button = QPushButton("Stop trying")
        self.stop_button.clicked.connect(self._stop)
        for button in (self.now_button, self.stop_button):
            layout.addWidget(button)
        self.error = None
        controller.lost.connect(self.show_lost)
        controller.reconnecting.connect(self._attempt)
        controller.connected.connect(lambda _: self.hide())
        self.hide()

    def show_lost(self, exc) -> None:
        self.error = exc
        self._say("reconnecting when the ECU answers again …")
        self.stop_button.setEnabled(True)
        self.show()

    def _attempt(self, number: int) -> None:
        self._say(f"reconnecting: attempt {number} …")

    def _stop(self) -> None:
        self.controller.stop_reconnecting()
        self.stop_button.setEnabled(False)
        self._say("not reconnecting: use Reconnect now when the ECU is back")

    def _say(self, what: str) -> None:
        exc = self.error
        self.label.setText(f"<b>Connection lost at {clock(exc.when)}</b> — {exc.what}: {exc.reason}. {what}")
        self.label.setToolTip(str(exc))
