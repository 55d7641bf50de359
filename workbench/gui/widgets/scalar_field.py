"""A scalar calibration's input: a spin box in physical units within its limits, or a combo box of
its verbal values (TAB_VERB). Emits the new value when the user commits it (Enter or focus out)."""

from __future__ import annotations

import math

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox, QHBoxLayout, QLabel, QWidget

from workbench.gui import theme
from workbench.gui.formatting import format_value

__all__ = ["ScalarField"]


class ScalarField(QWidget):
    committed = Signal(object)  # a float, or the text of a verbal value

    def __init__(self, *, unit: str, limits: tuple[float, float], decimals: int | None, step: float | None,
                 states: list[str] | None = None, writable: bool = True, parent: QWidget | None = None):
        super().__init__(parent)
        self.states = states
        self._shown = None
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        if states:
            self.input = QComboBox()
            self.input.addItems(states)
            self.input.activated.connect(lambda i: self.committed.emit(self.input.itemText(i)))
        else:
            self.input = QDoubleSpinBox()
            self.input.setDecimals(decimals if decimals is not None else 3)
            low, high = limits
            self.input.setRange(low if math.isfinite(low) else -1e12, high if math.isfinite(high) else 1e12)
            self.input.setSingleStep(step or 10 ** -(decimals if decimals is not None else 1))
            self.input.setKeyboardTracking(False)  # a value is committed when typed out, not per digit
            self.input.setSuffix(f" {unit}" if unit else "")
            self.input.setFont(theme.mono_font(13))
            self.input.setMinimumWidth(170)
            self.input.editingFinished.connect(self._commit)
        self.input.setEnabled(writable)
        layout.addWidget(self.input)
        self.range_label = QLabel("" if states else f"limits {format_value(limits[0])} … {format_value(limits[1])}"
                                  + (f" {unit}" if unit else ""))
        self.range_label.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(self.range_label)
        layout.addStretch(1)

    def show_value(self, value) -> None:
        """Show what the ECU holds (no ``committed`` follows)."""
        self._shown = value
        self.input.blockSignals(True)
        if self.states:
            text = value if isinstance(value, str) else format_value(value)
            index = self.input.findText(text)
            if index < 0:
                self.input.addItem(text)
                index = self.input.count() - 1
            self.input.setCurrentIndex(index)
        else:
            self.input.setValue(float(value))
        self.input.blockSignals(False)

    def _commit(self) -> None:
        value = self.input.value()
        if self._shown is None or abs(value - float(self._shown)) > 10 ** -(self.input.decimals() + 1):
            self.committed.emit(value)
