"""The CAN trace's rows: the newest frames on the bus, raw and decoded with the DBC."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.models.rows import RowsModel

__all__ = ["TraceModel"]

class TraceModel(RowsModel):
    """Rows: :class:`~workbench.gui.can_monitor.TraceEntry`, newest last."""

    COLUMNS = ("time [s]", "id", "message", "dlc", "data", "decoded")

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        entry = self.rows[index.row()]
        column = index.column()
        if role == Qt.DisplayRole:
            return (f"{entry.time:.4f}",
                    f"{entry.arbitration_id:08X}x" if entry.extended else f"{entry.arbitration_id:03X}",
                    entry.message or "", str(len(entry.data)), entry.data.hex(" ").upper(), entry.decoded)[column]
        if role == Qt.ForegroundRole:
            if column == 2:
                return QColor(theme.TRACE_COLOURS[2] if entry.message else theme.MUTED)
            if column == 5:
                return QColor(theme.TEXT)
            return QColor(theme.MUTED) if column == 0 else None
        return None
