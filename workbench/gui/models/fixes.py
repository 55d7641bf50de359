"""The fix-calibration panel's rows: every ``_EN``/``_VALUE`` pair with the signal it overrides, the
signal's live value, the override value and whether the override is on (``session.fixes()``).

The live value is the measurement the A2L links to the pair (its COMPARISON_QUANTITY) or names so
(:mod:`workbench.calib.fixes`); where there is none (a third-party A2L whose sent signal is computed under
another name) it comes from ``bus_value(fix)``: the window's CAN2 monitor. Live and override read alike, as
``cal fix --list`` prints them: the ``_VALUE``'s verbal table (``Low``; the measurement's own ``xsLEDEn = ON``
in the tooltip) and display format (``value_format``)."""

from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.formatting import format_value, parse_typed
from workbench.gui.models.rows import RowsModel

__all__ = ["FixModel"]

COLUMNS = ("signal", "live", "override", "on", "kind")
KIND_SHORT = {"CAN signal": "CAN", "sensor": "sensor"}
ON = COLUMNS.index("on")
OVERRIDE = COLUMNS.index("override")


class FixModel(RowsModel):
    """Rows: the session's :class:`~workbench.session.fixes.FixState` objects; checking "on" or editing
    "override" emits a request (the panel sends it to the ECU; the next refresh shows the result)."""

    COLUMNS = COLUMNS
    override_requested = Signal(object, object)  # the fix state, the value (a number or a verbal value's text)
    enable_requested = Signal(object)  # switch the override on with the _VALUE the ECU holds
    release_requested = Signal(object)
    value_requested = Signal(object, object)  # a new override value while the override is off

    def __init__(self, parent=None, value_format=None, bus_value=None):
        super().__init__(parent)
        # (_VALUE name, value) -> text: a live or override value in the _VALUE's A2L format
        self.value_format = value_format or (lambda name, value: format_value(value))
        self.bus_value = bus_value or (lambda fix: None)  # FixState -> the signal's text as sent on the bus, or None
        self.read_only = ""  # why nothing can be typed or switched now ("": it can)
        self.stale = False  # the values are the last ones read, not current (greyed)

    def set_read_only(self, why: str, stale: bool = False) -> None:
        self.read_only, self.stale = why, stale
        if self.rows:
            self.dataChanged.emit(self.index(0, 0), self.index(len(self.rows) - 1, len(COLUMNS) - 1))

    def live_text(self, fix) -> str:
        if fix.live is None and fix.pair.live is None:
            on_bus = self.bus_value(fix)
            if on_bus is not None:
                return on_bus
        return self.value_format(fix.pair.value, fix.live)

    def _live_source(self, fix) -> str:
        if fix.pair.live is None:
            return ("live: as sent on CAN2" if self.bus_value(fix) is not None else
                    "live: the A2L has no measurement of it")
        if fix.measured is not None and fix.measured != fix.live:
            return (f"live: {fix.pair.live} = {format_value(fix.measured)}, which {fix.pair.value} calls "
                    f"{format_value(fix.live)}")
        return f"live: {fix.pair.live}"

    def set_fixes(self, fixes) -> None:
        """New states; the same pairs as before only repaint (an open cell editor stays open)."""
        fixes = list(fixes)
        if [f.pair.stem for f in fixes] != [f.pair.stem for f in self.rows]:
            self.set_rows(fixes)
            return
        self.rows = fixes
        if fixes:
            self.dataChanged.emit(self.index(0, 0), self.index(len(fixes) - 1, len(COLUMNS) - 1))

    def data(self, index, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        fix = self.rows[index.row()]
        column = COLUMNS[index.column()]
        if role == Qt.DisplayRole:
            return {"signal": fix.pair.signal, "kind": KIND_SHORT.get(fix.pair.kind, fix.pair.kind),
                    "live": self.live_text(fix),
                    "override": self.value_format(fix.pair.value, fix.override), "on": None}[column]
        if role == Qt.EditRole and column == "override":
            return fix.override
        if role == Qt.CheckStateRole and column == "on":
            return Qt.Checked if fix.active else Qt.Unchecked
        if role == Qt.ForegroundRole:
            if column == "kind" or (self.stale and column != "signal"):
                return QColor(theme.MUTED)
            if column == "live" and fix.active:
                return QColor(theme.WARN)
        if role == Qt.TextAlignmentRole and column in ("live", "override"):
            return int(Qt.AlignRight | Qt.AlignVCenter)
        if role == Qt.ToolTipRole:
            return (f"{fix.pair.signal} ({fix.pair.kind})\n{fix.pair.enable} / {fix.pair.value}: while "
                    f"{fix.pair.enable} = 1 the ECU uses {fix.pair.value} instead of {fix.pair.signal}\n"
                    f"{self._live_source(fix)}\noverride: Enter writes, Esc restores"
                    + ("\nnot current" if self.stale else "")
                    + (f"\nread-only: {self.read_only}" if self.read_only else ""))
        return None

    def flags(self, index):
        flags = super().flags(index)
        if self.read_only:
            return flags
        if index.column() == ON:
            return flags | Qt.ItemIsUserCheckable
        if index.column() == OVERRIDE:
            return flags | Qt.ItemIsEditable
        return flags

    def setData(self, index, value, role=Qt.EditRole) -> bool:
        fix = self.rows[index.row()]
        if index.column() == ON and role == Qt.CheckStateRole:
            if Qt.CheckState(value) == Qt.Checked:  # not override(shown value): the row may be a refresh behind
                self.enable_requested.emit(fix)
            else:
                self.release_requested.emit(fix)
            return True
        if index.column() == OVERRIDE and role == Qt.EditRole:  # as typed: the session checks it
            if isinstance(value, str):
                try:
                    value = parse_typed(value)
                except ValueError:
                    pass  # a verbal value's text
            if fix.active:
                self.override_requested.emit(fix, value)
            else:
                self.value_requested.emit(fix, value)
            return True
        return False
