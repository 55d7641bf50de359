"""What fits a small screen: table headers never cut, columns as wide as their texts where that is their kind,
long names cut where they differ (tooltips whole), a map's axis titles whole, plots that keep their width
however many units they show, and a measurement window that closes."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import QRectF, Qt
from PySide6.QtGui import QFont, QFontMetrics

from workbench.gui.signal_hub import SignalHub, SignalInfo
from workbench.gui.widgets.names import elide_name, elide_names
from workbench.gui.widgets.plot_window import PlotWindow
from workbench.gui.widgets.table_field import TableField
from workbench.gui.widgets.variable_browser import VariableBrowser

HEADER_PADDING = 12  # theme.py: QHeaderView::section { padding: 3px 6px }


def header_text_width(view, column: int) -> int:
    """The header's text in its bold font (theme.py), with the section's padding."""
    font = QFont(view.horizontalHeader().font())
    font.setBold(True)
    text = view.model().headerData(column, Qt.Horizontal)
    return QFontMetrics(font).horizontalAdvance(text) + HEADER_PADDING


def shown_columns(view) -> list[int]:
    return [c for c in range(view.model().columnCount()) if not view.isColumnHidden(c)]


@pytest.fixture
def browser(qtbot, demo_workspace):
    widget = VariableBrowser()
    qtbot.addWidget(widget)
    widget.set_variables(demo_workspace.variables)
    widget.resize(300, 600)  # the variables dock on a 1366 x 768 screen
    widget.show()
    qtbot.waitExposed(widget)
    return widget


def test_the_browsers_headers_are_whole_and_kind_and_unit_as_wide_as_their_texts(browser, qtbot):
    table = browser.table
    assert shown_columns(table) == [0, 1, 3]  # the description is left out: too narrow to read
    for column in shown_columns(table):
        assert table.columnWidth(column) >= header_text_width(table, column), column
    metrics = QFontMetrics(table.font())
    units = {v.unit for v in browser.model.rows}
    assert table.columnWidth(3) >= max(metrics.horizontalAdvance(u) for u in units)
    assert table.columnWidth(1) >= metrics.horizontalAdvance("signal")
    assert table.columnWidth(0) > table.viewport().width() / 2  # the name has the room
    browser.resize(900, 600)
    qtbot.waitUntil(lambda: not table.isColumnHidden(5), timeout=5_000)  # room for the description: it is back
    longest = max(metrics.horizontalAdvance(v.name) for v in browser.model.rows)
    assert longest <= table.columnWidth(0) <= longest + 40  # the name as wide as it needs, the rest described
    table.sortByColumn(3, Qt.AscendingOrder)  # the sorted header shows an arrow beside its text
    assert table.columnWidth(3) >= header_text_width(table, 3) + 10


def test_similar_names_keep_what_tells_them_apart_and_the_tooltip_is_whole(browser):
    metrics = QFontMetrics(browser.table.font())
    names = ["CANRX_PCM_TO_FLCU_001_Pdu.Dlc", "CANRX_PCM_TO_FLCU_002_Pdu.Dlc", "CANTX_FLCU_TO_PCM_001_Pdu.Dlc"]
    for width in (130, 160):
        shown = [elide_name(name, metrics, width) for name in names]
        assert len(set(shown)) == 3 and all(metrics.horizontalAdvance(text) <= width for text in shown), shown
        assert all(text.startswith(name[:6]) and text.endswith("_Pdu.Dlc") for text, name in zip(shown, names))
    assert elide_name("zsRailPressureTmp", metrics, 60).startswith("zs…")
    assert elide_name("xsDC", metrics, 200) == "xsDC"
    row = next(r for r in range(browser.model.rowCount()) if browser.model.index(r, 0).data() == names[0])
    assert browser.model.index(row, 0).data(Qt.ToolTipRole).startswith(names[0])


def test_names_alike_keep_the_part_that_tells_them_apart_among_the_others_of_their_column(browser, qtbot):
    metrics = QFontMetrics(browser.table.font())
    names = [variable.name for variable in browser.model.rows]
    for width in (110, 125):  # the variables dock's name column on a 1366 x 768 screen (the trial's)
        shown = elide_names(names, metrics, width)
        assert all(metrics.horizontalAdvance(text) <= width for text in shown.values())
        for group in (["CANRX_PCM_TO_FLCU_001_Pdu.DlcError", "CANRX_PCM_TO_FLCU_002_Pdu.DlcError"],
                      ["CANRX_PCM_TO_FLCU_001_Pdu.TimeOut", "CANRX_PCM_TO_FLCU_002_Pdu.TimeOut"],
                      ["csPCM_TO_FLCU_001_BitStatus", "csPCM_TO_FLCU_002_BitStatus"]):
            assert len({shown[name] for name in group}) == len(group), [shown[name] for name in group]
        assert len(set(shown.values())) == len(names)  # the first word and the end alone: 74 % read apart
    legend = ["zsTank1Pressure", "zsTank2Pressure", "zsManifoldPressure", "xsValve1State", "xsValve2State"]
    for width in (60, 75, 90):  # a legend's name column beside a narrow plot (the trial's: 'zs…Pressure' thrice)
        shown = list(elide_names(legend, metrics, width).values())
        assert len(set(shown)) == len(legend) and all(metrics.horizontalAdvance(t) <= width for t in shown), shown


def test_a_maps_axis_titles_are_whole_above_its_heat_map(qtbot):
    field = TableField(unit="%", x_label="xaPRV_FF_TARGET [bar]", y_label="xaPRV_FF_MANIFOLD [bar]")
    qtbot.addWidget(field)
    field.resize(400, 330)  # the calibration dock on a 1366 x 768 screen
    field.show()
    field.show_value(np.zeros((6, 5)), np.arange(0, 60, 10.0), np.array([50, 100, 200, 400, 700.0]))
    qtbot.waitExposed(field)
    titles = field.axis_titles
    assert titles.isVisible() and "xaPRV_FF_MANIFOLD [bar]" in titles.text().replace("\u00a0", " ")
    assert "xaPRV_FF_TARGET [bar]" in titles.text().replace("\u00a0", " ")
    assert titles.heightForWidth(titles.width()) <= titles.height()  # every line of it shown
    line = QFontMetrics(titles.font())
    assert all(line.horizontalAdvance(title) <= titles.width() for title in titles.text().split("    "))
    assert not field.plot.getAxis("left").label.isVisible()  # no title up the 100 px axis



@pytest.fixture
def hub():
    hub = SignalHub()
    units = {"p": "bar", "dc": "%", "u": "V", "i": "A", "n": "rpm"}
    hub.add_signals([SignalInfo(name, "MDF", unit) for name, unit in units.items()]
                    + [SignalInfo("valve", "MDF", "", states=((0.0, "OFF"), (1.0, "ON")))])
    for name in [*units, "valve"]:
        hub.load(name, np.arange(10.0), np.arange(10.0))
    return hub


def test_many_units_leave_the_plot_most_of_its_width(qtbot, hub):
    plot = PlotWindow(hub, "analysis")
    qtbot.addWidget(plot)
    plot.resize(620, 300)  # the plots' column on a 1366 x 768 screen
    plot.show()
    qtbot.waitExposed(plot)
    plot.add_signals(["p", "dc", "u", "i", "n", "valve"])
    qtbot.wait(50)
    drawn = plot.drawn_axes()
    assert drawn[-1] == "bar" and 1 <= len(drawn) < 5 and "" not in drawn  # states: in a lane of their own
    axes_width = sum(axis.item.geometry().width() for axis in plot._axes if axis.unit in drawn)
    assert axes_width <= 0.45 * plot.graphics.width()
    plot.legend.selectRow(plot.signals.index("u"))  # a selected signal's axis is drawn
    assert "V" in plot.drawn_axes()
    plot.remove_signals(["p", "dc", "u", "i", "n"])
    assert plot.drawn_axes() == [] and plot.lanes.names == ["valve"]  # alone, the states in their lane


def test_a_measurement_window_closes_and_its_signals_are_no_longer_measured_for_it(qtbot):
    from gui_helpers import offline_window

    window = offline_window(qtbot)
    first = window.plots[0]
    names = set(first.signals) - {n for plot in window.plots[1:] for n in plot.signals} - set(window.numeric.signals)
    assert names and names <= window.hub.shown()
    first.close_button.click()
    assert first not in window.plots and not names & window.hub.shown()
    assert first.title not in [spec.title for spec in window.current_project().plots]  # nor saved in the project


def test_the_3d_views_labels_never_overlap_and_give_way_names_first(qtbot):
    from workbench.gui.widgets.surface_view import SurfaceView

    view = SurfaceView("xaPRV_FF_TARGET [bar]", "xaPRV_FF_MANIFOLD [bar]", "%")
    qtbot.addWidget(view)
    view.set_surface(np.arange(30.0).reshape(6, 5), np.arange(0, 60, 10.0), np.array([50, 100, 200, 400, 700.0]),
                     point_text=lambda axis, p: f"{p:.2f}")
    view.show()
    for size, everything in (((520, 420), True), ((330, 130), False)):  # a roomy dock; a 1080 px screen's map tab
        view.resize(*size)
        qtbot.waitUntil(lambda: (view.width(), view.height()) == size, timeout=2000)
        labels = view.labels()
        rects = [rect for rect, _ in labels]
        assert all(QRectF(view.rect()).contains(rect) for rect in rects)
        assert not any(a.intersects(b) for i, a in enumerate(rects) for b in rects[i + 1:]), labels
        texts = [text for _, text in labels]
        assert texts[0] == "0 … 29 %"  # the value range always
        every = ["0.00", "50.00", "50.00", "700.00", "xaPRV_FF_TARGET [bar]", "xaPRV_FF_MANIFOLD [bar]"]
        assert (sorted(texts[1:]) == sorted(every)) == everything  # a small view leaves out what would collide


def test_a_names_column_fitted_to_its_contents_shows_every_name_whole(qtbot):
    """As the A2L tools fit their object column: 'part.a2l' was drawn 'part…l' in a column sized to it."""
    from PySide6.QtGui import QStandardItem, QStandardItemModel
    from PySide6.QtWidgets import QProxyStyle, QStyle, QTableView

    from workbench.gui.widgets.names import NameDelegate

    drawn = []

    class Recording(QProxyStyle):
        def drawControl(self, element, option, painter, widget=None):
            if element == QStyle.CE_ItemViewItem:
                drawn.append(option.text)
            super().drawControl(element, option, painter, widget)

    names = ["part.a2l", "xsNotInTheElf", "zsRailPressure"]
    model = QStandardItemModel()
    for name in names:
        model.appendRow([QStandardItem(name)])
    view = QTableView()
    qtbot.addWidget(view)
    view.setStyle(Recording())
    view.setModel(model)
    view.setItemDelegateForColumn(0, NameDelegate(view))
    view.show()
    view.resizeColumnToContents(0)
    view.grab()
    assert sorted(drawn) == names
