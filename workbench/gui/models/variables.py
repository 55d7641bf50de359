"""The variable browser's rows: every MEASUREMENT, CHARACTERISTIC and AXIS_PTS of the A2L and every
CAN2 signal of the DBCs, with type, unit, function groups and description; filtered by a proxy."""

from __future__ import annotations

import re
from dataclasses import dataclass

from PySide6.QtCore import QSortFilterProxyModel, Qt
from PySide6.QtGui import QColor

from workbench.a2l.model import is_glob, name_pattern
from workbench.gui import theme
from workbench.gui.mime import signals_mime
from workbench.gui.models.rows import RowsModel

__all__ = ["ALL", "Variable", "VariableFilter", "VariableModel", "variables_of_a2l", "variables_of_dbc",
           "variables_of_file"]

ALL = ""  # a filter that lets every row through
COLUMNS = ("name", "kind", "type", "unit", "functions", "description")
KIND_LABELS = {"MEASUREMENT": "signal", "CHARACTERISTIC": "calibration", "AXIS_PTS": "axis", "CAN2": "CAN2",
               "MDF": "recorded"}
KIND_SHORT = {"CHARACTERISTIC": "calib."}  # the table's kind column: short, the filter and tooltips say it all
KIND_COLOURS = {"MEASUREMENT": theme.TRACE_COLOURS[0], "CHARACTERISTIC": theme.TRACE_COLOURS[1],
                "AXIS_PTS": theme.TRACE_COLOURS[4], "CAN2": theme.TRACE_COLOURS[2], "MDF": theme.TRACE_COLOURS[6]}


@dataclass(frozen=True)
class Variable:
    name: str
    kind: str  # MEASUREMENT, CHARACTERISTIC, AXIS_PTS, CAN2, MDF (a channel of a measurement file)
    type: str  # VALUE/CURVE/MAP... for a calibration, the data type for a measurement
    unit: str
    functions: tuple[str, ...]
    description: str

    @property
    def plottable(self) -> bool:
        return self.kind in ("MEASUREMENT", "CAN2", "MDF")

    @property
    def editable(self) -> bool:
        return self.kind in ("CHARACTERISTIC", "AXIS_PTS")


def variables_of_a2l(model) -> list[Variable]:
    """Rows for an :class:`~workbench.a2l.model.A2lModel`: its listing, plus FUNCTION membership."""
    functions: dict[str, list[str]] = {}
    for function_name in model.names("FUNCTION"):
        function = model.function(function_name)
        for names in (function.def_characteristics, function.ref_characteristics, function.in_measurements,
                      function.out_measurements, function.loc_measurements):
            for name in names:
                members = functions.setdefault(name, [])
                if function_name not in members:
                    members.append(function_name)
    return [Variable(row.name, row.kind, row.type, row.unit, tuple(functions.get(row.name, ())), row.long_identifier)
            for row in model.summaries(("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS"))]


def variables_of_dbc(signals) -> list[Variable]:
    """Rows for the CAN monitor's :class:`~workbench.gui.can_monitor.DbcSignal`\\ s."""
    return [Variable(s.name, "CAN2", "signal", s.unit, (s.message,), s.comment) for s in signals]


def variables_of_file(file: str, channels) -> list[Variable]:
    """Rows for the channels of a measurement file (:class:`~workbench.gui.offline.FileChannel`), ``file:name``."""
    return [Variable(f"{file}:{c.name}", "MDF", "recorded", c.unit, (file,), c.comment) for c in channels]


class VariableModel(RowsModel):
    """Rows: :class:`Variable`; drags carry their names."""

    COLUMNS = COLUMNS

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        row = self.rows[index.row()]
        column = COLUMNS[index.column()]
        if role == Qt.DisplayRole:
            if column == "kind":
                return KIND_SHORT.get(row.kind) or KIND_LABELS.get(row.kind, row.kind)
            if column == "functions":
                return ", ".join(row.functions)
            return getattr(row, column)
        if role == Qt.ForegroundRole:
            if column == "kind":
                return QColor(KIND_COLOURS.get(row.kind, theme.TEXT))
            if column in ("type", "functions", "description"):
                return QColor(theme.MUTED)
        if role == Qt.ToolTipRole:
            return f"{row.name}\n{row.description}" if row.description else row.name
        if role == Qt.UserRole:
            return row
        return None

    def flags(self, index):
        return super().flags(index) | Qt.ItemIsDragEnabled

    def mimeTypes(self):
        return ["application/x-workbench-names", "text/plain"]

    def mimeData(self, indexes):
        names = []
        for index in indexes:
            name = self.rows[index.row()].name
            if name not in names:
                names.append(name)
        return signals_mime(names)


class VariableFilter(QSortFilterProxyModel):
    """Rows whose name or description matches the search (words, or a glob with * and ?) and whose
    kind, function and unit are the chosen ones (``ALL``: any)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.search = ""
        self.kind = ALL
        self.function = ALL
        self.unit = ALL
        self._pattern: re.Pattern | None = None
        self.setSortCaseSensitivity(Qt.CaseInsensitive)

    def set_filters(self, *, search: str | None = None, kind: str | None = None, function: str | None = None,
                    unit: str | None = None) -> None:
        changing = hasattr(self, "beginFilterChange")  # Qt 6.10 (invalidateFilter is deprecated there)
        if changing:
            self.beginFilterChange()
        if search is not None:
            self.search = search.strip()
            self._pattern = name_pattern(self.search, ignore_case=True) if is_glob(self.search) else None
        if kind is not None:
            self.kind = kind
        if function is not None:
            self.function = function
        if unit is not None:
            self.unit = unit
        if changing:
            self.endFilterChange(QSortFilterProxyModel.Direction.Rows)
        else:
            self.invalidateFilter()

    def filterAcceptsRow(self, source_row, source_parent) -> bool:
        row: Variable = self.sourceModel().rows[source_row]
        if self.kind and row.kind != self.kind:
            return False
        if self.function and self.function not in row.functions:
            return False
        if self.unit and row.unit != self.unit:
            return False
        if not self.search:
            return True
        if self._pattern is not None:  # an object's own name stays that object, as on the command line (arr[1])
            return bool(self._pattern.fullmatch(row.name)) or row.name.lower() == self.search.lower()
        text = f"{row.name} {row.description}".lower()
        return all(word in text for word in self.search.lower().split())
