"""The fix-calibration panel (thesis chapter 6): every signal with an ``_EN``/``_VALUE`` pair, its live
value, the override value and a switch. Switching on writes ``_VALUE`` then ``_EN`` = 1 through the
session; the table refreshes every second while it is visible."""

from __future__ import annotations

from PySide6.QtCore import QTimer, Signal
from PySide6.QtWidgets import QAbstractItemView, QHeaderView, QLabel, QTableView, QVBoxLayout, QWidget

from workbench.gui import theme
from workbench.gui.formatting import format_value
from workbench.gui.models.fixes import FixModel

__all__ = ["FixPanel"]

REFRESH_MS = 1000


class FixPanel(QWidget):
    refreshed = Signal()
    error = Signal(object)

    def __init__(self, controller, hub=None, parent: QWidget | None = None):
        super().__init__(parent)
        self.controller = controller
        self.model = FixModel(self, formatter=(lambda name, value: hub.info(name).format(value) if name
                                               else format_value(value)) if hub is not None else None)
        self.model.override_requested.connect(self.override)
        self.model.enable_requested.connect(lambda fix: controller.write(fix.pair.enable, 1, on_error=self.error.emit))
        self.model.release_requested.connect(self.release)
        self.model.value_requested.connect(lambda fix, value: controller.write(fix.pair.value, value,
                                                                               on_error=self.error.emit))
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        hint = QLabel("Tick <b>on</b> to replace a signal by its override value (…_EN = 1); double-click the value "
                      "to change it.")
        hint.setWordWrap(True)
        hint.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(hint)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setFont(theme.mono_font())
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(22)
        self.table.setShowGrid(False)
        self.table.setAlternatingRowColors(True)
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeToContents)
        header.setSectionResizeMode(0, QHeaderView.Stretch)
        layout.addWidget(self.table)
        self._busy = False
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        controller.connected.connect(lambda _: (self.refresh(), self.timer.start()))
        controller.disconnected.connect(self.timer.stop)
        controller.written.connect(lambda _: self.refresh())

    def refresh(self) -> None:
        """Read every fix's state (one request in flight at a time)."""
        if self._busy or not self.controller.is_connected:
            return
        self._busy = True
        task = self.controller.call("fixes", on_done=self._show, on_error=self._failed)
        if task is None:
            self._busy = False

    def _show(self, fixes) -> None:
        self._busy = False
        self.model.set_fixes(fixes)
        self.refreshed.emit()

    def _failed(self, exc) -> None:
        self._busy = False
        self.timer.stop()  # one dialog, not one a second
        self.error.emit(exc)

    def override(self, fix, value: float) -> None:
        self.controller.call("override", fix.pair.stem, value, on_done=lambda _: self.controller.written.emit(
            fix.pair.enable), on_error=self.error.emit)

    def release(self, fix) -> None:
        self.controller.call("release", fix.pair.stem, on_done=lambda _: self.controller.written.emit(
            fix.pair.enable), on_error=self.error.emit)
