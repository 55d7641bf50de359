"""Verbal signals (states such as ON/OFF, OFF/TANK1_ON/TANK2_ON) and plain 0/1 flags as step traces in lanes of
their own below a plot's view, as CANape draws digital signals: each lane is labelled with its states' texts (a
flag's: 0 and 1) and named at its top left, in the trace's colour on the plot's background half seen through
(wherever the view is scrolled to); none is ever drawn on a physical unit's scale.

The lanes share one view box under the plot's view (in the plot's grid, between the view and the time
axis), linked to its time axis; its y coordinates are pixels: a lane is as tall as its states' texts need.
"""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor

from workbench.gui import theme

__all__ = ["DigitalLanes"]

LANE_PX = 34  # a two-state lane: its two texts one above the other, clear of each other and of the next lane's
STATE_PX = 13  # between two state texts (the tick font's height and a pixel)
PAD_PX = 7  # between a lane's edge and its lowest or highest state
MAX_LANE_PX = 80  # a lane of many states: not all of its texts are written
ROW = 3  # of the plot's grid: below the view (row 2), above the time axis (moved to row 4)
ABOVE_PX = 8  # between the view and the lanes: the room of half a tick label (a unit axis' lowest, centred on its tick)


class _Lane:
    def __init__(self, name: str, states, curve: pg.PlotDataItem, title: str):
        self.name, self.curve = name, curve
        background = QColor(theme.PLOT_BACKGROUND)
        background.setAlpha(170)  # the trace under the name still shows (a step there is not hidden)
        self.title = pg.TextItem(title or name, color=curve.opts["pen"].color(), anchor=(0, 0), fill=background)
        self.states = sorted(states)
        self.low, self.high = self.states[0][0], self.states[-1][0]
        self.height = min(max(LANE_PX, (len(self.states) - 1) * STATE_PX + 2 * PAD_PX), MAX_LANE_PX)
        self.bottom = 0.0

    def level(self, value):
        """Where ``value`` is drawn in the lane (its lowest state at the bottom, its highest at the top)."""
        span = (self.high - self.low) or 1.0
        fraction = np.clip((np.asarray(value, dtype=np.float64) - self.low) / span, 0.0, 1.0)
        return self.bottom + PAD_PX + fraction * (self.height - 2 * PAD_PX)


class DigitalLanes:
    """The lanes of one plot (:class:`pyqtgraph.PlotItem`); empty, they take no room."""

    def __init__(self, plot: pg.PlotItem):
        self.plot = plot
        self.view = pg.ViewBox(enableMenu=False)
        self.view.setMouseEnabled(x=True, y=False)
        self.view.enableAutoRange(axis=pg.ViewBox.YAxis, enable=False)
        self.view.setXLink(plot.vb)
        self.axis = pg.AxisItem("left")
        self.axis.linkToView(self.view)
        self.axis.setPen(theme.GRID)
        self.axis.setTextPen(theme.TEXT)
        self.axis.setStyle(maxTickLevel=0)
        self._lanes: list[_Lane] = []
        self._separators: list[pg.InfiniteLine] = []
        self._cursors: dict[int, tuple] = {}  # the plot's cursors continued through the lanes: (line, its slot)
        bottom = plot.getAxis("bottom")  # the time axis below the lanes
        plot.layout.removeItem(bottom)
        plot.layout.addItem(bottom, ROW + 1, 1)
        self.view.sigXRangeChanged.connect(self._place_titles)

    @property
    def names(self) -> list[str]:
        return [lane.name for lane in self._lanes]

    def add(self, name: str, states, curve: pg.PlotDataItem, title: str = "") -> None:
        """A lane for ``name`` (``title``: how it is named on the lane, when not by ``name``)."""
        if not self._lanes:
            self.plot.layout.addItem(self.axis, ROW, 0)
            self.plot.layout.setAlignment(self.axis, Qt.AlignRight)
            self.plot.layout.addItem(self.view, ROW, 1)
            self.plot.layout.setRowSpacing(ROW - 1, ABOVE_PX)  # the lowest label was half under the first lane's
        lane = _Lane(name, states, curve, title)
        self._lanes.append(lane)
        self.view.addItem(curve)
        self.view.addItem(lane.title, ignoreBounds=True)
        self._relayout()

    def remove(self, name: str) -> bool:
        """Takes ``name``'s lane away; False when it has none."""
        lane = next((lane for lane in self._lanes if lane.name == name), None)
        if lane is None:
            return False
        self._lanes.remove(lane)
        self.view.removeItem(lane.curve)
        self.view.removeItem(lane.title)
        if not self._lanes:
            self.plot.layout.setRowSpacing(ROW - 1, 0)
            for item in (self.axis, self.view):
                self.plot.layout.removeItem(item)
                if item.scene() is not None:
                    item.scene().removeItem(item)
        self._relayout()
        return True

    def set_data(self, name: str, t, values) -> None:
        lane = next(lane for lane in self._lanes if lane.name == name)
        lane.curve.setData(t, lane.level(values))

    def level(self, name: str, value) -> float:
        """Where ``value`` of ``name`` is drawn in the lanes' view (for tests and cursors)."""
        return float(next(lane for lane in self._lanes if lane.name == name).level(value))

    def show_cursor(self, cursor: pg.InfiniteLine, on: bool) -> None:
        """The plot's ``cursor`` drawn through the lanes too (while ``on``), wherever it is moved."""
        shown = self._cursors.pop(id(cursor), None)
        if shown is not None:
            self.view.removeItem(shown[0])
            cursor.sigPositionChanged.disconnect(shown[1])
        if on:
            line = pg.InfiniteLine(pos=cursor.value(), angle=90, movable=False, pen=cursor.pen)
            follow = lambda moved: line.setValue(moved.value())  # noqa: E731
            cursor.sigPositionChanged.connect(follow)
            self.view.addItem(line, ignoreBounds=True)
            self._cursors[id(cursor)] = (line, follow)

    def _relayout(self) -> None:
        """Lanes top down in the order added; the row as tall as they are; their states' texts as ticks."""
        for line in self._separators:
            self.view.removeItem(line)
        self._separators = []
        total = sum(lane.height for lane in self._lanes)
        top, ticks = total, []
        for lane in self._lanes:
            top -= lane.height
            lane.bottom = top
            written = None
            for value, text in lane.states:
                y = float(lane.level(value))
                if written is None or y - written >= STATE_PX:  # texts never overlap
                    ticks.append((y, text))
                    written = y
            if top > 0:
                line = pg.InfiniteLine(pos=top, angle=0, pen=pg.mkPen(theme.GRID))
                self.view.addItem(line, ignoreBounds=True)
                self._separators.append(line)
        self.axis.setTicks([ticks])
        self.plot.layout.setRowFixedHeight(ROW, total)
        if total:
            self.view.setYRange(0, total, padding=0)
        self._place_titles()

    def _place_titles(self) -> None:
        """Each lane's name at its top left, where the time axis starts now."""
        left = self.view.viewRange()[0][0]
        for lane in self._lanes:
            lane.title.setPos(left, lane.bottom + lane.height)
