"""A measurement window: live time plot of XCP and CAN2 signals with one y-axis per unit.

pyqtgraph draws; a QTimer (25 Hz) copies the visible time window out of each signal's ring
buffer and hands it to the curve, which downsamples to the pixels it has (peak method, so
spikes stay visible); a pause in the measurement is a break in the line. While *following*, the
x range slides with the newest sample; panning or zooming with the mouse stops following, the
Follow button resumes it. Two cursors show every signal's value at two instants and the time
between them; one cursor shows every signal's value at one instant. Signals with the same unit
share a y-axis (one view box, one scale); each axis stands in the view's row, as tall as the view, so
a value is drawn at its tick; it is coloured like its first signal and autoscales unless the user
zooms it, never to less than twenty steps of its signals' format (noise below the last digit
shown looks flat, as in CANape). The axes take at most two fifths of the plot's width: those beyond it (in the order their
units came, the selected signal's first) are not drawn; their curves keep their own scale and the
legend their values and units. Verbal signals (states such as ON/OFF) and plain 0/1 flags have no unit's axis:
they step in lanes of their own below the view, labelled with their states' texts (:mod:`.digital_lanes`). The legend is as wide as its columns want, at
most half the window, until the user drags its edge.
"""

from __future__ import annotations

from collections.abc import Callable

import pyqtgraph as pg
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QAbstractItemView,
    QGraphicsLinearLayout,
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
from workbench.gui.widgets.columns import refit_columns, share_columns, wanted_width
from workbench.gui.widgets.digital_lanes import DigitalLanes
from workbench.gui.widgets.spaced_axis import SpacedAxis
from workbench.gui.widgets.names import NameDelegate

__all__ = ["PlotWindow"]

REFRESH_HZ = 25
LEGEND_SHARE = 0.5  # of the window's width for the legend at most, until the user drags its edge
LEGEND_NAME_PX = 170  # the names' column's share of the legend's width: longer names are cut
AXES_SHARE = 0.4  # of the plot's width, at most, for its y-axes (one is always drawn)
MIN_SPAN_STEPS = 20  # display steps (the format's last digit) an axis spans at least: noise below them looks flat
AXIS_WIDTH_PX = 50  # what an axis takes, counted alike for all (their widths follow their ticks: no flicker)
LEGEND_EVERY = 4  # refreshes per update of the legend's numbers (6 Hz: readable, and a frame saved)
SPANS_S = (2.0, 5.0, 10.0, 30.0, 60.0, 300.0)
_LABEL_INSET_PX = 8  # the cursors' times right of the y-axis' ticks (5 px into the plot)


class _Axis:
    """One y-axis (one unit): its view box and axis item."""

    def __init__(self, unit: str, view: pg.ViewBox, item: pg.AxisItem):
        self.unit, self.view, self.item = unit, view, item
        self.traces: list[str] = []


class PlotWindow(SignalDropTarget, QWidget):
    """Time plot of signals from a :class:`SignalHub`; drop names on it to add them."""

    signals_changed = Signal(list)  # the names shown, in order
    samples_arrived = Signal()  # the first samples are on screen (once per window)
    close_requested = Signal()  # the window's close button

    def __init__(self, hub: SignalHub, title: str = "Measurement", span_s: float = 10.0,
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.hub = hub
        self.not_current: Callable[[], str] = lambda: ""  # why live samples are not coming now ("": they are)
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
        self.close_button = self._tool("✕", "close this measurement window")
        self.close_button.clicked.connect(self.close_requested)
        for widget in (self.follow_button, self.span_box, self.autoscale_button, self.cursor_button,
                       self.cursor2_button, self.close_button):
            bar.addWidget(widget)
        layout.addLayout(bar)

        splitter = QSplitter(Qt.Horizontal)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.ci.setContentsMargins(2, 4, 8, 2)
        self.plot = pg.PlotItem(axisItems={"bottom": SpacedAxis("bottom")})  # labels that never run together
        self.plot.showGrid(x=True, y=True, alpha=1.0)
        for name in ("left", "bottom"):  # the grid is drawn by these axes, in their pen's colour
            axis = self.plot.getAxis(name)
            axis.setPen(theme.GRID)
            axis.setTextPen(theme.TEXT)
            axis.setStyle(maxTickLevel=1)
        self.plot.setLabel("bottom", "time", units="s")
        self.plot.setMenuEnabled(False)
        self.plot.hideButtons()
        # the units' axes stand in a row where the plot's own left axis was: in the view's row of the plot's
        # grid, so each is exactly as tall as the view and its ticks say where a value is drawn (an axis beside
        # the whole plot is taller by the time axis and the title, and every value was drawn off its tick)
        left = self.plot.getAxis("left")
        self.plot.layout.removeItem(left)
        left.hide()
        self._axis_row = QGraphicsLinearLayout(Qt.Horizontal)
        self._axis_row.setContentsMargins(0, 0, 0, 0)
        self._axis_row.setSpacing(0)
        self.plot.layout.addItem(self._axis_row, 2, 0)
        self.plot.layout.setAlignment(self._axis_row, Qt.AlignRight)
        self._drawn: list[_Axis] = []  # left to right
        self.lanes = DigitalLanes(self.plot)  # verbal signals: below the view
        self.lanes.view.sigRangeChangedManually.connect(self._user_moved)
        self.graphics.addItem(self.plot, row=0, col=100)
        self.plot.vb.sigResized.connect(self._sync_views)
        self.plot.vb.sigResized.connect(self._fit_axes)
        self.plot.vb.sigRangeChangedManually.connect(self._user_moved)
        self.plot.vb.sigRangeChanged.connect(self._place_cursor_label)
        self.cursor = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen(theme.WARN, width=1.5))
        self.cursor.setZValue(100)
        self.cursor.sigPositionChanged.connect(self._show_cursor_values)
        backing = QColor(theme.PLOT_BACKGROUND)
        backing.setAlpha(235)  # the times stay readable over the curves
        self.cursor_label = pg.TextItem(color=theme.WARN, anchor=(0, 0), fill=backing)  # inside the plot, at its top
        self.cursor_label.setZValue(110)  # above the cursors' lines
        self.cursor2 = pg.InfiniteLine(angle=90, movable=True, pen=pg.mkPen(theme.ACCENT, width=1.5))
        self.cursor2.setZValue(100)
        self.cursor2.sigPositionChanged.connect(self._show_cursor_values)
        splitter.addWidget(self.graphics)

        self.legend = QTableWidget(0, 4)
        self.legend.setHorizontalHeaderLabels(["signal", "value", "at t2", "unit"])
        self.legend.verticalHeader().hide()
        self.legend.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.legend.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.legend.setShowGrid(False)
        self.legend.setItemDelegateForColumn(0, NameDelegate(self.legend))  # names keep their distinct ends
        self.legend.verticalHeader().setDefaultSectionSize(22)
        self.legend.setColumnHidden(2, True)  # shown with the second cursor
        share_columns(self.legend, (1, 1, 1, 1), fit=(1, 2, 3))  # signal, value, at the 2nd cursor, unit
        self._value_chars = 0  # the longest value text the legend showed
        self.legend.setMinimumWidth(160)
        self.legend.setToolTip("Del removes the selected signals; drop names here or on the plot to add them")
        self.legend.itemSelectionChanged.connect(self._fit_axes)  # the selected signal's axis is drawn
        splitter.addWidget(self.legend)
        splitter.setStretchFactor(0, 1)
        splitter.setStretchFactor(1, 0)
        splitter.setSizes([700, 300])
        splitter.splitterMoved.connect(self._legend_moved)
        self.splitter = splitter
        self._legend_sized_by_user = False
        layout.addWidget(splitter, 1)

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self._size_legend()

    def _size_legend(self) -> None:
        """The legend as wide as its columns want (names up to :data:`LEGEND_NAME_PX`), at most
        :data:`LEGEND_SHARE` of the window; the plot the rest. Once the user dragged the edge, theirs."""
        width = self.splitter.width()
        if self._legend_sized_by_user or width <= 0:
            return
        wanted = wanted_width(self.legend, {0: LEGEND_NAME_PX})
        legend = max(min(wanted, int(width * LEGEND_SHARE)), self.legend.minimumWidth())
        if self.splitter.sizes()[1] != legend:
            self.splitter.setSizes([width - legend, legend])

    def _legend_moved(self, *_) -> None:
        self._legend_sized_by_user = True

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
            if self.lanes.remove(name):
                continue
            for axis in list(self._axes):
                if name in axis.traces:
                    axis.traces.remove(name)
                    axis.view.removeItem(curve)
                    if not axis.traces:
                        self._drop_axis(axis)
                    else:
                        self._limit_span(axis)
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
        # a verbal signal or a flag steps between its states in a lane of its own (a unit's scale says nothing of it)
        curve = pg.PlotDataItem(pen=pg.mkPen(colour, width=1), name=name, autoDownsampleFactor=1.0, connect="finite",
                                stepMode="right" if info.lane_states else None)
        curve.setDownsampling(auto=True, method="peak")
        curve.setClipToView(True)
        if info.lane_states:
            self.lanes.add(name, info.lane_states, curve, info.label)
        else:
            axis = self._axis_for(info.unit, colour)
            axis.traces.append(name)
            axis.view.addItem(curve)
            self._limit_span(axis)
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
        item = SpacedAxis("left")
        item.linkToView(view)
        item.setLabel(unit)  # no unit: no label
        pen = pg.mkPen(colour)
        item.setPen(pen)
        item.setTextPen(pen)
        view.enableAutoRange(axis=pg.ViewBox.YAxis, enable=True)
        axis = _Axis(unit, view, item)
        self._axes.append(axis)
        self._sync_views()
        self._fit_axes()
        return axis

    def _limit_span(self, axis: _Axis) -> None:
        """Autoscaled or zoomed, ``axis`` spans at least :data:`MIN_SPAN_STEPS` of its finest signal's display
        step (25.00 bar: 0.2 bar), so it never reads 25.0000 ... 25.0025 around a value shown as 25.00."""
        steps = [10.0 ** -info.decimals for info in map(self.hub.info, axis.traces) if info.decimals is not None]
        axis.view.setLimits(minYRange=MIN_SPAN_STEPS * min(steps) if steps else None)

    def _drop_axis(self, axis: _Axis) -> None:
        if axis in self._drawn:
            self._show_axes([a for a in self._drawn if a is not axis])
        if axis.view is not self.plot.vb:
            self.plot.scene().removeItem(axis.view)
        self._axes.remove(axis)
        self._fit_axes()

    def drawn_axes(self) -> list[str]:
        """The units whose y-axes are drawn, left to right."""
        return [axis.unit for axis in self._drawn]

    def _fit_axes(self, *_) -> None:
        """Draw the y-axes that fit :data:`AXES_SHARE` of the plot's width (see the module docstring)."""
        selected = {self._order[index.row()] for index in self.legend.selectedIndexes()
                    if index.row() < len(self._order)}  # the legend is refilled after a removal
        ranked = sorted(self._axes, key=lambda axis: not selected.intersection(axis.traces))
        drawn = ranked[:max(1, int(self.graphics.width() * AXES_SHARE / AXIS_WIDTH_PX))]
        self._show_axes([axis for axis in reversed(self._axes) if axis in drawn])  # the first unit's beside the plot

    def _show_axes(self, axes: list[_Axis]) -> None:
        """Draw ``axes``, left to right, in the axes' row (the others leave the scene)."""
        if axes == self._drawn:
            return
        for axis in self._drawn:
            self._axis_row.removeItem(axis.item)
            self.plot.scene().removeItem(axis.item)
        for axis in axes:
            self._axis_row.addItem(axis.item)
        self._drawn = axes

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
        refit_columns(self.legend)
        self._size_legend()

    def _update_legend_values(self, at: float | None, column: int = 1) -> None:
        """Each signal's value at ``at`` (None: its newest) into the legend's ``column``."""
        longest = 0
        why = self.not_current() if at is None else ""
        for row, name in enumerate(self._order):
            buffer = self.hub.buffer(name)
            if at is None:
                last = buffer.last()
                value = None if last is None else last[1]
            else:
                value = buffer.at(at)
            item = self.legend.item(row, column)
            if item is not None:
                refused = self.hub.refused(name)
                text = "no DAQ" if refused and value is None else self.hub.info(name).format(value)
                item.setText(text)
                # the newest value of a live signal while none comes (the ECU lost, not connected): greyed, as the
                # numeric view's; a value at a cursor, or a file's, is what it is
                stale = at is None and value is not None and self.hub.info(name).source != "MDF" and why
                item.setForeground(QColor(theme.MUTED) if stale else self.legend.palette().text().color())
                item.setToolTip(f"not measured: {refused}" if refused else
                                f"not current: {why} (the last value measured)" if stale else "")
                longest = max(longest, len(text))
        if longest > self._value_chars:  # a longer value than any before: the value columns widen (rarely)
            self._value_chars = longest
            refit_columns(self.legend)
            self._size_legend()

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
            self.lanes.show_cursor(self.cursor, True)
            self._show_cursor_values()
        else:
            self.cursor2_button.setChecked(False)
            self.plot.removeItem(self.cursor)
            self.plot.removeItem(self.cursor_label)
            self.lanes.show_cursor(self.cursor, False)
            self._show_cursor_values()

    def set_second_cursor(self, on: bool) -> None:
        if on and not self.cursor_button.isChecked():
            self.cursor_button.setChecked(True)
        self.legend.setColumnHidden(2, not on)
        refit_columns(self.legend)
        self._size_legend()
        if on:
            (x0, x1), _ = self.plot.vb.viewRange()
            self.cursor2.setPos(x0 + (x1 - x0) * 0.75)
            self.plot.addItem(self.cursor2, ignoreBounds=True)
        else:
            self.plot.removeItem(self.cursor2)
        self.lanes.show_cursor(self.cursor2, on)
        self._show_cursor_values()

    def _show_cursor_values(self, *_) -> None:
        # the value columns named for the time their values are taken at, as the cursors' label names the times
        cursors = (self.cursor_button.isChecked(), self.cursor2_button.isChecked())
        first = {(False, False): "value", (True, False): "at t"}.get(cursors, "at t1")
        if self.legend.horizontalHeaderItem(1).text() != first:
            self.legend.setHorizontalHeaderLabels(["signal", first, "at t2", "unit"])
        if not self.cursor_button.isChecked():
            return
        t = float(self.cursor.value())
        text = f"t = {t:.3f} s"
        if self.cursor2_button.isChecked():
            t2 = float(self.cursor2.value())
            text = f"t1 = {t:.3f} s\nt2 = {t2:.3f} s\nΔt = {t2 - t:.3f} s"  # one below the other: a narrow plot
            self._update_legend_values(t2, column=2)
        self.cursor_label.setText(text)
        self._place_cursor_label()
        self._update_legend_values(t)

    def _place_cursor_label(self, *_) -> None:
        """The cursors' times at the plot's top left, wherever the cursors are and however it is zoomed, clear of
        the ticks of the axis beside it (they point into the plot and covered the label's first letter)."""
        (x0, _), (_, y1) = self.plot.vb.viewRange()
        pixel = self.plot.vb.viewPixelSize()[0]
        self.cursor_label.setPos(x0 + _LABEL_INSET_PX * pixel, y1)

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
        lanes = set(self.lanes.names)
        for name, curve in self._curves.items():
            t, v = self.hub.buffer(name).window(x0, x1, gaps=True)  # a pause breaks the line (NaN)
            if name in lanes:
                self.lanes.set_data(name, t, v)
            else:
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
