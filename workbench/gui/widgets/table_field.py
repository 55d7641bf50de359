"""A curve's or map's values: an editable, shaded table beside a plot of the curve or a heat map of
the map. Emits the whole new array after each cell edit."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QAbstractItemView, QHeaderView, QSplitter, QTableView, QVBoxLayout, QWidget

from workbench.gui import theme
from workbench.gui.models.calibration_table import CalibrationTableModel, colour_map

__all__ = ["TableField"]


class TableField(QWidget):
    committed = Signal(object)  # the new array
    refused = Signal(str)

    def __init__(self, *, unit: str, x_label: str, y_label: str | None, parent: QWidget | None = None):
        super().__init__(parent)
        self.unit = unit
        self.model = CalibrationTableModel(self)
        self.model.edited.connect(self.committed)
        self.model.refused.connect(self.refused)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        splitter = QSplitter(Qt.Vertical)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setFont(theme.mono_font())
        self.table.setSelectionMode(QAbstractItemView.ExtendedSelection)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.Stretch)
        self.table.verticalHeader().setDefaultSectionSize(24)
        self.table.setCornerButtonEnabled(False)
        self.table.setToolTip(f"X: {x_label}" + (f", Y: {y_label}" if y_label else "") + f"; values in {unit or '-'}")
        splitter.addWidget(self.table)
        self.plot = pg.PlotWidget()
        self.plot.showGrid(x=True, y=True, alpha=theme.GRID_ALPHA)
        self.plot.setMenuEnabled(False)
        self.plot.setLabel("bottom", x_label)
        self.plot.setMinimumHeight(140)
        splitter.addWidget(self.plot)
        splitter.setStretchFactor(0, 1)
        splitter.setStretchFactor(1, 1)
        layout.addWidget(splitter)
        self.y_label = y_label
        self._curve = self._image = None

    def show_value(self, value: np.ndarray, x_points, y_points=None, **options) -> None:
        self.model.set_value(value, x_points, y_points, **options)
        rows = self.model.rowCount()
        self.table.setMinimumHeight(min(rows, 12) * self.table.verticalHeader().defaultSectionSize()
                                    + self.table.horizontalHeader().height() + 4)
        self._draw()

    def set_reference(self, reference) -> None:
        self.model.set_reference(reference)

    def _draw(self) -> None:
        value, x = self.model.value, self.model.x_points
        if not self.model.is_map:
            if self._curve is None:
                self._curve = self.plot.plot(pen=pg.mkPen(theme.TRACE_COLOURS[1], width=2), symbol="o", symbolSize=6,
                                             symbolBrush=theme.TRACE_COLOURS[1])
                self.plot.setLabel("left", self.unit or "")
            self._curve.setData(x, value)
            return
        y = self.model.y_points if self.model.y_points is not None else np.arange(value.shape[1])
        if self._image is None:
            self._image = pg.ImageItem(axisOrder="col-major")
            self._image.setColorMap(colour_map())
            self.plot.addItem(self._image)
            self.plot.setLabel("left", self.y_label or "")
        self._image.setImage(value, autoLevels=True)
        # cells centred on the breakpoints' indices; the axes are labelled with the breakpoints
        self._image.setRect(-0.5, -0.5, value.shape[0], value.shape[1])
        self.plot.getAxis("bottom").setTicks([[(i, f"{p:g}") for i, p in enumerate(x)]])
        self.plot.getAxis("left").setTicks([[(i, f"{p:g}") for i, p in enumerate(y)]])
