"""The compare view's rows: one per object of a :class:`~workbench.calib.dataset.DatasetDiff` (working
page vs reference page, the ECU vs a parameter set, two parameter sets), with both values and what
differs; its details: the differing elements of one object. Numbers have the decimals of the A2L's
display format, as in the other views (``decimals(name, where)``, e.g. ``a2l_info.value_decimals``)."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QSortFilterProxyModel, Qt
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.formatting import format_value, with_unit
from workbench.gui.models.rows import RowsModel

__all__ = ["CompareFilter", "CompareModel", "ElementModel", "describe_value", "no_decimals"]

COLUMNS = ("object", "status", "A", "B", "difference")
STATUS_TEXT = {"only-in-a": "only in A", "only-in-b": "only in B", "shape-changed": "shape differs",
               "changed": "differs", "equal": "equal"}
STATUS_COLOUR = {"only-in-a": theme.ACCENT, "only-in-b": theme.ACCENT, "shape-changed": theme.BAD,
                 "changed": theme.WARN, "equal": theme.MUTED}


def no_decimals(name: str, where: str) -> int | None:
    return None


def describe_value(value, decimals: int | None = None) -> str:
    """A CalValue in one cell: a scalar with ``decimals`` and its unit, an array by its kind and shape."""
    if value is None:
        return "—"
    if value.kind in ("VALUE", "ASCII"):
        unit = f" {value.unit}" if value.unit and not isinstance(value.value, str) else ""
        return f"{format_value(value.value, decimals)}{unit}"
    return f"{value.kind} {' x '.join(map(str, np.shape(value.value)))}"


def _difference(diff, decimals) -> str:
    if diff.status == "equal":
        return ""
    if diff.status in ("only-in-a", "only-in-b"):
        return "not in " + ("B" if diff.status == "only-in-a" else "A")
    if diff.status == "shape-changed":
        return "; ".join(f"{d.where}: {d.a} → {d.b}" for d in diff.differences)
    numeric = [d for d in diff.differences if d.delta is not None]
    if len(diff.differences) == 1:
        d = diff.differences[0]
        return f"Δ {_delta(d, decimals(diff.name, d.where))}" if d.delta is not None else f"{d.where}: {d.a} → {d.b}"
    largest = max(numeric, key=lambda d: abs(d.delta)) if numeric else None
    return f"{len(diff.differences)} values" + (
        f", max Δ {_delta(largest, decimals(diff.name, largest.where))}" if largest is not None else "")


def _signed(delta, places: int | None) -> str:
    """B - A with its sign, as the details' column shows it."""
    return f"{delta:+.6g}" if places is None else f"{delta:+.{places}f}"


def _delta(element, places: int | None) -> str:
    """B - A with its sign and, when A and B are in the same unit, the unit (as ``cal diff`` shows it)."""
    unit_a, unit_b = element.units
    return with_unit(_signed(element.delta, places), unit_a if unit_a == unit_b else "")


class CompareModel(RowsModel):
    """Rows: :class:`~workbench.calib.dataset.diff.ObjectDiff`."""

    COLUMNS = COLUMNS

    def __init__(self, parent=None):
        super().__init__(parent)
        self.a_label = "A"
        self.b_label = "B"
        self.decimals = no_decimals  # (object, element "value"/"x[2]") -> the A2L's decimals for it
        self.sorted_by: tuple[int, Qt.SortOrder] = (-1, Qt.AscendingOrder)
        self._objects: list = []  # the diff's order

    def set_diff(self, diff) -> None:
        self.a_label, self.b_label = diff.a_label, diff.b_label
        self._objects = list(diff.objects)
        self.set_rows(self._sorted())
        self.headerDataChanged.emit(Qt.Horizontal, 2, 3)

    def sort(self, column: int, order=Qt.AscendingOrder) -> None:
        """By ``column``'s text (equal texts in the diff's order); -1: the diff's order. Each row's text is made once:
        a QSortFilterProxyModel's sort asked ``data`` twice a comparison (7,000 objects: 1.4 s, the window frozen)."""
        self.sorted_by = (column, order)
        self.reorder(self._sorted())

    def _sorted(self) -> list:
        column, order = self.sorted_by
        if column < 0:
            return list(self._objects)
        return sorted(self._objects, key=lambda diff: self._texts(diff)[column], reverse=order == Qt.DescendingOrder)

    def _texts(self, diff) -> tuple[str, str, str, str, str]:
        places = self.decimals(diff.name, "value")
        return (diff.name, STATUS_TEXT.get(diff.status, diff.status), describe_value(diff.a, places),
                describe_value(diff.b, places), _difference(diff, self.decimals))

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
            return self._texts(diff)[index.column()]
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
    """Only the objects that differ (unless ``show_equal``), whose name contains ``search`` (any case), in the order
    the :class:`CompareModel` sorts them by (a header click sorts the model, not this proxy)."""

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

    def sort(self, column: int, order=Qt.AscendingOrder) -> None:
        self.sourceModel().sort(column, order)

    def filterAcceptsRow(self, source_row, source_parent) -> bool:
        diff = self.sourceModel().rows[source_row]
        if diff.status == "equal" and not self.show_equal:
            return False
        return not self.search or self.search in diff.name.lower()


class ElementModel(RowsModel):
    """The differing elements of one object: where (with the axis points), A, B, B - A."""

    COLUMNS = ("where", "A", "B", "B − A")

    def __init__(self, parent=None):
        super().__init__(parent)
        self.name = ""
        self.decimals = no_decimals

    def show(self, name: str, elements) -> None:
        """The differing elements of object ``name``."""
        self.name = name
        self.set_rows(list(elements))

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid() or role not in (Qt.DisplayRole, Qt.TextAlignmentRole):
            return None
        element = self.rows[index.row()]
        if role == Qt.TextAlignmentRole:
            return int(Qt.AlignRight | Qt.AlignVCenter) if index.column() else None
        places = self.decimals(self.name, element.where)
        points = (format_value(p, self.decimals(self.name, axis)) for p, axis in zip(element.at, "xyz"))
        where = element.where + (f" at ({', '.join(points)})" if element.at else "")
        delta = "" if element.delta is None else _signed(element.delta, places)
        return (where, _plain(element.a, places), _plain(element.b, places), delta)[index.column()]


def _plain(value, decimals: int | None) -> str:
    return format_value(value, decimals) if isinstance(value, (int, float, np.number)) else str(value)
