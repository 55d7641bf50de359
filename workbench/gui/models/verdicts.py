"""The tests of a requirement test run as the window's *Requirement tests* dialog shows them: one row per test, its
verdict (or pending, running), requirement ids, time and one-line reason, coloured as the report colours them."""

from __future__ import annotations

from PySide6.QtCore import QModelIndex, Qt
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.models.rows import RowsModel

__all__ = ["VerdictsModel"]

_SHOWN = {"passed": "PASSED", "failed": "FAILED", "not judged": "NOT JUDGED", "error": "ERROR", "skipped": "SKIPPED",
          "interrupted": "INTERRUPTED", "running": "running", "pending": "", "cancelled": "CANCELLED"}
_COLOUR = {"passed": theme.GOOD, "failed": theme.BAD, "not judged": theme.WARN, "error": theme.WARN,
           "skipped": theme.MUTED, "interrupted": theme.MUTED, "cancelled": theme.MUTED, "running": theme.ACCENT}
_MEANING = {"passed": "every expectation held", "failed": "an expectation did not hold: the ECU broke the requirement",
            "not judged": "the test broke before it judged (the ECU lost, CAN2 silent, a mistake in the test): its "
                          "requirements are neither verified nor failed",
            "error": "the test could not start or end (no ECU, another EPK, a value it could not restore)",
            "skipped": "not run here (e.g. it needs the simulated ECU's faults)",
            "interrupted": "the run stopped during this test", "cancelled": "the run was cancelled before its end"}


class VerdictsModel(RowsModel):
    """The tests of a run, each ``{"nodeid", "state", "requirements", "message", "duration"}`` (state: pending,
    running, or a verdict)."""

    COLUMNS = ("Verdict", "Requirements", "Test", "Time", "Reason")

    def __init__(self, parent=None):
        super().__init__(parent)
        self.by_id: dict[str, dict] = {}

    def clear(self) -> None:
        self.by_id = {}
        self.set_rows([])

    def row_of(self, nodeid: str) -> dict:
        row = self.by_id.get(nodeid)
        if row is None:
            row = self.by_id[nodeid] = {"nodeid": nodeid, "state": "pending", "requirements": [], "message": "",
                                        "duration": None}
            self.beginInsertRows(QModelIndex(), len(self.rows), len(self.rows))
            self.rows.append(row)
            self.endInsertRows()
        return row

    def end(self, cancelled: bool) -> None:
        """The run ended: the tests still to come were cancelled, so were those running (interrupted when the run
        stopped by itself)."""
        for row in self.rows:
            if row["state"] in ("pending", "running"):
                row["state"] = "cancelled" if cancelled or row["state"] == "pending" else "interrupted"
        self.layoutChanged.emit()

    def changed(self, nodeid: str) -> None:
        number = self.rows.index(self.by_id[nodeid])
        self.dataChanged.emit(self.index(number, 0), self.index(number, len(self.COLUMNS) - 1))

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        row, column = self.rows[index.row()], index.column()
        if role == Qt.ForegroundRole and column == 0:
            colour = _COLOUR.get(row["state"])
            return QColor(colour) if colour else None
        if role == Qt.ToolTipRole:
            return _MEANING.get(row["state"]) if column == 0 else (row["message"] or None) if column == 4 else \
                self.data(index)
        if role != Qt.DisplayRole:
            return None
        if column == 0:
            return _SHOWN[row["state"]]
        if column == 1:
            return ", ".join(row["requirements"])
        if column == 2:
            return row["nodeid"]
        if column == 3:
            return f"{row['duration']:.1f} s" if row["duration"] is not None else ""
        return row["message"]
