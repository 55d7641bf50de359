"""A CURVE or MAP as a table: X across, Y down (as CANape shows them), shaded by value, cells that
differ from the reference page marked, edits handed out as whole new arrays (the session checks
their limits when it writes them: one rule for every editor)."""

from __future__ import annotations

import itertools
import math

import numpy as np
from PySide6.QtCore import QAbstractTableModel, QModelIndex, Qt, Signal
from PySide6.QtGui import QColor, QFont

from workbench.gui import theme
from workbench.gui.formatting import format_value

__all__ = ["OPERATING_POINT_ROLE", "CalibrationTableModel", "colour_map", "shade"]

OPERATING_POINT_ROLE = Qt.UserRole + 1  # True for the cells around the operating point (framed by the table)

# dark blue -> teal -> amber -> red: readable light text on every step
_STOPS = ((0.0, (38, 70, 140)), (0.35, (26, 120, 130)), (0.7, (160, 120, 30)), (1.0, (170, 50, 50)))


def shade(fraction: float) -> QColor:
    """The cell colour for a value at ``fraction`` (0..1) of the table's range."""
    fraction = min(max(fraction, 0.0), 1.0)
    for (f0, c0), (f1, c1) in zip(_STOPS, _STOPS[1:]):
        if fraction <= f1:
            t = (fraction - f0) / (f1 - f0)
            return QColor(*(round(a + (b - a) * t) for a, b in zip(c0, c1)))
    return QColor(*_STOPS[-1][1])


def colour_map():
    """The same colours as a pyqtgraph colour map (the heat map beside the table)."""
    import pyqtgraph as pg

    return pg.ColorMap([stop for stop, _ in _STOPS], [colour for _, colour in _STOPS])


class CalibrationTableModel(QAbstractTableModel):
    """``value``: shape (nx,) for a curve or (nx, ny) for a map, indexed [x, y]; ``axes``: their points."""

    edited = Signal(object)  # the whole new array after one cell changed
    refused = Signal(str)  # why an entry was not taken

    def __init__(self, parent=None):
        super().__init__(parent)
        self.value = np.zeros((0,))
        self.reference: np.ndarray | None = None
        self.x_points: np.ndarray = np.zeros(0)
        self.y_points: np.ndarray | None = None
        self.decimals: int | None = None
        self.axis_decimals: tuple[int | None, ...] = ()  # the A2L's decimals of the X (and Y) points
        self.read_only = ""  # why nothing can be written now (greyed cells, the reason in their tooltips); "": writable
        self.axis_labels: tuple[str, str | None] | None = None  # "target [bar]" of X, of Y (set by the table)
        self.operating_cells: frozenset[tuple[int, ...]] = frozenset()  # the cells around the operating point

    def set_value(self, value: np.ndarray, x_points, y_points=None, *, decimals=None, axis_decimals=()) -> None:
        """New values; of the same shape they repaint in place, so a selected range stays selected for the
        next block operation (a reset would clear it after every write)."""
        value = np.array(value, dtype=np.float64)
        same_shape = value.shape == self.value.shape and value.size > 0
        if not same_shape:
            self.beginResetModel()
            self.operating_cells = frozenset()
        self.value = value
        self.x_points = np.asarray(x_points, dtype=np.float64)
        self.y_points = None if y_points is None else np.asarray(y_points, dtype=np.float64)
        self.decimals = decimals
        self.axis_decimals = tuple(axis_decimals)
        if not same_shape:
            self.endResetModel()
            return
        self.dataChanged.emit(self.index(0, 0), self.index(self.rowCount() - 1, self.columnCount() - 1))
        self.headerDataChanged.emit(Qt.Horizontal, 0, self.columnCount() - 1)
        self.headerDataChanged.emit(Qt.Vertical, 0, self.rowCount() - 1)

    def point_texts(self) -> list[str]:
        """The X breakpoints as the header shows them."""
        return [self.point_text(0, p) for p in self.x_points]

    def cell_texts(self):
        """(cell, text) of every value (their widths, with the breakpoints', size the columns)."""
        for cell in np.ndindex(*self.value.shape):
            yield cell, format_value(float(self.value[cell]), self.decimals)

    def set_read_only(self, why: str) -> None:
        self.read_only = why
        if self.rowCount() and self.columnCount():
            self.dataChanged.emit(self.index(0, 0), self.index(self.rowCount() - 1, self.columnCount() - 1))

    def set_reference(self, reference: np.ndarray | None) -> None:
        self.reference = None if reference is None else np.array(reference, dtype=np.float64)
        if self.rowCount() and self.columnCount():
            self.dataChanged.emit(self.index(0, 0), self.index(self.rowCount() - 1, self.columnCount() - 1))

    def set_operating_point(self, position: tuple[float, ...] | None) -> None:
        """The cells around ``position`` (a fractional index per axis, X first; None: none) are marked: the
        breakpoints either side of it on each axis, the one it is on when it is on one."""
        cells = frozenset() if position is None else frozenset(
            itertools.product(*(sorted({math.floor(p), math.ceil(p)}) for p in position)))
        if cells == self.operating_cells:
            return
        changed, self.operating_cells = self.operating_cells | cells, cells
        for cell in changed:
            index = self.table_index(cell)
            self.dataChanged.emit(index, index, [OPERATING_POINT_ROLE])

    @property
    def is_map(self) -> bool:
        return self.value.ndim == 2

    def rowCount(self, parent=QModelIndex()) -> int:
        if parent.isValid() or not self.value.size:
            return 0
        return self.value.shape[1] if self.is_map else 1

    def columnCount(self, parent=QModelIndex()) -> int:
        return 0 if parent.isValid() or not self.value.size else self.value.shape[0]

    def cell(self, index) -> tuple[int, ...]:
        """The array index ([x] or [x, y]) of a table index."""
        return (index.column(), index.row()) if self.is_map else (index.column(),)

    def table_index(self, cell: tuple[int, ...]):
        """The table index of an array index ([x] or [x, y])."""
        return self.index(cell[1], cell[0]) if self.is_map else self.index(0, cell[0])

    def modified(self, cell: tuple[int, ...]) -> bool:
        if self.reference is None or self.reference.shape != self.value.shape:
            return False
        a, b = self.value[cell], self.reference[cell]
        return not (a == b or (np.isnan(a) and np.isnan(b)))

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        cell = self.cell(index)
        value = float(self.value[cell])
        if role in (Qt.DisplayRole, Qt.EditRole):
            return format_value(value, self.decimals) if role == Qt.DisplayRole else value
        if role == Qt.BackgroundRole:
            low, high = np.nanmin(self.value), np.nanmax(self.value)
            return shade(0.5 if high == low else (value - low) / (high - low))
        if role == Qt.ForegroundRole:
            if self.read_only:
                return QColor(theme.MUTED)
            return QColor(theme.WARN) if self.modified(cell) else QColor("#f2f4f7")
        if role == Qt.FontRole and self.modified(cell):
            font = QFont()
            font.setBold(True)
            return font
        if role == OPERATING_POINT_ROLE:
            return cell in self.operating_cells
        if role == Qt.TextAlignmentRole:
            return int(Qt.AlignRight | Qt.AlignVCenter)
        if role == Qt.ToolTipRole:
            text = f"{format_value(value, self.decimals)}"
            if self.reference is not None and self.modified(cell):
                text += f" (reference page: {format_value(float(self.reference[cell]), self.decimals)})"
            return f"{text}\nread-only: {self.read_only}" if self.read_only else text
        return None

    def headerData(self, section, orientation, role=Qt.DisplayRole):
        if role == Qt.ToolTipRole:  # which axis the breakpoints are: X across, Y down
            label = self.axis_labels[0 if orientation == Qt.Horizontal else 1] if self.axis_labels else ""
            return f"{'X' if orientation == Qt.Horizontal else 'Y'}: {label}" if label else None
        if role != Qt.DisplayRole:
            return None
        if orientation == Qt.Horizontal:
            return self.point_text(0, self.x_points[section]) if section < len(self.x_points) else str(section)
        if self.is_map and self.y_points is not None and section < len(self.y_points):
            return self.point_text(1, self.y_points[section])
        return "value"

    def point_text(self, axis: int, point) -> str:
        """A breakpoint of axis ``axis`` (0: X) with its A2L decimals, as the values have theirs."""
        decimals = self.axis_decimals[axis] if axis < len(self.axis_decimals) else None
        return format_value(float(point), decimals)

    def flags(self, index):
        flags = super().flags(index)
        return flags if self.read_only else flags | Qt.ItemIsEditable

    def setData(self, index, value, role=Qt.EditRole) -> bool:
        """A cell's new value (a number, or its text): the whole array goes to ``edited``, the cell keeps showing
        what the ECU holds until it is read back."""
        if role != Qt.EditRole or not index.isValid():
            return False
        try:
            number = float(str(value).replace(",", ".")) if isinstance(value, str) else float(value)
        except ValueError:
            self.refused.emit(f"{value!r} is not a number")
            return False
        new = self.value.copy()
        new[self.cell(index)] = number
        self.edited.emit(new)  # the editor writes it; the table shows what the ECU reads back
        return True
