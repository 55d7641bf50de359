"""The measurement window on synthetic samples (no ECU): curves, axes per unit, cursor, drops."""

import numpy as np
import pyqtgraph as pg
import pytest
from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QColor, QDropEvent

from workbench.gui import theme

from workbench.gui.mime import signals_mime
from workbench.gui.signal_hub import SignalHub, SignalInfo
from workbench.gui.widgets.plot_window import PlotWindow


@pytest.fixture
def hub():
    hub = SignalHub()
    hub.add_signals([SignalInfo("rail", "XCP", "bar", decimals=2), SignalInfo("target", "CAN2", "bar"),
                     SignalInfo("duty", "XCP", "%"),
                     SignalInfo("state", "XCP", "", states=((0.0, "OFF"), (1.0, "TANK1_ON")))])
    t = np.linspace(0.0, 20.0, 2001)
    hub.sink("rail", t, 25 * (1 - np.exp(-t)))
    hub.sink("target", t[::10], np.full(201, 25.0))
    hub.sink("duty", t, 40 + np.sin(t))
    hub.sink("state", t, (t > 5).astype(float))
    return hub


@pytest.fixture
def plot(qtbot, hub):
    window = PlotWindow(hub, "Rail", span_s=10.0)
    qtbot.addWidget(window)
    window.show()
    return window


def test_signals_of_one_unit_share_an_axis_and_the_view_follows_the_newest_sample(plot):
    plot.add_signals(["rail", "target", "duty"])
    assert [axis.unit for axis in plot._axes] == ["bar", "%"]
    plot.refresh()
    (x0, x1), _ = plot.plot.vb.viewRange()
    assert (x0, x1) == pytest.approx((10.0, 20.0))
    assert 1001 + 101 + 1001 <= plot.samples_shown() <= 1001 + 101 + 1001 + 6  # the visible 10 s (and edge samples)
    assert plot.legend.item(0, 1).text() == "25.00"  # the A2L's decimals


def test_the_first_samples_on_screen_are_announced_once(plot, qtbot):
    with qtbot.waitSignal(plot.samples_arrived, timeout=2000):
        plot.add_signals(["rail"])
    assert plot.samples_shown()


def test_the_cursor_stops_following_and_shows_each_value_at_its_time(plot):
    plot.add_signals(["rail", "state"])
    plot.refresh()
    plot.cursor_button.setChecked(True)
    assert not plot.following and not plot.follow_button.isChecked()
    plot.cursor.setPos(7.0)
    assert float(plot.legend.item(0, 1).text()) == pytest.approx(25 * (1 - np.exp(-7.0)), abs=0.01)
    assert plot.legend.item(1, 1).text() == "TANK1_ON"  # a verbal value by its name
    headers = lambda: [plot.legend.horizontalHeaderItem(c).text() for c in (1, 2)]  # noqa: E731
    assert headers()[0] == "at t"  # the cursor's time (the cursor label's "t = 7.000 s"), not the newest "value"
    plot.cursor2_button.setChecked(True)
    assert headers() == ["at t1", "at t2"]  # as the label names the two times
    plot.follow_button.setChecked(True)
    assert plot.following and not plot.cursor_button.isChecked()
    assert headers()[0] == "value"


def test_the_cursors_time_is_clear_of_the_ticks_of_the_axis_beside_it(plot, qtbot):
    plot.add_signals(["rail"])
    plot.refresh()
    plot.cursor_button.setChecked(True)
    plot.cursor.setPos(7.0)
    view = plot.plot.vb
    # placed once the view has its range: at the view's top, within its width
    qtbot.waitUntil(lambda: abs(plot.cursor_label.sceneBoundingRect().top() - view.sceneBoundingRect().top()) < 2
                    and plot.cursor_label.sceneBoundingRect().left() < view.sceneBoundingRect().center().x(),
                    timeout=2000)
    label = plot.cursor_label.sceneBoundingRect()
    ticks = max(abs(axis.item.style["tickLength"]) for axis in plot._axes)  # they point into the plot
    assert label.left() >= view.sceneBoundingRect().left() + ticks + 1  # its first letter was under them


def test_removing_the_last_signal_of_a_unit_drops_its_axis(plot, hub):
    plot.add_signals(["rail", "duty"])
    plot.remove_signals(["duty"])
    assert [axis.unit for axis in plot._axes] == ["bar"] and plot.signals == ["rail"]
    assert hub.shown() == {"rail"}


def test_dropping_names_adds_the_known_ones(plot):
    mime = signals_mime(["duty", "no_such_signal"])
    event = QDropEvent(QPointF(10, 10), Qt.CopyAction, mime, Qt.LeftButton, Qt.NoModifier)
    plot.dropEvent(event)
    assert plot.signals == ["duty"]


def test_a_pause_in_the_measurement_is_a_gap_in_the_drawn_line(qtbot):
    hub = SignalHub()
    hub.add_signals([SignalInfo("rail", "XCP", "bar")])
    hub.sink("rail", np.linspace(0, 5, 501), np.full(501, 20.0))
    hub.mark_gap(["rail"])  # e.g. DAQ stopped for a flash
    hub.sink("rail", np.linspace(15, 20, 501), np.full(501, 30.0))
    plot = PlotWindow(hub, "Gap", span_s=30.0)
    qtbot.addWidget(plot)
    plot.resize(800, 300)
    plot.show()
    plot.add_signals(["rail"])
    plot.set_following(False)
    plot.plot.vb.setRange(xRange=(0, 20), yRange=(0, 40), padding=0)
    plot.refresh()
    image = plot.graphics.grab().toImage()
    trace = QColor(theme.trace_colour(0))

    def drawn_between(t0: float, t1: float) -> bool:
        scene = plot.plot.vb.mapViewToScene
        x0, x1 = int(scene(QPointF(t0, 0)).x()), int(scene(QPointF(t1, 0)).x())
        return any(_near(QColor(image.pixel(x, y)), trace) for x in range(x0, x1) for y in range(image.height()))

    assert drawn_between(1, 4) and drawn_between(16, 19)  # the measured stretches
    assert not drawn_between(6, 14)  # not the straight line across the pause


def _near(a, b) -> bool:
    return abs(a.red() - b.red()) + abs(a.green() - b.green()) + abs(a.blue() - b.blue()) < 60


def _tick_texts(axis) -> list:
    """What ``axis`` (a drawn pyqtgraph AxisItem) writes: (its rectangle in the axis, text) of each tick label."""
    from PySide6.QtGui import QImage, QPainter

    image = QImage(10, 10, QImage.Format_ARGB32)
    painter = QPainter(image)
    try:
        specs = axis.generateDrawSpecs(painter)
    finally:
        painter.end()
    return [(rect, text) for rect, _, text in specs[2]] if specs else []


def _tick_rows(axis) -> dict[float, float]:
    """Each tick label's value -> its scene y."""
    return {float(text): axis.mapToScene(rect.center()).y() for rect, text in _tick_texts(axis)}


def test_curves_of_one_unit_are_drawn_at_their_values_on_that_units_axis(qtbot):
    hub = SignalHub()
    hub.add_signals([SignalInfo("rail", "XCP", "bar", decimals=2), SignalInfo("target", "CAN2", "bar", decimals=2)])
    t = np.linspace(0.0, 10.0, 101)
    hub.sink("rail", t, np.full(101, 30.0))
    hub.sink("target", t, np.full(101, 25.0))
    plot = PlotWindow(hub, "Rail", span_s=10.0)
    qtbot.addWidget(plot)
    plot.resize(700, 320)
    plot.show()
    plot.add_signals(["rail", "target"])
    assert plot.drawn_axes() == ["bar"] and len(plot._axes) == 1  # one unit, one axis, one scale
    plot.refresh()
    axis = plot._axes[0]
    qtbot.waitUntil(lambda: {25.0, 30.0} <= set(_tick_rows(axis.item)), timeout=2000)
    ticks = _tick_rows(axis.item)
    image = plot.graphics.grab().toImage()
    for index, (name, value) in enumerate((("rail", 30.0), ("target", 25.0))):
        curve = plot._curves[name]
        assert curve.getViewBox() is axis.view
        drawn_at = curve.mapToScene(QPointF(5.33, value)).y()  # between the grid's lines
        assert abs(drawn_at - ticks[value]) <= 1.0, (name, drawn_at, ticks)  # the line is where its tick says
        x = int(curve.mapToScene(QPointF(5.33, value)).x())
        rows = [y for y in range(image.height()) if _near(QColor(image.pixel(x, y)), QColor(theme.trace_colour(index)))]
        assert rows and abs(sum(rows) / len(rows) - ticks[value]) <= 1.5, (name, rows, ticks[value])


def test_verbal_signals_step_in_lanes_of_their_own_labelled_with_their_states(plot, hub, qtbot):
    hub.add_signals([SignalInfo("valve", "XCP", "", states=((0.0, "OFF"), (1.0, "ON")))])
    hub.sink("valve", np.linspace(0.0, 20.0, 201), (np.arange(201) % 40 >= 20).astype(float))
    plot.add_signals(["rail", "state", "valve"])
    plot.refresh()
    assert plot.drawn_axes() == ["bar"] and [axis.unit for axis in plot._axes] == ["bar"]  # no scale for states
    assert plot.lanes.names == ["state", "valve"]
    lanes = plot.lanes.view
    titles = [item for item in lanes.childGroup.childItems() if isinstance(item, pg.TextItem)]  # each lane named
    assert sorted(title.toPlainText() for title in titles) == ["state", "valve"]
    qtbot.waitUntil(lambda: all(lanes.sceneBoundingRect().adjusted(-1, -1, 1, 1).contains(title.sceneBoundingRect())
                                for title in titles), timeout=2000)  # once laid out
    level = plot.lanes.level
    assert sorted(plot.lanes.axis._tickLevels[0]) == sorted([  # each state's text where the lane draws it
        (level("state", 0.0), "OFF"), (level("state", 1.0), "TANK1_ON"), (level("valve", 0.0), "OFF"),
        (level("valve", 1.0), "ON")])
    curve = plot._curves["valve"]
    assert curve.getViewBox() is plot.lanes.view
    assert set(np.unique(curve.yData)) == {level("valve", 0.0), level("valve", 1.0)}
    valve_lane = (min(curve.yData), max(curve.yData))
    state_lane = (min(plot._curves["state"].yData), max(plot._curves["state"].yData))
    assert valve_lane[1] < state_lane[0]  # one below the other, apart
    plot.remove_signals(["state", "valve"])
    assert plot.lanes.names == [] and plot.lanes.view.scene() is None


def test_an_autoscaled_axis_spans_at_least_twenty_steps_of_the_signals_format(qtbot):
    hub = SignalHub()
    hub.add_signals([SignalInfo("rail", "XCP", "bar", decimals=2), SignalInfo("raw", "MDF", "V")])
    t = np.linspace(0.0, 10.0, 1001)
    noise = 25.0 + 0.0025 * (np.arange(1001) % 7) / 6  # below the format's last digit: 25.00 throughout
    hub.sink("rail", t, noise)
    hub.sink("raw", t, noise)
    plot = PlotWindow(hub, "Rail", span_s=10.0)
    qtbot.addWidget(plot)
    plot.resize(700, 320)
    plot.show()
    plot.add_signals(["rail", "raw"])
    plot.refresh()
    bar, volt = plot._axes
    qtbot.waitUntil(lambda: 24.0 < bar.view.viewRange()[1][0] and 24.0 < volt.view.viewRange()[1][0], timeout=2000)
    (y0, y1) = bar.view.viewRange()[1]
    assert y1 - y0 >= 0.2 * 0.999 and y0 < 25.0 < 25.0025 < y1  # 20 steps of 0.01 bar about the noise
    assert all(round(value, 2) == value for value in _tick_rows(bar.item))  # no tick finer than the format
    assert volt.view.viewRange()[1][1] - volt.view.viewRange()[1][0] < 0.01  # no format: as the values come


@pytest.mark.parametrize("width", range(120, 271, 15))  # the plot's share of a crowded window
def test_the_time_axis_labels_never_run_together(qtbot, width):
    hub = SignalHub()
    hub.add_signals([SignalInfo("rail", "XCP", "bar", decimals=2)])
    t = np.linspace(139.0, 149.0, 101)
    hub.sink("rail", t, np.full(101, 25.0))
    plot = PlotWindow(hub, "Rail", span_s=10.0)
    qtbot.addWidget(plot)
    plot.resize(700, 250)
    plot.show()
    plot.add_signals(["rail"])
    plot._legend_moved()  # the user dragged the legend's edge: the plot is narrow
    plot.splitter.setSizes([width, 700 - width])
    plot.refresh()
    time_axis = plot.plot.getAxis("bottom")
    qtbot.waitUntil(lambda: bool(_tick_texts(time_axis)), timeout=2000)
    labels = sorted((rect.left(), rect.right(), text) for rect, text in _tick_texts(time_axis))
    assert all(right + 4 <= next_left for (_, right, _), (next_left, _, _) in zip(labels, labels[1:])), labels


def test_the_lowest_label_of_a_unit_axis_stays_clear_of_the_lanes_below(qtbot, hub):
    """On a laptop's screen the bar axis' lowest label ('698') was half under the first lane's 'ON'."""
    from PySide6.QtGui import QImage, QPainter

    plot = PlotWindow(hub, "Tanks", span_s=10.0)
    qtbot.addWidget(plot)
    plot.resize(600, 190)  # as 'Tanks and valves' at 1366 x 768
    plot.show()
    qtbot.waitExposed(plot)
    plot.add_signals(["rail", "state"])
    plot.refresh()
    axis = plot._axes[0].item
    lanes_top = plot.lanes.view.sceneBoundingRect().top()

    def label_bottoms():
        image = QImage(8, 8, QImage.Format_ARGB32)
        painter = QPainter(image)
        texts = axis.generateDrawSpecs(painter)[2]
        painter.end()
        return [axis.mapRectToScene(rect).bottom() for rect, _, _ in texts]

    qtbot.waitUntil(lambda: len(label_bottoms()) >= 2, timeout=2000)
    assert max(label_bottoms()) <= lanes_top + 1
