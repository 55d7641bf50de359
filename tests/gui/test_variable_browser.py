import pytest
from PySide6.QtCore import Qt

from workbench.gui.mime import MIME_SIGNALS, names_from_mime
from workbench.gui.widgets.variable_browser import VariableBrowser


@pytest.fixture
def browser(qtbot, demo_workspace):
    widget = VariableBrowser()
    qtbot.addWidget(widget)
    widget.set_variables(demo_workspace.variables)
    return widget


def shown(browser) -> set[str]:
    model = browser.model
    return {model.index(row, 0).data() for row in range(model.rowCount())}


def test_every_measurement_calibration_and_can2_signal_is_listed(browser, demo_workspace):
    names = shown(browser)
    model = demo_workspace.model
    assert set(model.names("MEASUREMENT")) <= names and set(model.names("CHARACTERISTIC")) <= names
    assert {"FLCU_TO_PCM_002.RailPressure", "PCM_TO_FLCU_002.TargetRailPressure"} <= names
    assert browser.count.text() == f"{len(names)} of {len(names)} objects"


def test_words_search_names_and_descriptions_and_a_glob_matches_whole_names(browser):
    browser.search.setText("rail pressure")
    assert {"zsRailPressure", "zsRailPressureTmp", "FLCU_TO_PCM_002.RailPressure"} <= shown(browser)
    assert "xsSWITCH_TANK_THR" not in shown(browser)
    browser.search.setText("xs*THR")
    assert shown(browser) == {"xsSWITCH_TANK_THR", "xsEMPTY_TANK_THR"}


def test_filters_by_kind_function_and_unit(browser):
    browser.kind_box.setCurrentIndex(browser.kind_box.findData("CHARACTERISTIC"))
    browser.function_box.setCurrentIndex(browser.function_box.findData("TankCtrl"))
    assert shown(browser) == {"xsSWITCH_TANK_THR"}
    browser.function_box.setCurrentIndex(0)
    browser.kind_box.setCurrentIndex(browser.kind_box.findData("MEASUREMENT"))
    browser.unit_box.setCurrentIndex(browser.unit_box.findData("bar"))
    rows = shown(browser)
    assert "zsRailPressure" in rows and "xsDC" not in rows and all(not n.startswith("xs") or "Press" in n for n in rows)


def test_the_function_filter_finds_a_function_by_typing_any_part_of_its_name(browser, qtbot):
    """A real ECU's A2L has thousands of FUNCTIONs: typed, in any case, the list narrows to those containing it."""
    box = browser.function_box
    field, completer = box.lineEdit(), box.completer()
    field.selectAll()
    qtbot.keyClicks(field, "CTRL")
    qtbot.waitUntil(completer.popup().isVisible)
    listed = completer.completionModel()
    assert [listed.index(row, 0).data() for row in range(listed.rowCount())] == ["PRVCtrl", "TankCtrl"]
    qtbot.keyClick(completer.popup(), Qt.Key_Down)  # the first, taken with Enter
    qtbot.keyClick(completer.popup(), Qt.Key_Return)
    assert box.currentData() == "PRVCtrl" and field.text() == "PRVCtrl" and "xsSWITCH_TANK_THR" not in shown(browser)
    field.selectAll()
    qtbot.keyClicks(field, "tankc")  # Enter on the only one left
    qtbot.keyClick(field, Qt.Key_Return)
    tank_ctrl = shown(browser)
    assert box.currentData() == "TankCtrl" and "xsSWITCH_TANK_THR" in tank_ctrl
    field.setText("no such function")  # names none: the field shows the chosen one again when left
    field.editingFinished.emit()
    assert field.text() == "TankCtrl" and shown(browser) == tank_ctrl
    field.setText("ALL")
    field.editingFinished.emit()
    assert box.currentIndex() == 0 and len(shown(browser)) > len(tank_ctrl)


def test_a_drag_carries_the_selected_names_and_a_double_click_asks_to_open(browser, qtbot):
    browser.search.setText("zsRail*")  # a glob: the whole name
    row = next(r for r in range(browser.model.rowCount()) if browser.model.index(r, 0).data() == "zsRailPressure")
    index = browser.model.index(row, 0)
    mime = browser.model.mimeData([index, browser.model.index(row, 1)])
    assert mime.hasFormat(MIME_SIGNALS) and names_from_mime(mime) == ["zsRailPressure"]
    with qtbot.waitSignal(browser.open_requested) as opened:
        browser.table.doubleClicked.emit(index)
    assert opened.args[0].name == "zsRailPressure" and opened.args[0].plottable
    assert browser.model.flags(index) & Qt.ItemIsDragEnabled


def test_a_name_with_brackets_finds_its_own_object(qtbot):
    """ASAP2 names may hold [ ] (arr[1]): typed whole, the name shows its object (and what the glob matches)."""
    from workbench.gui.models.variables import Variable

    widget = VariableBrowser()
    qtbot.addWidget(widget)
    widget.set_variables([Variable(name, "MEASUREMENT", "UBYTE", "", (), "") for name in ("arr[1]", "arr1", "arr2")])
    widget.search.setText("arr[1]")
    assert shown(widget) == {"arr[1]", "arr1"}
    widget.search.setText("arr[12]")
    assert shown(widget) == {"arr1", "arr2"}


def many_variables(count: int):
    from workbench.gui.models.variables import Variable

    kinds = ("MEASUREMENT", "CHARACTERISTIC")
    return [Variable(f"{'uv'[i % 2]}{(count - i):05d}_{'Sig' if i % 3 else 'sig'}", kinds[i % 2], "UWORD",
                     ("bar", "V", "")[i % 3], (), f"object {i}") for i in range(count)]


def test_a_header_sorts_thousands_of_objects_without_asking_the_model_for_each_comparison(qtbot, monkeypatch):
    """A QSortFilterProxyModel sorts by asking ``data`` twice a comparison: 7.5 s for 52,000 objects, the window
    frozen. The model sorts its rows itself; Qt then only asks about the rows it sizes and shows."""
    from workbench.gui.models.variables import VariableModel

    widget = VariableBrowser()
    qtbot.addWidget(widget)
    widget.resize(400, 600)
    widget.show()
    rows = many_variables(5000)
    widget.set_variables(rows)
    calls = []
    original = VariableModel.data
    monkeypatch.setattr(VariableModel, "data", lambda self, index, role=Qt.DisplayRole: (
        calls.append(role), original(self, index, role))[1])
    widget.table.sortByColumn(0, Qt.AscendingOrder)
    names = [widget.model.index(row, 0).data() for row in range(widget.model.rowCount())]
    assert names == sorted((row.name for row in rows), key=str.casefold)
    assert len(calls) < 2 * len(rows)  # a proxy's sort: ~24 a row
    widget.table.sortByColumn(3, Qt.DescendingOrder)  # by unit: equal units keep the A2L's order
    shown = [widget.model.index(row, 0).data(Qt.UserRole) for row in range(widget.model.rowCount())]
    assert [row.unit for row in shown[:3]] == ["V", "V", "V"] and shown[:2] == [rows[1], rows[4]]
    widget.search.setText("sig")  # the search keeps the order sorted by
    shown = [widget.model.index(row, 0).data(Qt.UserRole) for row in range(widget.model.rowCount())]
    assert len(shown) == len(rows) and shown[0] == rows[1]
    widget.search.setText("u0*_Sig")
    assert widget.count.text() == "2,500 of 5,000 objects"  # a glob is case-insensitive too
    widget.table.sortByColumn(-1, Qt.AscendingOrder)  # back to the A2L's order
    assert widget.model.index(0, 0).data() == rows[0].name


def test_sorting_keeps_the_selected_row_selected(browser):
    browser.search.setText("zsRail*")
    row = next(r for r in range(browser.model.rowCount()) if browser.model.index(r, 0).data() == "zsRailPressure")
    browser.table.selectRow(row)
    for column, order in ((0, Qt.DescendingOrder), (0, Qt.AscendingOrder), (-1, Qt.AscendingOrder)):
        browser.table.sortByColumn(column, order)
        (selected,) = browser.table.selectionModel().selectedRows()
        assert selected.data() == "zsRailPressure" and browser.table.currentIndex().row() == selected.row()
