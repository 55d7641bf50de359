"""The compare view's rows: one per object of a :class:`~workbench.calib.dataset.DatasetDiff` (working
page vs reference page, the ECU vs a parameter set, two parameter sets), with both values and what
differs; its details: the differing elements of one object."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QSortFilterProxyModel, Qt
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.formatting import format_value
from workbench.gui.models.rows import RowsModel

__all__ = ["CompareFilter", "CompareModel", "ElementModel", "describe_value"]

COLUMNS = ("object", "status", "A", "B", "difference")
STATUS_TEXT = {"only-in-a": "only in A", "only-in-b": "only in B", "shape-changed": "shape differs",
               "changed": "differs", "equal": "equal"}
STATUS_COLOUR = {"only-in-a": theme.ACCENT, "only-in-b": theme.ACCENT, "shape-changed": theme.BAD,
                 "changed": theme.WARN, "equal": theme.MUTED}


def describe_value(value) -> str:
    """A CalValue in one cell: a scalar with its unit, an array by its kind and shape."""
    if value is None:
        return "—"
    if value.kind in ("VALUE", "ASCII"):
        unit = f" {value.unit}" if value.unit and not isinstance(value.value, str) else ""
        return f"{format_value(value.value)}{unit}"
    return f"{value.kind} {' x '.join(map(str, np.shape(value.value)))}"


def _difference(diff) -> str:
    if diff.status == "equal":
        return ""
    if diff.status in ("only-in-a", "only-in-b"):
        return "not in " + ("B" if diff.status == "only-in-a" else "A")
    if diff.status == "shape-changed":
        return "; ".join(f"{d.where}: {d.a} → {d.b}" for d in diff.differences)
    deltas = [d.delta for d in diff.differences if d.delta is not None]
    if len(diff.differences) == 1:
        d = diff.differences[0]
        return f"Δ {format_value(d.delta)}" if d.delta is not None else f"{d.where}: {d.a} → {d.b}"
    largest = max(deltas, key=abs) if deltas else None
    return f"{len(diff.differences)} values" + (f", max Δ {format_value(largest)}" if largest is not None else "")


class CompareModel(RowsModel):
    """Rows: :class:`~workbench.calib.dataset.diff.ObjectDiff`."""

    COLUMNS = COLUMNS

    def __init__(self, parent=None):
        super().__init__(parent)
        self.a_label = "A"
        self.b_label = "B"

    def set_diff(self, diff) -> None:
        self.a_label, self.b_label = diff.a_label, diff.b_label
        self.set_rows(diff.objects)
        self.headerDataChanged.emit(Qt.Horizontal, 2, 3)

    def headerData(self, section, orientation, role=Qt.DisplayRole):
        if orientation == Qt.Horizontal and role == Qt.ToolTipRole and section in (2, 3):
            return self.a_label if section == 2 else self.b_label
        return super().headerData(section, orientation, role)

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        diff = self.rows[index.row()]
        column = COLUMNS[index.column()]
        if role == Qt.DisplayRole:
            return {"object": diff.name, "status": STATUS_TEXT.get(diff.status, diff.status),
                    "A": describe_value(diff.a), "B": describe_value(diff.b), "difference": _difference(diff)}[column]
        if role == Qt.ForegroundRole and column == "status":
            return QColor(STATUS_COLOUR.get(diff.status, theme.TEXT))
        if role == Qt.TextAlignmentRole and column in ("A", "B"):
            return int(Qt.AlignRight | Qt.AlignVCenter)
        if role == Qt.ToolTipRole:
            return f"{diff.name}\nA: {self.a_label}\nB: {self.b_label}"
        if role == Qt.UserRole:
            return diff
        return None


class CompareFilter(QSortFilterProxyModel):
    """Only the objects that differ (unless ``show_equal``), whose name contains ``search`` (any case)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.show_equal = False
        self.search = ""

    def set_filter(self, *, show_equal: bool | None = None, search: str | None = None) -> None:
        changing = hasattr(self, "beginFilterChange")  # Qt 6.10 (invalidateFilter is deprecated there)
        if changing:
            self.beginFilterChange()
        if show_equal is not None:
            self.show_equal = show_equal
        if search is not None:
            self.search = search.strip().lower()
        if changing:
            self.endFilterChange(QSortFilterProxyModel.Direction.Rows)
        else:
            self.invalidateFilter()

    def filterAcceptsRow(self, source_row, source_parent) -> bool:
        diff = self.sourceModel().rows[source_row]
        if diff.status == "equal" and not self.show_equal:
            return False
        return not self.search or self.search in diff.name.lower()


class ElementModel(RowsModel):
    """The differing elements of one object: where (with the axis points), A, B, B - A."""

    COLUMNS = ("where", "A", "B", "B − A")

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid() or role not in (Qt.DisplayRole, Qt.TextAlignmentRole):
            return None
        element = self.rows[index.row()]
        if role == Qt.TextAlignmentRole:
            return int(Qt.AlignRight | Qt.AlignVCenter) if index.column() else None
        where = element.where + (f" at ({', '.join(format_value(p) for p in element.at)})" if element.at else "")
        return (where, _plain(element.a), _plain(element.b),
                "" if element.delta is None else f"{element.delta:+.6g}")[index.column()]


def _plain(value) -> str:
    return format_value(value) if isinstance(value, (int, float, np.number)) else str(value)
