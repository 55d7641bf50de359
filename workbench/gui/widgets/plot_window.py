"""A measurement window: live time plot of XCP and CAN2 signals with one y-axis per unit.

pyqtgraph draws; a QTimer (25 Hz) copies the visible time window out of each signal's ring
buffer and hands it to the curve, which downsamples to the pixels it has (peak method, so
spikes stay visible); a pause in the measurement is a break in the line. While *following*, the x range slides with the newest sample; panning or
zooming with the mouse stops following, the Follow button resumes it. Two cursors show every
signal's value at two instants and the time between them; one cursor shows every
signal's value at one instant. Signals with the same unit share a y-axis; each axis is coloured
like its first signal and autoscales unless the user zooms it.
"""

from __future__ import annotations

import pyqtgraph as pg
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QHBoxLayout,
    QLabel,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from workbench.gui import theme
from workbench.gui.mime import SignalDropTarget
from workbench.gui.signal_hub import SignalHub
from workbench.gui.widgets.columns import share_columns

__all__ = ["PlotWindow"]

REFRESH_HZ = 25
LEGEND_EVERY = 4  # refreshes per update of the legend's numbers (6 Hz: readable, and a frame saved)
SPANS_S = (2.0, 5.0, 10.0, 30.0, 60.0, 300.0)


class _Axis:
    """One y-axis (one unit): its view box and axis item."""

    def __init__(self, unit: str, view: pg.ViewBox, item: pg.AxisItem):
        self.unit, self.view, self.item = unit, view, item
        self.traces: list[str] = []


class PlotWindow(SignalDropTarget, QWidget):
    """Time plot of signals from a :class:`SignalHub`; drop names on it to add them."""

    signals_changed = Signal(list)  # the names shown, in order
    samples_arrived = Signal()  # the first samples are on screen (once per window)

    def __init__(self, hub: SignalHub, title: str = "Measurement", span_s: float = 10.0,
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.hub = hub
        self.title = title
        self.span_s = span_s
        self.following = True
        self.frames = 0  # refreshes done (for the benchmark and tests)
        self._live = False
        self._curves: dict[str, pg.PlotDataItem] = {}
        self._axes: list[_Axis] = []
        self._order: list[str] = []
        self.setAcceptDrops(True)
        self._build()
        self.timer = QTimer(self)
        self.timer.setInterval(int(1000 / REFRESH_HZ))
        self.timer.timeout.connect(self.refresh)
        self.timer.start()

    # --- building -------------------------------------------------------------------------------

    def _build(self) -> None:
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(0)
        bar = QHBoxLayout()
        bar.setContentsMargins(6, 3, 6, 3)
        self.title_label = QLabel(self.title)
        self.title_label.setStyleSheet("font-weight: 600;")
        bar.addWidget(self.title_label)
        bar.addStretch(1)
        self.follow_button = self._tool("Follow", "slide with the newest samples (stops when you pan or zoom)",
                                        checkable=True, checked=True)
        self.follow_button.toggled.connect(self.set_following)
        self.span_box = QComboBox()
        for span in SPANS_S:
            self.span_box.addItem(f"{span:g} s", span)
        self.span_box.setCurrentIndex(min(range(len(SPANS_S)), key=lambda i: abs(SPANS_S[i] - self.span_s)))
        self.span_box.setToolTip("time span shown while following")
        self.span_box.currentIndexChanged.connect(lambda i: self.set_span(SPANS_S[i]))
        self.autoscale_button = self._tool("Autoscale", "fit every y-axis to its signals")
        self.autoscale_button.clicked.connect(self.autoscale)
        self.cursor_button = self._tool("Cursor", "a cursor with every signal's value (stops following)",
                                        checkable=True)
        self.cursor_button.toggled.connect(self.set_cursor)
        self.cursor2_button = self._tool("2nd", "a second cursor: each signal's value there and the time between the "
                                                "cursors", checkable=True)
        self.cursor2_button.toggled.connect(self.set_second_cursor)
        for widget in (self.follow_button, self.span_box, self.autoscale_button, self.cursor_button,
                       self.cursor2_button):
            bar.addWidget(widget)
        layout.addLayout(bar)

        splitter = QSplitter(Qt.Horizontal)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.ci.setContentsMargins(2, 4, 8, 2)
        self.plot = pg.PlotItem()
        self.plot.showGrid(x=True, y=True, alpha=1.0)
        for name in ("left", "bottom"):  # the grid is drawn by these axes, in their pen's colour
            axis = self.plot.getAxis(name)
            axis.setPen(theme.GRID)
            axis.setTextPen(theme.TEXT)
            axis.setStyle(maxTickLevel=1)
        self.plot.setLabel("bottom", "time", units="s")
        self.plot.setMenuEnabled(False)
        self.plot.hideButtons()
        self.plot.getAxis("left").setWidth(0)
        self.plot.getAxis("left").hide()
        self.graphics.addItem(self.plot, row=0, col=100)
        self.plot.vb.sigResized.connect(self._sync_views)
        self.plot.vb.sigRangeChangedManually.connect(self._user_moved)
        self.cursor = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen(theme.WARN, width=1.5))
        self.cursor.setZValue(100)
        self.cursor.sigPositionChanged.connect(self._show_cursor_values)
        self.cursor_label = pg.TextItem(color=theme.WARN, anchor=(0, 0))  # inside the plot, below its top
        self.cursor2 = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen(theme.ACCENT, width=1.5))
        self.cursor2.setZValue(100)
        self.cursor2.sigPositionChanged.connect(self._show_cursor_values)
        splitter.addWidget(self.graphics)

        self.legend = QTableWidget(0, 4)
        self.legend.setHorizontalHeaderLabels(["signal", "value", "at 2nd", "unit"])
        self.legend.verticalHeader().hide()
        self.legend.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.legend.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.legend.setShowGrid(False)
        self.legend.setTextElideMode(Qt.ElideMiddle)
        self.legend.verticalHeader().setDefaultSectionSize(22)
        self.legend.setColumnHidden(2, True)  # shown with the second cursor
        share_columns(self.legend, (3, 1.6, 1.6, 0.9))  # signal, value, at the 2nd cursor, unit
        self.legend.setMinimumWidth(160)
        self.legend.setToolTip("Del removes the selected signals; drop names here or on the plot to add them")
        splitter.addWidget(self.legend)
        splitter.setStretchFactor(0, 1)
        splitter.setStretchFactor(1, 0)
        splitter.setSizes([700, 300])
        layout.addWidget(splitter, 1)

    def _tool(self, text: str, tip: str, *, checkable: bool = False, checked: bool = False) -> QToolButton:
        button = QToolButton()
        button.setText(text)
        button.setToolTip(tip)
        button.setCheckable(checkable)
        button.setChecked(checked)
        return button

    # --- signals --------------------------------------------------------------------------------

    @property
    def signals(self) -> list[str]:
        return list(self._order)

    def add_signals(self, names) -> None:
        added = False
        for name in names:
            if name in self._curves:
                continue
            self._add_curve(name)
            added = True
        if added:
            self._changed()

    def remove_signals(self, names) -> None:
        for name in names:
            curve = self._curves.pop(name, None)
            if curve is None:
                continue
            self._order.remove(name)
            for axis in list(self._axes):
                if name in axis.traces:
                    axis.traces.remove(name)
                    axis.view.removeItem(curve)
                    if not axis.traces:
                        self._drop_axis(axis)
        self._changed()

    def _changed(self) -> None:
        self._fill_legend()
        self.hub.show(self, self._order)
        self.signals_changed.emit(self.signals)

    def _add_curve(self, name: str) -> None:
        info = self.hub.info(name)
        colour = theme.trace_colour(len(self._order))
        # a 1-pixel (cosmetic) pen: wider ones make Qt stroke every segment, ~4x slower; downsampling to
        # about one min/max pair per pixel column keeps spikes and draws no line nobody can see
        curve = pg.PlotDataItem(pen=pg.mkPen(colour, width=1), name=name, autoDownsampleFactor=1.0, connect="finite")
        curve.setDownsampling(auto=True, method="peak")
        curve.setClipToView(True)
        axis = self._axis_for(info.unit, colour)
        axis.traces.append(name)
        axis.view.addItem(curve)
        self._curves[name] = curve
        self._order.append(name)

    def _axis_for(self, unit: str, colour: str) -> _Axis:
        for axis in self._axes:
            if axis.unit == unit:
                return axis
        if not self._axes:
            view = self.plot.vb
        else:
            view = pg.ViewBox()
            view.setXLink(self.plot.vb)
            self.plot.scene().addItem(view)
        item = pg.AxisItem("left")
        item.linkToView(view)
        item.setLabel(unit)  # no unit: no label
        pen = pg.mkPen(colour)
        item.setPen(pen)
        item.setTextPen(pen)
        self.graphics.addItem(item, row=0, col=99 - len(self._axes))
        view.enableAutoRange(axis=pg.ViewBox.YAxis, enable=True)
        axis = _Axis(unit, view, item)
        self._axes.append(axis)
        self._sync_views()
        return axis

    def _drop_axis(self, axis: _Axis) -> None:
        self.graphics.removeItem(axis.item)
        if axis.view is not self.plot.vb:
            self.plot.scene().removeItem(axis.view)
        self._axes.remove(axis)

    def _sync_views(self) -> None:
        for axis in self._axes:
            if axis.view is not self.plot.vb:
                axis.view.setGeometry(self.plot.vb.sceneBoundingRect())
                axis.view.linkedViewChanged(self.plot.vb, axis.view.XAxis)

    # --- legend ---------------------------------------------------------------------------------

    def _fill_legend(self) -> None:
        self.legend.setRowCount(len(self._order))
        for row, name in enumerate(self._order):
            colour = QColor(self._curves[name].opts["pen"].color())
            item = QTableWidgetItem(self.hub.info(name).label or name)
            item.setData(Qt.DecorationRole, colour)
            item.setForeground(colour)
            description = self.hub.info(name).description
            item.setToolTip(f"{name}\n{description}" if description else name)
            self.legend.setItem(row, 0, item)
            for column in (1, 2):
                value = QTableWidgetItem("—")
                value.setTextAlignment(Qt.AlignRight | Qt.AlignVCenter)
                value.setFont(theme.mono_font())
                self.legend.setItem(row, column, value)
            unit = QTableWidgetItem(self.hub.info(name).unit)
            unit.setForeground(QColor(theme.MUTED))
            self.legend.setItem(row, 3, unit)

    def _update_legend_values(self, at: float | None, column: int = 1) -> None:
        """Each signal's value at ``at`` (None: its newest) into the legend's ``column``."""
        for row, name in enumerate(self._order):
            buffer = self.hub.buffer(name)
            if at is None:
                last = buffer.last()
                value = None if last is None else last[1]
            else:
                value = buffer.at(at)
            item = self.legend.item(row, column)
            if item is not None:
                item.setText(self.hub.info(name).format(value))

    def value_at_cursors(self, name: str) -> tuple[str, str]:
        """The legend's texts of ``name`` at the cursor and the second cursor."""
        row = self._order.index(name)
        return self.legend.item(row, 1).text(), self.legend.item(row, 2).text()

    def keyPressEvent(self, event) -> None:
        if event.key() in (Qt.Key_Delete, Qt.Key_Backspace):
            rows = sorted({index.row() for index in self.legend.selectedIndexes()})
            self.remove_signals([self._order[row] for row in rows])
            return
        super().keyPressEvent(event)

    # --- time axis ------------------------------------------------------------------------------

    def set_following(self, on: bool) -> None:
        self.following = on
        if self.follow_button.isChecked() != on:
            self.follow_button.setChecked(on)
        if on and self.cursor_button.isChecked():
            self.cursor_button.setChecked(False)

    def show_all(self) -> None:
        """Every sample of the signals in view (not following): a file opened for analysis."""
        spans = [span for span in (self.hub.buffer(n).span() for n in self._order) if span]
        self.set_following(False)
        if spans:
            self.plot.vb.setXRange(min(s[0] for s in spans), max(s[1] for s in spans), padding=0.01)

    def set_span(self, span_s: float) -> None:
        self.span_s = span_s
        self.set_following(True)

    def _user_moved(self, *_) -> None:
        self.set_following(False)

    def autoscale(self) -> None:
        for axis in self._axes:
            axis.view.enableAutoRange(axis=pg.ViewBox.YAxis, enable=True)

    def set_cursor(self, on: bool) -> None:
        if on:
            self.set_following(False)
            (x0, x1), _ = self.plot.vb.viewRange()
            self.cursor.setPos((x0 + x1) / 2)
            self.plot.addItem(self.cursor, ignoreBounds=True)
            self.plot.addItem(self.cursor_label, ignoreBounds=True)
            self._show_cursor_values()
        else:
            self.cursor2_button.setChecked(False)
            self.plot.removeItem(self.cursor)
            self.plot.removeItem(self.cursor_label)

    def set_second_cursor(self, on: bool) -> None:
        if on and not self.cursor_button.isChecked():
            self.cursor_button.setChecked(True)
        self.legend.setColumnHidden(2, not on)
        self.legend._column_sharer.share()
        if on:
            (x0, x1), _ = self.plot.vb.viewRange()
            self.cursor2.setPos(x0 + (x1 - x0) * 0.75)
            self.plot.addItem(self.cursor2, ignoreBounds=True)
        else:
            self.plot.removeItem(self.cursor2)
        self._show_cursor_values()

    def _show_cursor_values(self, *_) -> None:
        if not self.cursor_button.isChecked():
            return
        t = float(self.cursor.value())
        text = f"t = {t:.3f} s"
        if self.cursor2_button.isChecked():
            t2 = float(self.cursor2.value())
            text = f"t1 = {t:.3f} s   t2 = {t2:.3f} s   Δt = {t2 - t:.3f} s"
            self._update_legend_values(t2, column=2)
        self.cursor_label.setText(text)
        (x0, _), (_, y1) = self.plot.vb.viewRange()
        self.cursor_label.setPos(x0, y1)  # the plot's top left: the times stay readable wherever the cursors are
        self._update_legend_values(t)

    # --- refresh --------------------------------------------------------------------------------

    def refresh(self) -> None:
        """Copy the visible window of every signal into its curve (the timer's slot)."""
        if not self._order or not self.isVisible():
            return
        if self.following:
            x0, x1 = self._following_window()
            self.plot.vb.setXRange(x0, x1, padding=0)
        else:
            (x0, x1), _ = self.plot.vb.viewRange()
        for name, curve in self._curves.items():
            t, v = self.hub.buffer(name).window(x0, x1, gaps=True)  # a pause breaks the line (NaN)
            curve.setData(t, v)
        if not self.cursor_button.isChecked() and self.frames % LEGEND_EVERY == 0:
            self._update_legend_values(None)
        self.frames += 1
        if not self._live and self.samples_shown():
            self._live = True
            self.samples_arrived.emit()

    def _following_window(self) -> tuple[float, float]:
        """The span ending at the newest sample, as a scope sweeps: until the samples fill the span it
        starts at the oldest one, so a new measurement draws from the left edge."""
        spans = [span for span in (self.hub.buffer(n).span() for n in self._order) if span]
        if not spans:
            now = self.hub.now()
            return now - self.span_s, now
        oldest, newest = min(s[0] for s in spans), max(s[1] for s in spans)
        start = max(newest - self.span_s, oldest)
        return start, start + self.span_s

    def samples_shown(self) -> int:
        """How many samples the curves hold now (0 until the first arrived)."""
        return sum(len(curve.xData) for curve in self._curves.values() if curve.xData is not None)
