"""The part every table model of the GUI shares: a list of rows under fixed column titles."""

from __future__ import annotations

from PySide6.QtCore import QAbstractTableModel, QModelIndex, Qt

__all__ = ["RowsModel"]


class RowsModel(QAbstractTableModel):
    """``rows`` shown under ``COLUMNS`` (a subclass's titles); subclasses answer :meth:`data`."""

    COLUMNS: tuple[str, ...] = ()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.rows: list = []

    def set_rows(self, rows) -> None:
        self.beginResetModel()
        self.rows = list(rows)
        self.endResetModel()

    def reorder(self, rows: list) -> None:
        """The same rows in another order (a sort): the selection and current row stay on theirs."""
        self.layoutAboutToBeChanged.emit()
        where = {id(row): number for number, row in enumerate(rows)}
        before = self.persistentIndexList()
        after = [self.index(where[id(self.rows[index.row()])], index.column()) for index in before]
        self.rows = rows
        self.changePersistentIndexList(before, after)
        self.layoutChanged.emit()

    def rowCount(self, parent=QModelIndex()) -> int:
        return 0 if parent.isValid() else len(self.rows)

    def columnCount(self, parent=QModelIndex()) -> int:
        return 0 if parent.isValid() else len(self.COLUMNS)

    def headerData(self, section, orientation, role=Qt.DisplayRole):
        if orientation == Qt.Horizontal and role == Qt.DisplayRole:
            return self.COLUMNS[section]
        return None
