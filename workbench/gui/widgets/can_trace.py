"""The CAN trace: the newest frames of the ECU's bus (XCP and CAN2), raw and decoded with the DBCs."""

from __future__ import annotations

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QAbstractItemView, QCheckBox, QHBoxLayout, QLabel, QTableView, QVBoxLayout, QWidget

from workbench.gui import theme
from workbench.gui.models.trace import TraceModel
from workbench.gui.widgets.columns import share_columns

__all__ = ["CanTrace"]

REFRESH_MS = 200
SHOWN = 500


class CanTrace(QWidget):
    def __init__(self, hub, parent: QWidget | None = None):
        super().__init__(parent)
        self.hub = hub
        self.model = TraceModel(self)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        bar = QHBoxLayout()
        self.known_only = QCheckBox("DBC messages only")
        self.known_only.setToolTip("hide frames the DBCs do not describe (XCP on CAN1)")
        self.pause = QCheckBox("pause")
        self.summary = QLabel()
        self.summary.setStyleSheet(f"color: {theme.MUTED};")
        bar.addWidget(self.known_only)
        bar.addWidget(self.pause)
        bar.addStretch(1)
        bar.addWidget(self.summary)
        layout.addLayout(bar)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setFont(theme.mono_font(9))
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(20)
        self.table.setShowGrid(False)
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        # eight data bytes whole on a laptop (XCP frames have nothing decoded: that column gives the room)
        share_columns(self.table, (1, 0.8, 2, 0.5, 3.5, 2.5))  # time, id, message, dlc, data, decoded
        layout.addWidget(self.table)
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        self.timer.start()

    def clear(self) -> None:
        """No frames (another project opens: they were decoded with its DBCs)."""
        self.model.set_rows([])
        self.summary.setText("")

    def refresh(self) -> None:
        monitor = self.hub.can_monitor
        if monitor is None or self.pause.isChecked() or not self.isVisible():
            return
        entries = monitor.trace_snapshot()
        if self.known_only.isChecked():
            entries = [e for e in entries if e.message]
        self.model.set_rows(entries[-SHOWN:])
        self.table.scrollToBottom()
        self.summary.setText(f"{monitor.frames} frames")
