"""A numeric view: signals as a table of live values with units (CANape's "numeric window"). While nothing is measured
(not connected, the connection lost, flashing: ``not_current`` says why) the last values stay, greyed, the reason in
their tooltips: never shown as live."""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QAbstractItemView, QTableWidget, QTableWidgetItem

from workbench.gui import theme
from workbench.gui.mime import SignalDropTarget
from workbench.gui.signal_hub import SignalHub
from workbench.gui.widgets.columns import refit_columns, share_columns
from workbench.gui.widgets.names import NameDelegate

__all__ = ["NumericView"]

REFRESH_MS = 100


class NumericView(SignalDropTarget, QTableWidget):
    signals_changed = Signal(list)

    def __init__(self, hub: SignalHub, parent=None):
        super().__init__(0, 4, parent)
        self.hub = hub
        self.not_current: Callable[[], str] = lambda: ""  # why the values are not live now ("": they are)
        self._names: list[str] = []
        self.setHorizontalHeaderLabels(["signal", "value", "unit", "source"])
        self.verticalHeader().hide()
        self.verticalHeader().setDefaultSectionSize(22)
        self.setShowGrid(False)
        self.setAlternatingRowColors(True)
        self.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.setAcceptDrops(True)
        self.viewport().setAcceptDrops(True)
        self.setDragDropMode(QAbstractItemView.DropOnly)
        self.setItemDelegateForColumn(0, NameDelegate(self))  # names keep their distinct ends
        share_columns(self, (3.2, 1.6, 1, 1), fit=(2, 3))  # signal, value, unit, source
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        self.timer.start()

    @property
    def signals(self) -> list[str]:
        return list(self._names)

    def add_signals(self, names) -> None:
        for name in names:
            if name in self._names:
                continue
            info = self.hub.info(name)
            row = self.rowCount()
            self.insertRow(row)
            item = QTableWidgetItem(name)
            item.setToolTip(f"{name}\n{info.description}" if info.description else name)
            self.setItem(row, 0, item)
            value = QTableWidgetItem("—")
            value.setFont(theme.mono_font(11))
            value.setTextAlignment(Qt.AlignRight | Qt.AlignVCenter)
            self.setItem(row, 1, value)
            for column, text in ((2, info.unit), (3, info.source)):
                cell = QTableWidgetItem(text)
                cell.setForeground(QColor(theme.MUTED))
                self.setItem(row, column, cell)
            self._names.append(name)
        refit_columns(self)
        self.hub.show(self, self._names)
        self.signals_changed.emit(self.signals)

    def remove_signals(self, names) -> None:
        for name in names:
            if name in self._names:
                self.removeRow(self._names.index(name))
                self._names.remove(name)
        self.hub.show(self, self._names)
        self.signals_changed.emit(self.signals)

    def refresh(self) -> None:
        if not self.isVisible():
            return
        why = self.not_current()
        colour = QColor(theme.MUTED) if why else self.palette().text().color()
        for row, name in enumerate(self._names):
            last = self.hub.buffer(name).last()
            item = self.item(row, 1)
            item.setText(self.hub.info(name).format(None if last is None else last[1]))
            item.setForeground(colour)
            item.setToolTip(f"not current: {why} (the last value measured)" if why else "")

    def keyPressEvent(self, event) -> None:
        if event.key() in (Qt.Key_Delete, Qt.Key_Backspace):
            self.remove_signals([self._names[i.row()] for i in self.selectionModel().selectedRows()])
            return
        super().keyPressEvent(event)
