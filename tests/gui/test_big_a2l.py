"""The window with an A2L of thousands of objects (a real ECU's has 50,000-200,000): the browser lists, searches and
filters them from the model's listing, without building the objects, and a search typed letter by letter looks only
at what the letters before found."""

from __future__ import annotations

from typing import NamedTuple

import pytest
from gui_helpers import WAIT_MS
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

UNITS, OBJECTS = 3, 1000  # objects a unit: every fifth a calibration, every third signal in bar


class Generated(NamedTuple):
    name: str
    kind: str
    unit: str
    function: str
    description: str


def generated_a2l(path) -> list[Generated]:
    """Units of scalars as a build's A2L has them, each unit a FUNCTION naming its objects."""
    objects, blocks, functions = [], [], []
    for unit in range(UNITS):
        members = {"CHARACTERISTIC": [], "MEASUREMENT": []}
        for index in range(OBJECTS):
            name = f"u{unit}_var{index:04d}"
            if index % 5 == 0:
                kind, physical, description = "CHARACTERISTIC", "", f"calibration {index} of unit {unit}"
                blocks.append(f'/begin CHARACTERISTIC {name} "{description}" VALUE 0x{index:X} '
                              "RL_UWORD 0 CM_Identity 0 100 /end CHARACTERISTIC")
            else:
                kind, physical = "MEASUREMENT", "bar" if index % 3 == 0 else ""
                description, method = f"signal {index} of unit {unit}", "CM_Bar" if physical else "CM_Identity"
                blocks.append(f'/begin MEASUREMENT {name} "{description}" UWORD {method} 1 0 0 1000 '
                              f"ECU_ADDRESS 0x{0x10000 + index:X} /end MEASUREMENT")
            members[kind].append(name)
            objects.append(Generated(name, kind, physical, f"Unit{unit}", description))
        functions.append(f'/begin FUNCTION Unit{unit} "unit {unit}" '
                         f'/begin DEF_CHARACTERISTIC {" ".join(members["CHARACTERISTIC"])} /end DEF_CHARACTERISTIC '
                         f'/begin LOC_MEASUREMENT {" ".join(members["MEASUREMENT"])} /end LOC_MEASUREMENT /end FUNCTION')
    path.write_text('ASAP2_VERSION 1 71\n/begin PROJECT Big ""\n/begin MODULE Big ""\n'
                    '/begin COMPU_METHOD CM_Identity "" IDENTICAL "%6.1" "" /end COMPU_METHOD\n'
                    '/begin COMPU_METHOD CM_Bar "" LINEAR "%6.1" "bar" COEFFS_LINEAR 0.1 0 /end COMPU_METHOD\n'
                    "/begin RECORD_LAYOUT RL_UWORD FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n"
                    + "\n".join(blocks + functions) + "\n/end MODULE\n/end PROJECT\n")
    return objects


@pytest.fixture
def big_window(qtbot, tmp_path, monkeypatch):
    """The window on the generated A2L, read; ``built``: the A2L objects built meanwhile (kind, name)."""
    from workbench.a2l.model import A2lModel
    from workbench.gui.project import Project
    from workbench.gui.widgets.main_window import MainWindow

    objects = generated_a2l(tmp_path / "big.a2l")
    built = []
    get = A2lModel._get
    monkeypatch.setattr(A2lModel, "_get", lambda self, kind, name: (built.append((kind, name)), get(self, kind, name))[1])
    window = MainWindow(Project(a2l=tmp_path / "big.a2l"))
    qtbot.addWidget(window)
    window.show()
    with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
    return window, objects, built


def shown(browser) -> list[str]:
    return [browser.model.index(row, 0).data() for row in range(browser.model.rowCount())]


def in_a2l_order(objects, keep) -> list[str]:
    """The names of ``objects`` that ``keep`` keeps, as the browser lists them until a header is clicked: the A2L's
    signals, then its calibrations."""
    return [o.name for kind in ("MEASUREMENT", "CHARACTERISTIC") for o in objects if o.kind == kind and keep(o)]


def test_the_browser_lists_searches_and_filters_thousands_of_objects_without_building_them(big_window):
    window, objects, built = big_window
    browser = window.browser
    assert browser.count.text() == f"{len(objects):,} of {len(objects):,} objects"
    browser.kind_box.setCurrentIndex(browser.kind_box.findData("CHARACTERISTIC"))
    browser.function_box.setCurrentIndex(browser.function_box.findData("Unit1"))
    assert shown(browser) == in_a2l_order(objects, lambda o: o.kind == "CHARACTERISTIC" and o.function == "Unit1")
    browser.kind_box.setCurrentIndex(0)
    browser.function_box.setCurrentIndex(0)
    browser.unit_box.setCurrentIndex(browser.unit_box.findData("bar"))
    browser.search.setText("u2*")
    assert shown(browser) == in_a2l_order(objects, lambda o: o.unit == "bar" and o.name.startswith("u2"))
    browser.unit_box.setCurrentIndex(0)
    browser.search.setText("unit signal 999")  # words: in the descriptions
    assert shown(browser) == ["u0_var0999", "u1_var0999", "u2_var0999"]
    assert {kind for kind, _ in built} == {"COMPU_METHOD"}  # their units; no MEASUREMENT, no FUNCTION read whole


def test_a_search_typed_letter_by_letter_looks_only_at_what_the_letters_before_found(big_window):
    window, objects, built = big_window
    browser = window.browser
    model = browser.model
    browser.search.setFocus()
    typed = "u1_var01"
    QTest.keyClicks(browser.search, typed)

    def found(text: str) -> list[str]:
        return in_a2l_order(objects, lambda o: text in f"{o.name} {o.description}".lower())

    assert shown(browser) == found(typed)
    assert model.scanned == len(objects) + sum(len(found(typed[:end])) for end in range(1, len(typed)))
    scanned = model.scanned
    QTest.keyClick(browser.search, Qt.Key_Backspace)  # a letter taken back: what it found before
    assert shown(browser) == found("u1_var0") and model.scanned == scanned
    browser.kind_box.setCurrentIndex(browser.kind_box.findData("MEASUREMENT"))  # another filter: looked at again
    assert shown(browser) == in_a2l_order(objects, lambda o: o.kind == "MEASUREMENT" and o.name.startswith("u1_var0"))
    assert model.scanned > scanned
    browser.table.sortByColumn(0, Qt.DescendingOrder)  # sorted: the search and filter keep their rows
    assert shown(browser) == sorted(in_a2l_order(objects, lambda o: o.kind == "MEASUREMENT"
                                                 and o.name.startswith("u1_var0")), reverse=True)
    window.open_variable(browser.variable("u1_var0001"))  # a signal by name: the first plot
    assert window.plots and window.plots[0].signals == ["u1_var0001"]
    assert {kind for kind, _ in built} == {"COMPU_METHOD", "MEASUREMENT"}  # the one the plot describes
    assert {name for kind, name in built if kind == "MEASUREMENT"} == {"u1_var0001"}
