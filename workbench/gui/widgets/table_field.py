"""A curve's or map's values: an editable, shaded table beside a plot of the curve, or a heat map and a
3D surface of the map. A cell is typed as every value is (Enter writes, Esc restores, leaving writes
nothing); a selected range takes block operations (set, add, multiply, interpolate between its
corners). Each edit emits the whole new array once; the session checks and writes it."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor, QFont, QFontMetrics, QPen
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QSplitter,
    QTableView,
    QTabWidget,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from workbench.gui import theme
from workbench.gui.formatting import format_value, parse_typed
from workbench.gui.models.block_ops import block_operation
from workbench.gui.models.calibration_table import OPERATING_POINT_ROLE, CalibrationTableModel, colour_map
from workbench.gui.widgets.scalar_field import limits_text
from workbench.gui.widgets.surface_view import SurfaceView
from workbench.gui.widgets.value_input import ValueDelegate

__all__ = ["TableField"]

_OPERATIONS = (("set", "= set", "set the selected cells to the value"),
               ("add", "+ add", "add the value to the selected cells"),
               ("multiply", "× multiply", "multiply the selected cells by the value"),
               ("interpolate", "interpolate", "fill the selected range linearly between its corners (bilinearly on "
                                              "a map), over the axis points"))


class TableField(QWidget):
    committed = Signal(object)  # the new array
    refused = Signal(str)

    def __init__(self, *, unit: str, x_label: str, y_label: str | None,
                 extended_limits: tuple[float, float] | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.unit = unit
        self.y_label = y_label
        self.model = CalibrationTableModel(self)
        self.model.axis_labels = (x_label, y_label)
        self.model.edited.connect(self.committed)
        self.model.refused.connect(self.refused)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addLayout(self._block_bar(unit, extended_limits))
        splitter = QSplitter(Qt.Vertical)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setFont(theme.mono_font())
        self.table.setSelectionMode(QAbstractItemView.ExtendedSelection)
        self.table.setEditTriggers(QAbstractItemView.DoubleClicked | QAbstractItemView.AnyKeyPressed
                                   | QAbstractItemView.EditKeyPressed)
        self.delegate = _CellDelegate(self.table)
        self.delegate.refused.connect(self.refused)
        self.table.setItemDelegate(self.delegate)
        # columns share the width, never narrower than their widest text (a curve of many points scrolls sideways)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.Stretch)
        self.table.horizontalHeader().setMinimumSectionSize(36)
        self.table.setHorizontalScrollMode(QAbstractItemView.ScrollPerPixel)
        self.table.verticalHeader().setDefaultSectionSize(24)
        self.table.setCornerButtonEnabled(False)
        self.table.setToolTip(f"X: {x_label}" + (f", Y: {y_label}" if y_label else "") + f"; values in {unit or '-'}"
                              "\nEnter writes, Esc restores; select a range for the block operations above")
        splitter.addWidget(self.table)
        self.views = QTabWidget()
        self.views.setDocumentMode(True)
        self.plot = pg.PlotWidget()
        self.plot.showGrid(x=True, y=True, alpha=theme.GRID_ALPHA)
        self.plot.setMenuEnabled(False)
        self.plot.setLabel("bottom", x_label)
        self.plot.setMinimumHeight(120)
        page = QWidget()
        column = QVBoxLayout(page)
        column.setContentsMargins(4, 2, 0, 0)
        column.setSpacing(0)
        # a heat map's axis titles read across, in one line above it (two when narrow): up its Y-axis a title
        # is cut at the height a heat map gets, and one line costs less height than a title under the X-axis
        # Y grows downwards, as in the table: its first breakpoint is the top row of both (CANape's, INCA's way)
        titles = (f"↓ Y: {y_label}", f"→ X: {x_label}")  # a line breaks between them, not inside one
        self.axis_titles = QLabel("    ".join(t.replace(" ", "\u00a0") for t in titles) if y_label else "")
        self.axis_titles.setWordWrap(True)
        self.axis_titles.setStyleSheet(f"color: {theme.MUTED};")
        # the two lines they take on a laptop's screen kept from the start: the tab's least height counts no wrapped
        # line, and the heat map's X labels were cut by the one it had not counted
        self.axis_titles.setMinimumHeight(2 * self.axis_titles.fontMetrics().lineSpacing())
        self.axis_titles.setAlignment(Qt.AlignLeft | Qt.AlignBottom)
        self.axis_titles.hide()
        column.addWidget(self.axis_titles)
        column.addWidget(self.plot, 1)
        self.views.addTab(page, "plot")
        self.surface: SurfaceView | None = None
        self._x_label = x_label
        splitter.addWidget(self.views)
        splitter.setStretchFactor(0, 1)
        splitter.setStretchFactor(1, 1)
        layout.addWidget(splitter, 1)
        self._curve = self._image = None
        self.operating_point: tuple[float, ...] | None = None  # fractional indices of the breakpoints, X first
        self.marker = pg.ScatterPlotItem(size=15, symbol="crosshair", pen=pg.mkPen(theme.OPERATING_POINT, width=2),
                                         brush=None)
        self.marker.setZValue(10)  # over the heat map's cells and the curve
        self.plot.addItem(self.marker)

    def _block_bar(self, unit: str, extended_limits) -> QHBoxLayout:
        bar = QHBoxLayout()
        bar.setContentsMargins(0, 0, 0, 0)
        self.operand = QLineEdit()
        self.operand.setPlaceholderText("value")
        self.operand.setToolTip("the value of set, add and multiply")
        self.operand.setMaximumWidth(90)
        self.operand.setMinimumWidth(self.operand.fontMetrics().horizontalAdvance("value") + 26)  # + padding
        bar.addWidget(self.operand)
        self.block_buttons = {}
        for operation, text, tip in _OPERATIONS:
            button = QToolButton()
            button.setText(text)
            button.setToolTip(tip)
            button.clicked.connect(lambda _=False, o=operation: self.apply_block(o))
            bar.addWidget(button)
            self.block_buttons[operation] = button
        self.extended = None
        if extended_limits is not None:
            self.extended = QCheckBox(limits_text(extended_limits, unit, "extended"))
            self.extended.setToolTip("write values beyond the limits, up to the A2L's EXTENDED_LIMITS")
            bar.addWidget(self.extended)
        bar.addStretch(1)
        return bar

    @property
    def allow_extended_limits(self) -> bool:
        return self.extended is not None and self.extended.isChecked()

    # --- values ---------------------------------------------------------------------------------

    def show_value(self, value: np.ndarray, x_points, y_points=None, **options) -> None:
        self.model.set_value(value, x_points, y_points, **options)
        self._fit_columns()
        rows = self.model.rowCount()
        scroll_bar = self.table.horizontalScrollBar().sizeHint().height() if rows == 1 else 0  # a long curve's
        header = self.table.horizontalHeader()
        header.ensurePolished()  # its height with the style sheet's padding (unpolished it is 14 px less)
        self.table.setMinimumHeight(min(rows, 8) * self.table.verticalHeader().defaultSectionSize()
                                    + header.sizeHint().height() + scroll_bar + 2 * self.table.frameWidth())
        self._draw()

    def set_read_only(self, why: str) -> None:
        """Cells greyed and not editable, the block operations off, ``why`` in the tooltips; "": writable."""
        self.model.set_read_only(why)
        for widget in (*self.block_buttons.values(), self.operand) + ((self.extended,) if self.extended else ()):
            widget.setEnabled(not why)
        self.table.setToolTip(f"read-only: {why}" if why else "")

    def _fit_columns(self) -> None:
        """The columns' least width: the widest breakpoint (bold, with the header's padding of the style sheet)
        or value (bold where it differs from the reference, with the cell's margins)."""
        header = self.table.horizontalHeader()
        bold_header, bold_cell = QFont(header.font()), QFont(self.table.font())
        bold_header.setBold(True)
        bold_cell.setBold(True)
        cell_metrics = {False: QFontMetrics(self.table.font()), True: QFontMetrics(bold_cell)}
        points = QFontMetrics(bold_header)
        widest = max((points.horizontalAdvance(text) + 14 for text in self.model.point_texts()), default=0)
        for cell, text in self.model.cell_texts():
            widest = max(widest, cell_metrics[self.model.modified(cell)].horizontalAdvance(text) + 8)
        header.setMinimumSectionSize(max(36, widest))

    def _ticks(self, axis: int, points) -> list[list[tuple[int, str]]]:
        """A heat map axis' labels: the first and last breakpoint always, the others where there is room (pyqtgraph
        draws a second tick level's texts only when they do not crowd the axis: they overlapped on a small map)."""
        labels = [(i, self.model.point_text(axis, p)) for i, p in enumerate(points)]
        return [labels[:1] + labels[-1:] if len(labels) > 1 else labels, labels[1:-1]]

    def set_reference(self, reference) -> None:
        self.model.set_reference(reference)
        self._fit_columns()  # modified values are bold

    def selected_cells(self) -> list[tuple[int, ...]]:
        return sorted({self.model.cell(index) for index in self.table.selectionModel().selectedIndexes()})

    def apply_block(self, operation: str) -> None:
        """A block operation on the selected cells: the new array is committed (one write), or why not refused."""
        try:
            operand = 0.0
            if operation != "interpolate":
                operand = parse_typed(self.operand.text())
            axes = [self.model.x_points] + ([self.model.y_points] if self.model.is_map else [])
            new = block_operation(self.model.value, self.selected_cells(), operation, operand, axes)
        except ValueError as exc:
            self.refused.emit(f"{operation}: {exc}")
            return
        if not np.array_equal(new, self.model.value, equal_nan=True):
            self.committed.emit(new)

    def show_operating_point(self, position: tuple[float, ...] | None) -> None:
        """Marks where the axes' inputs are (:mod:`.operating_point`): ``position`` a fractional index of the
        breakpoints per axis, X first, None for no mark. The cells around it are framed; the heat map and the 3D
        view have a cross there, a curve's plot a cross on the curve."""
        if position == self.operating_point:
            return
        self.operating_point = position
        self.model.set_operating_point(position)
        if self.surface is not None:
            self.surface.set_operating_point(position)
        if position is None:
            self.marker.setData([], [])
        elif self.model.is_map:
            self.marker.setData([position[0]], [position[1]])
        else:
            index = np.arange(len(self.model.x_points), dtype=np.float64)
            self.marker.setData([np.interp(position[0], index, self.model.x_points)],
                                [np.interp(position[0], index, self.model.value)])

    # --- drawing --------------------------------------------------------------------------------

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
            self.plot.getViewBox().invertY(True)  # the first Y breakpoint on top, as the table's first row
            self.plot.setLabel("bottom", None)  # both titles are above the map
            self.plot.setMinimumHeight(100)
            self.axis_titles.setVisible(bool(self.y_label))
            self.views.setTabText(0, "heat map")
            self.surface = SurfaceView(self._x_label, self.y_label or "Y", self.unit)
            self.views.addTab(self.surface, "3D")
        self._image.setImage(value, autoLevels=True)
        # cells centred on the breakpoints' indices; the axes are labelled with the breakpoints
        self._image.setRect(-0.5, -0.5, value.shape[0], value.shape[1])
        self.plot.getAxis("bottom").setTicks(self._ticks(0, x))
        self.plot.getAxis("left").setTicks(self._ticks(1, y))
        self.surface.set_surface(value, x, y, point_text=self.model.point_text,
                                 value_text=lambda v: format_value(v, self.model.decimals))


class _CellDelegate(ValueDelegate):
    """A value's cell, framed when it is one of the cells around the operating point."""

    def paint(self, painter, option, index) -> None:
        super().paint(painter, option, index)
        if index.data(OPERATING_POINT_ROLE):
            painter.save()
            painter.setPen(QPen(QColor(theme.OPERATING_POINT), 2))
            painter.drawRect(option.rect.adjusted(1, 1, -1, -1))
            painter.restore()
