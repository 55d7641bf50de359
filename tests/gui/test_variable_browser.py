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
    proxy = browser.proxy
    return {proxy.index(row, 0).data() for row in range(proxy.rowCount())}


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


def test_a_drag_carries_the_selected_names_and_a_double_click_asks_to_open(browser, qtbot):
    browser.search.setText("zsRail*")  # a glob: the whole name
    row = next(r for r in range(browser.proxy.rowCount()) if browser.proxy.index(r, 0).data() == "zsRailPressure")
    index = browser.proxy.index(row, 0)
    mime = browser.proxy.mimeData([index, browser.proxy.index(row, 1)])
    assert mime.hasFormat(MIME_SIGNALS) and names_from_mime(mime) == ["zsRailPressure"]
    with qtbot.waitSignal(browser.open_requested) as opened:
        browser.table.doubleClicked.emit(index)
    assert opened.args[0].name == "zsRailPressure" and opened.args[0].plottable
    assert browser.proxy.flags(index) & Qt.ItemIsDragEnabled


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
