"""The main window's actions, toolbar and menus (File, Edit, ECU, Calibration, View, Tools) and their keys.

:func:`build_menus` makes every action an attribute of the window (``window.connect_action`` ...), one
function per menu in the menu bar's order; the slots they call are the window's. :func:`enable_ecu_actions`
says which actions a connection (or none) allows.
"""

from __future__ import annotations

from PySide6.QtGui import QAction, QActionGroup, QKeySequence

from workbench.gui.project import PlotSpec, recent_projects
from workbench.gui.widgets.a2l_tools_dialog import CHECK, CLEANUP, FLATTEN, INSERT, MERGE, REMOVE, UPDATE

__all__ = ["KEYS", "build_menus", "enable_ecu_actions"]

# The window's keys (README "Keys"): function keys for the ECU as in CANape and INCA, the F9 row for the link
# (Ctrl with it for the flash, whose dialog still asks), Ctrl+Shift+letter for the pages and plots; none is
# one of Qt's standard keys on Windows, X11, KDE, GNOME or macOS (Ctrl+K deletes to the end of a line on X11,
# Ctrl+P prints, Ctrl+R refreshes on GNOME, Ctrl+Shift+F is full screen on KDE) and none repeats another.
# Copying the reference page onto the working page has no key: it overwrites every change since start-up.
KEYS = {"connect": "F9", "disconnect": "Shift+F9", "flash": "Ctrl+F9", "record": "F12",
        "working page": "Ctrl+Shift+W", "reference page": "Ctrl+Shift+R", "new plot": "Ctrl+Shift+P",
        "find variable": "Ctrl+F", "undo": "Ctrl+Z", "redo": ("Ctrl+Shift+Z", "Ctrl+Y"), "quit": "Ctrl+Q"}


def build_menus(window) -> None:
    """The actions of ``window`` (a MainWindow), its toolbar and its menu bar."""
    _ecu_actions(window)
    _toolbar(window)
    bar = window.menuBar()
    _file_menu(window, bar.addMenu("&File"))
    _edit_menu(window, bar.addMenu("&Edit"))
    _ecu_menu(window, bar.addMenu("&ECU"))
    _calibration_menu(window, bar.addMenu("&Calibration"))
    _view_menu(window, bar.addMenu("&View"))
    _tools_menu(window, bar.addMenu("&Tools"))
    enable_ecu_actions(window)


def enable_ecu_actions(window, session=None, info=None) -> None:
    """The actions a connection allows: ``session`` and its ``info`` (GET_ID, pages, boot), or None when there is
    none. Connect and Record follow the link's own steps (the window's connect_ecu, _lost, _start_measuring)."""
    connected = session is not None and info is not None
    writable = connected and not info.boot and not session.read_only
    window.disconnect_action.setEnabled(connected)
    window.flash_action.setEnabled(connected)
    for action in (window.working_action, window.reference_action, window.copy_action):
        action.setEnabled(writable and bool(info.pages))  # a read-only session refuses page switches
    window.save_set_action.setEnabled(connected and not info.boot)
    window.compare_pages_action.setEnabled(connected and not info.boot and bool(info.pages))
    if not connected:
        window.connect_action.setEnabled(not window.controller.closing)  # once the session before let go of the ECU
        window.record_action.setEnabled(False)
        window.record_action.setChecked(False)


def _action(window, text: str, slot, tip: str = "", shortcut=None, checkable: bool = False) -> QAction:
    """An action; ``shortcut``: a key of :data:`KEYS` (or a QKeySequence), shown in the menus and the tooltip."""
    made = QAction(text, window)
    made.setStatusTip(tip)
    made.setCheckable(checkable)
    _set_keys(made, KEYS.get(shortcut, shortcut), tip or text)
    made.triggered.connect(slot)
    return made


def _ecu_actions(window) -> None:
    """The ECU's actions, disabled until a connection allows them (the toolbar and the ECU menu share them)."""
    window.connect_action = _action(window, "Connect", lambda: window.connect_ecu(), "connect to the ECU", "connect")
    window.disconnect_action = _action(window, "Disconnect", lambda: window.controller.close(), "disconnect",
                                      "disconnect")
    pages = QActionGroup(window)
    window.working_action = _action(window, "Working page", lambda: window.set_page("working"),
                                   "the ECU and XCP use the working page (CAL RAM, writable)", "working page",
                                   checkable=True)
    window.reference_action = _action(window, "Reference page", lambda: window.set_page("reference"),
                                     "the ECU and XCP use the reference page (CAL ROM, the flashed values)",
                                     "reference page", checkable=True)
    for page in (window.working_action, window.reference_action):
        pages.addAction(page)
    window.working_action.setChecked(True)
    window.copy_action = _action(window, "Copy reference → working", window.copy_reference,
                                "start the working page over from the flashed values (says first what it "
                                "overwrites, asks)")
    window.flash_action = _action(window, "Flash…", window.open_flash_dialog, "flash CALIB/APPLICATIVE from an s19, "
                                 "or the working page into CAL ROM", "flash")
    window.record_action = _action(window, "Record", window.record_toggled,
                                  "record the measured signals (and CAN2, decoded with the project's DBC) to an MDF4 "
                                  "file; again to stop", "record", checkable=True)
    window.raw_can_action = _action(window, "Log raw CAN frames in recordings", lambda: None,
                                   "recordings also hold every frame of the CAN bus (ASAM bus logging)",
                                   checkable=True)
    window.settings_action = _action(window, "Connection…", window.edit_connection, "connection settings")
    window.plot_action = _action(window, "New plot", lambda: window.add_plot(PlotSpec("Measurement")),
                                "a new measurement window (drop signals on it)", "new plot")


def _toolbar(window) -> None:
    toolbar = window.addToolBar("main")
    toolbar.setObjectName("main_toolbar")
    toolbar.setMovable(False)
    for item in (window.connect_action, window.disconnect_action, None, window.working_action,
                 window.reference_action, None, window.plot_action, None, window.flash_action, window.record_action):
        toolbar.addSeparator() if item is None else toolbar.addAction(item)


def _file_menu(window, menu) -> None:
    window.open_action = _action(window, "Open…", window.open_project_dialog, "open a project file", QKeySequence.Open)
    window.save_action = _action(window, "Save", window.save, "save the project", QKeySequence.Save)
    window.save_as_action = _action(window, "Save as…", window.save_as, "save the project under a new name",
                                   QKeySequence.SaveAs)
    window.open_mdf_action = _action(window, "Open measurement file…", window.open_measurement_dialog,
                                    "an MDF file (ours, or any asammdf reads) in a plot with cursors, no ECU needed")
    window.open_image_action = _action(window, "Open image…", lambda: window.offline_image.open_dialog(),
                                      "an s19/hex whose calibrations the editors show and edit before connecting "
                                      "(the project's image from then on)")
    window.save_image_action = _action(window, "Save image", lambda: window.offline_image.save(),
                                      "write the project's s19/hex with the calibrations edited offline (only the "
                                      "records of changed bytes rewritten)")
    window.save_image_as_action = _action(window, "Save image as…", lambda: window.offline_image.save_as(),
                                         "write the s19/hex with the calibrations edited offline under a new name")
    for item in (window.open_action, window.save_action, window.save_as_action, None, window.open_image_action,
                 window.save_image_action, window.save_image_as_action, None, window.open_mdf_action):
        menu.addSeparator() if item is None else menu.addAction(item)
    window.recent_menu = menu.addMenu("Recent projects")
    window.recent_menu.aboutToShow.connect(lambda: _fill_recent(window))
    menu.addSeparator()
    window.quit_action = _action(window, "Quit", window.close, "close the window (and the connection)", "quit")
    menu.addAction(window.quit_action)


def _fill_recent(window) -> None:
    menu = window.recent_menu
    menu.clear()
    for path in recent_projects():
        menu.addAction(str(path), lambda p=path: window.open_project_file(p))
    if menu.isEmpty():
        menu.addAction("(none)").setEnabled(False)


def _edit_menu(window, menu) -> None:
    """Undo and Redo of the calibration editor shown, enabled as its own buttons are; the variables' search."""
    window.undo_action = window.undo_group.createUndoAction(window, "Undo")
    _set_keys(window.undo_action, KEYS["undo"], "write back the value before the editor's last write")
    window.redo_action = window.undo_group.createRedoAction(window, "Redo")
    _set_keys(window.redo_action, KEYS["redo"], "write the value undone again")
    window.find_action = _action(window, "Find variable…", window.find_variable,
                                "search the variable browser (Down goes to the results, Enter opens one)",
                                "find variable")
    for item in (window.undo_action, window.redo_action, None, window.find_action):
        menu.addSeparator() if item is None else menu.addAction(item)


def _ecu_menu(window, menu) -> None:
    for item in (window.settings_action, window.connect_action, window.disconnect_action, window.working_action,
                 window.reference_action, window.flash_action, window.record_action, window.raw_can_action,
                 window.copy_action):
        menu.addAction(item)


def _calibration_menu(window, menu) -> None:
    sets = window.parameter_sets
    menu.addAction(_action(window, "Open parameter set…", sets.open_dialog,
                          "a DCM/CDFX compared with the ECU (offline: with the project's s19), to apply"))
    window.save_set_action = _action(window, "Save the ECU's values as parameter set…", sets.save_dialog,
                                    "every calibration of the working page into a DCM or CDFX file")
    window.compare_pages_action = _action(window, "Compare working ↔ reference page", sets.compare_pages,
                                         "every calibration of the working page beside the flashed one")
    menu.addAction(window.save_set_action)
    menu.addAction(window.compare_pages_action)
    menu.addAction(_action(window, "Compare two parameter sets…", sets.compare_files_dialog,
                          "two DCM/CDFX files (or s19 images) object by object"))


def _view_menu(window, menu) -> None:
    menu.addAction(window.plot_action)
    for dock in (window.browser_dock, window.editor_dock, window.fix_dock, window.numeric_dock, window.trace_dock,
                 window.compare_dock):
        menu.addAction(dock.toggleViewAction())


def _tools_menu(window, menu) -> None:
    """The A2L tool chain of a build (``workbench a2l update|check|merge|insert|remove|cleanup|flatten``), one dialog
    for all: ``window.a2l_update_action`` ... ``window.a2l_flatten_action``; then the requirement tests
    (``workbench test``): ``window.tests_action``."""
    for operation, text, tip in (
            (UPDATE, "Update A2L from ELF…", "set every address (and the EPK) of an A2L from the ELF of a build"),
            (CHECK, "Check A2L…", "syntax, references, names and memory placement, with file:line:column"),
            (MERGE, "Merge A2L fragments…", "module fragments into a master A2L"),
            (INSERT, "Insert into A2L from ELF…", "new MEASUREMENTs/CHARACTERISTICs from the ELF's variables, or a "
             "new A2L from the ELF alone"),
            (REMOVE, "Remove from A2L…", "objects by name pattern or address range, with the references to them"),
            (CLEANUP, "Clean up A2L…", "remove what nothing uses: conversions, record layouts, units, empty groups"),
            (FLATTEN, "Flatten A2L includes…", "write the text of every /include inline")):
        if operation == INSERT:
            menu.addSeparator()  # the build's chain above, the edits below
        item = _action(window, text, lambda _=False, operation=operation: window.open_a2l_tools(operation), tip)
        setattr(window, f"a2l_{operation}_action", item)
        menu.addAction(item)
    menu.addSeparator()  # the tests of a build's software, as CANape's and INCA's test automation sit by their tools
    window.tests_action = _action(window, "Requirement tests…", window.open_requirement_tests,
                                 "run requirement tests (workbench test) on simulated ECUs or the ECU connected, "
                                 "each test's verdict as it ends, the traced report")
    menu.addAction(window.tests_action)


def _set_keys(item: QAction, keys, tip: str) -> None:
    """``keys`` (a text, a tuple of them, a QKeySequence.StandardKey or None) on ``item``, the first in its
    tooltip."""
    if isinstance(keys, (str, tuple)):
        item.setShortcuts([QKeySequence(k) for k in ((keys,) if isinstance(keys, str) else keys)])
    elif keys is not None:
        item.setShortcuts(keys)
    shown = item.shortcut().toString(QKeySequence.NativeText)
    item.setToolTip(f"{tip} ({shown})" if shown else tip)
