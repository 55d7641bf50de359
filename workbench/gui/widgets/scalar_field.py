"""A scalar calibration's input: a :class:`~workbench.gui.widgets.value_input.ValueEdit` in physical
units (or the texts of its verbal values) beside its unit and limits, and - where the A2L gives
EXTENDED_LIMITS - the explicit choice to write up to them. Enter emits the typed value as typed;
the session's write checks it."""

from __future__ import annotations

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QCheckBox, QHBoxLayout, QLabel, QWidget

from workbench.gui import theme
from workbench.gui.formatting import format_value
from workbench.gui.widgets.value_input import HINT, ValueEdit

__all__ = ["ScalarField"]


def limits_text(limits: tuple[float, float], unit: str, words: str = "limits") -> str:
    return f"{words} {format_value(limits[0])} … {format_value(limits[1])}" + (f" {unit}" if unit else "")


class ScalarField(QWidget):
    committed = Signal(object)  # a float, or the text of a verbal value, as typed
    refused = Signal(str)  # the text is no value

    def __init__(self, *, unit: str, limits: tuple[float, float], decimals: int | None,
                 states: list[str] | None = None, extended_limits: tuple[float, float] | None = None,
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.states = tuple(states or ())
        self.decimals = decimals
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.input = ValueEdit(self.states)
        self.input.setFont(theme.mono_font(13))
        self.input.setMinimumWidth(120)
        self.input.setMaximumWidth(240)
        self.input.committed.connect(self.committed)
        self.input.refused.connect(self.refused)
        layout.addWidget(self.input, 1)
        self.unit_label = QLabel(unit if not self.states else "")
        layout.addWidget(self.unit_label)
        self.range_label = QLabel("" if self.states else limits_text(limits, unit))
        self.range_label.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(self.range_label)
        self.extended = None
        if extended_limits is not None and not self.states:
            self.extended = QCheckBox(limits_text(extended_limits, unit, "extended"))
            self.extended.setToolTip("write values beyond the limits, up to the A2L's EXTENDED_LIMITS")
            layout.addWidget(self.extended)
        layout.addStretch(1)

    @property
    def allow_extended_limits(self) -> bool:
        return self.extended is not None and self.extended.isChecked()

    def set_read_only(self, why: str) -> None:
        """Greyed, nothing typed, ``why`` in the tooltip (a disabled field still shows it); "": writable."""
        self.input.setEnabled(not why)
        self.input.setToolTip(f"read-only: {why}" if why else HINT)
        if self.extended is not None:
            self.extended.setEnabled(not why)

    def show_value(self, value) -> None:
        """Show what the ECU holds (no ``committed`` follows); what is being typed stays until Enter/Esc."""
        self.input.show_value(value if isinstance(value, str)
                              else format_value(value, None if self.states else self.decimals))
