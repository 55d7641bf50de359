"""The variable browser's rows: every MEASUREMENT, CHARACTERISTIC and AXIS_PTS of the A2L and every
CAN2 signal of the DBCs, with type, unit, function groups and description; filtered and sorted by the model."""

from __future__ import annotations

import re
from typing import NamedTuple

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


class Variable(NamedTuple):
    """A row (a tuple: 130,000 of them are a tenth of a second and 20 MB, where frozen dataclasses took four times)."""

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
    """Rows for an :class:`~workbench.a2l.model.A2lModel`: its listing, plus FUNCTION membership (the model's reverse
    index of the FUNCTIONs' lists: building each FUNCTION took seconds for an A2L of 100,000 objects)."""
    membership = model.membership
    return [Variable(row.name, row.kind, row.type, row.unit, membership(row.name)[0], row.long_identifier)
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

    Filtered and sorted here, not by a QSortFilterProxyModel, which asks Python about every row for a filter and twice
    for every comparison of a sort: on an A2L of 52,000 objects a keystroke in the search took 0.2 s and a sort by name
    7.5 s, the window frozen meanwhile. A letter typed onto the search looks only at the rows the search before it
    found (its words hold the words before), and a letter taken back finds the rows it had: typing in an A2L of
    130,000 objects passes over all of them once, at the first letter."""

    COLUMNS = COLUMNS

    def __init__(self, parent=None):
        super().__init__(parent)
        self.all_rows: list[Variable] = []
        self.search = ""
        self.kind = ALL
        self.function = ALL
        self.unit = ALL
        self.sorted_by: tuple[int, Qt.SortOrder] = (-1, Qt.AscendingOrder)
        self.scanned = 0  # rows the searches looked at (what a test counts)
        self._pattern: re.Pattern | None = None
        self._texts: list[str] = []  # of all_rows: "name description" in lower case, what the words search
        self._order: list[int] = []  # all_rows' indices in the sorted order
        self._chosen: list[int] | None = None  # of _order: those of the kind, function and unit chosen (None: unknown)
        self._typed: list[tuple[str, list[int]]] = []  # word searches each typed onto the one before: what they found
        self._by_name: dict[str, Variable] | None = None

    def set_rows(self, rows) -> None:
        """Every row there is (those that pass the filters are shown); the kind, function and unit chosen start over
        (any), the search stays."""
        self.all_rows = list(rows)
        self._texts = [f"{row.name} {row.description}".lower() for row in self.all_rows]
        self._by_name = None
        self.kind = self.function = self.unit = ALL
        self._order = self._sorted()
        self._forget()
        self._show()

    def variable(self, name: str) -> Variable | None:
        """The row named ``name`` (whether shown or not)."""
        if self._by_name is None:
            self._by_name = {}
            for row in reversed(self.all_rows):  # the first of a name, as a search lists it first
                self._by_name[row.name] = row
        return self._by_name.get(name)

    def set_filters(self, *, search: str | None = None, kind: str | None = None, function: str | None = None,
                    unit: str | None = None) -> None:
        if search is not None:
            self.search = search.strip()
            self._pattern = name_pattern(self.search, ignore_case=True) if is_glob(self.search) else None
        chosen = {"kind": kind, "function": function, "unit": unit}
        if any(value is not None and value != getattr(self, key) for key, value in chosen.items()):
            for key, value in chosen.items():
                if value is not None:
                    setattr(self, key, value)
            self._forget()
        self._show()

    def sort(self, column: int, order=Qt.AscendingOrder) -> None:
        """By ``column``'s text, case-insensitively (equal texts in the A2L's order); -1: the A2L's order. The rows
        shown stay, in another order: the selection stays on its rows."""
        self.sorted_by = (column, order)
        shown = {id(row) for row in self.rows}
        self._order = self._sorted()
        self._forget()
        self.reorder([row for row in map(self.all_rows.__getitem__, self._order) if id(row) in shown])

    def _sorted(self) -> list[int]:
        column, order = self.sorted_by
        if column < 0:
            return list(range(len(self.all_rows)))
        title, rows = COLUMNS[column], self.all_rows
        return sorted(range(len(rows)), key=lambda i: _display(rows[i], title).casefold(),
                      reverse=order == Qt.DescendingOrder)

    def _forget(self) -> None:
        """The rows, their order or the kind, function or unit changed: what the searches found is no longer so."""
        self._chosen = None
        self._typed = []

    def _show(self) -> None:
        super().set_rows(map(self.all_rows.__getitem__, self._passing()))

    def _passing(self) -> list[int]:
        """all_rows' indices that pass the filters, in the sorted order."""
        search = self.search
        if not search:
            return self._of_chosen()
        if self._pattern is not None:  # an object's own name stays that object, as on the command line (arr[1])
            match, lower, rows = self._pattern.fullmatch, search.lower(), self.all_rows
            candidates = self._of_chosen()
            self.scanned += len(candidates)
            return [i for i in candidates if match(rows[i].name) is not None or rows[i].name.lower() == lower]
        search = search.lower()
        while self._typed and not search.startswith(self._typed[-1][0]):  # letters taken back (or another search)
            self._typed.pop()
        if self._typed and self._typed[-1][0] == search:
            return self._typed[-1][1]
        candidates = self._typed[-1][1] if self._typed else self._of_chosen()  # typed on: within what was found
        self.scanned += len(candidates)
        texts = self._texts
        for word in search.split():
            candidates = [i for i in candidates if word in texts[i]]
        self._typed.append((search, candidates))
        return candidates

    def _of_chosen(self) -> list[int]:
        """_order's indices of the kind, function and unit chosen."""
        if self._chosen is None:
            kind, function, unit, rows = self.kind, self.function, self.unit, self.all_rows
            self._chosen = self._order if not (kind or function or unit) else [
                i for i in self._order if (not kind or rows[i].kind == kind)
                and (not function or function in rows[i].functions) and (not unit or rows[i].unit == unit)]
        return self._chosen

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
        """The names of the rows dragged, each once (a cell per column is given), in the order given."""
        return signals_mime(list(dict.fromkeys(self.rows[index.row()].name for index in indexes)))
