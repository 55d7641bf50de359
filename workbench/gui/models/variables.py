"""The variable browser's rows: every MEASUREMENT, CHARACTERISTIC and AXIS_PTS of the A2L and every
CAN2 signal of the DBCs, with type, unit, function groups and description; filtered and sorted by the model."""

from __future__ import annotations

import re
from dataclasses import dataclass

from PySide6.QtCore import Qt
from PySide6.QtGui import QColor

from workbench.a2l.model import is_glob, name_pattern
from workbench.gui import theme
from workbench.gui.mime import signals_mime
from workbench.gui.models.rows import RowsModel

__all__ = ["ALL", "Variable", "VariableModel", "variables_of_a2l", "variables_of_dbc",
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


_ROLES = frozenset((Qt.DisplayRole, Qt.ForegroundRole, Qt.ToolTipRole, Qt.UserRole))  # the roles the rows answer


def _display(row: Variable, column: str) -> str:
    """The text of ``row`` in ``column`` as the table shows it (and sorts it)."""
    if column == "kind":
        return KIND_SHORT.get(row.kind) or KIND_LABELS.get(row.kind, row.kind)
    if column == "functions":
        return ", ".join(row.functions)
    return getattr(row, column)


class VariableModel(RowsModel):
    """Rows: the :class:`Variable` objects that pass the filters (:meth:`set_filters`: the search, words or a glob with *
    and ?, and the kind, function and unit chosen; ``ALL``: any), in the order of the column sorted by (:meth:`sort`;
    the A2L's order, the DBCs' signals after, until a header is clicked); drags carry their names.

    Filtered and sorted here, in one pass over the rows, not by a QSortFilterProxyModel, which asks Python about
    every row for a filter and twice for every comparison of a sort: on an A2L of 52,000 objects a keystroke in the
    search took 0.2 s and a sort by name 7.5 s, the window frozen meanwhile."""

    COLUMNS = COLUMNS

    def __init__(self, parent=None):
        super().__init__(parent)
        self.all_rows: list[Variable] = []
        self.search = ""
        self.kind = ALL
        self.function = ALL
        self.unit = ALL
        self.sorted_by: tuple[int, Qt.SortOrder] = (-1, Qt.AscendingOrder)
        self._pattern: re.Pattern | None = None
        self._texts: list[str] = []  # of all_rows: "name description" in lower case, what the words search
        self._order: list[int] = []  # all_rows' indices in the sorted order

    def set_rows(self, rows) -> None:
        """Every row there is (those that pass the filters are shown)."""
        self.all_rows = list(rows)
        self._texts = [f"{row.name} {row.description}".lower() for row in self.all_rows]
        self._order = self._sorted()
        self._show()

    def set_filters(self, *, search: str | None = None, kind: str | None = None, function: str | None = None,
                    unit: str | None = None) -> None:
        if search is not None:
            self.search = search.strip()
            self._pattern = name_pattern(self.search, ignore_case=True) if is_glob(self.search) else None
        if kind is not None:
            self.kind = kind
        if function is not None:
            self.function = function
        if unit is not None:
            self.unit = unit
        self._show()

    def sort(self, column: int, order=Qt.AscendingOrder) -> None:
        """By ``column``'s text, case-insensitively (equal texts in the A2L's order); -1: the A2L's order. The rows
        shown stay, in another order: the selection stays on its rows."""
        self.sorted_by = (column, order)
        self._order = self._sorted()
        passing = self._passing()
        rows = [self.all_rows[i] for i in self._order if passing[i]]
        self.layoutAboutToBeChanged.emit()
        where = {id(row): number for number, row in enumerate(rows)}
        before = self.persistentIndexList()
        after = [self.index(where[id(self.rows[index.row()])], index.column()) for index in before]
        self.rows = rows
        self.changePersistentIndexList(before, after)
        self.layoutChanged.emit()

    def _sorted(self) -> list[int]:
        column, order = self.sorted_by
        if column < 0:
            return list(range(len(self.all_rows)))
        title, rows = COLUMNS[column], self.all_rows
        return sorted(range(len(rows)), key=lambda i: _display(rows[i], title).casefold(),
                      reverse=order == Qt.DescendingOrder)

    def _show(self) -> None:
        passing = self._passing()
        super().set_rows([self.all_rows[i] for i in self._order if passing[i]])

    def _passing(self) -> list[bool]:
        """Whether each of all_rows passes the filters."""
        rows, kind, function, unit, search = self.all_rows, self.kind, self.function, self.unit, self.search
        passing = [(not kind or row.kind == kind) and (not function or function in row.functions)
                   and (not unit or row.unit == unit) for row in rows]
        if not search:
            return passing
        if self._pattern is not None:  # an object's own name stays that object, as on the command line (arr[1])
            match, lower = self._pattern.fullmatch, search.lower()
            return [ok and (match(row.name) is not None or row.name.lower() == lower) for ok, row in zip(passing, rows)]
        words = search.lower().split()
        if len(words) == 1:
            (word,) = words
            return [ok and word in text for ok, text in zip(passing, self._texts)]
        return [ok and all(word in text for word in words) for ok, text in zip(passing, self._texts)]

    def data(self, index, role=Qt.DisplayRole):
        if role not in _ROLES or not index.isValid():  # first: Qt asks a dozen roles a cell (sizing a column: 1,000s)
            return None
        row = self.rows[index.row()]
        column = COLUMNS[index.column()]
        if role == Qt.DisplayRole:
            return _display(row, column)
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
