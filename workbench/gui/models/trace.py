"""The CAN trace's rows: the newest frames on the bus, raw and decoded with the DBC."""

from __future__ import annotations

from PySide6.QtCore import QAbstractTableModel, QModelIndex, Qt
from PySide6.QtGui import QColor

from workbench.gui import theme

__all__ = ["TraceModel"]

COLUMNS = ("time [s]", "id", "message", "dlc", "data", "decoded")


class TraceModel(QAbstractTableModel):
    def __init__(self, parent=None):
        super().__init__(parent)
        self.rows: list = []  # TraceEntry, newest last

    def set_entries(self, entries) -> None:
        self.beginResetModel()
        self.rows = list(entries)
        self.endResetModel()

    def rowCount(self, parent=QModelIndex()) -> int:
        return 0 if parent.isValid() else len(self.rows)

    def columnCount(self, parent=QModelIndex()) -> int:
        return 0 if parent.isValid() else len(COLUMNS)

    def headerData(self, section, orientation, role=Qt.DisplayRole):
        if orientation == Qt.Horizontal and role == Qt.DisplayRole:
            return COLUMNS[section]
        return None

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
