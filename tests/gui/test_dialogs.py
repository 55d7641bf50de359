"""Dialogs that need no ECU: connection settings from the A2L's IF_DATA, cache synchronisation."""

import pytest
from PySide6.QtWidgets import QDialogButtonBox, QLabel

from workbench.errors import InputError
from workbench.gui import theme
from workbench.gui.project import Connection, Project, project_from_dict
from workbench.gui.widgets.connection_dialog import ConnectionDialog, parse_bus_kwargs
from workbench.gui.widgets.sync_dialog import (
    SHOWN_AT_ONCE,
    SyncChoice,
    SyncDialog,
    SyncDifference,
)


def test_the_connection_is_prefilled_from_the_a2l_and_the_project(qtbot, demo_workspace):
    dialog = ConnectionDialog(Connection("udp_multicast", "239.74.163.2", None, {"port": 43210}),
                              demo_workspace.config)
    qtbot.addWidget(dialog)
    assert dialog.transport.currentData() == "CAN"
    assert dialog.ids.text() == "master 7F0h, slave 7F1h, 1000 kbit/s"
    assert dialog.bus_kwargs.text() == "port=43210"
    assert dialog.connection() == Connection("udp_multicast", "239.74.163.2", None, {"port": 43210})
    dialog.transport.setCurrentIndex(dialog.transport.findData("tcp"))
    assert (dialog.host.text(), dialog.port.value()) == ("127.0.0.1", 5555)  # the A2L's XCP_ON_TCP_IP
    assert dialog.connection() == Connection(host="127.0.0.1", port=5555, protocol="tcp")


def test_the_seed_and_key_is_the_a2ls_unless_given(qtbot, demo_workspace, tmp_path):
    dialog = ConnectionDialog(Connection(), demo_workspace.config)
    qtbot.addWidget(dialog)
    assert dialog.key_function.placeholderText() == "as the A2L says: workbench.sim.seedkey:compute_key"
    dialog.setStyleSheet(theme.STYLE_SHEET)  # as the application draws it: its padding takes room
    dialog.show()
    room = dialog.key_function.width() - 2 * (6 + 1)  # the theme's padding and border on each side
    # whole, not 'as the A2L says: workbench.sim.seedkey:co'
    assert room >= dialog.key_function.fontMetrics().horizontalAdvance(dialog.key_function.placeholderText())
    assert dialog.connection().key_function is None
    dialog.key_function.setText(" keys/SeedNKeyXcp.dll ")
    given = dialog.connection()
    assert given.key_function == "keys/SeedNKeyXcp.dll" and given.session_options()["key_function"] == given.key_function
    dialog.transport.setCurrentIndex(dialog.transport.findData("udp"))
    assert dialog.connection().key_function == "keys/SeedNKeyXcp.dll"  # for every transport
    project = Project(path=tmp_path / "bench.wbproj", connection=given)  # kept in the project file
    assert project_from_dict(project.to_dict(), project.path).connection == given
    again = ConnectionDialog(given, demo_workspace.config)
    qtbot.addWidget(again)
    assert again.key_function.text() == "keys/SeedNKeyXcp.dll"


def test_daq_list_can_ids_are_kept_in_the_project_and_given_to_the_session(qtbot, demo_workspace, tmp_path):
    dialog = ConnectionDialog(Connection(daq_can_ids={"1": 0x7F6}), demo_workspace.config)  # as a project file has it
    qtbot.addWidget(dialog)
    assert dialog.daq_can_ids.text() == "1=0x7F6"
    assert "no VARIABLE list" in dialog.daq_can_ids.placeholderText()  # the demo's lists all send on CAN_ID_SLAVE
    dialog.daq_can_ids.setText("0=0x7F4, 1=0x80012345")
    given = dialog.connection()
    assert given.session_options()["daq_can_ids"] == {0: 0x7F4, 1: 0x80012345}
    project = Project(path=tmp_path / "bench.wbproj", connection=given)
    assert project_from_dict(project.to_dict(), project.path).connection == given
    dialog.daq_can_ids.setText("0x7F4")
    dialog._accept()
    assert "give LIST=ID" in dialog.error.text() and dialog.result() == 0


def test_a_key_library_is_chosen_with_a_file_dialog(qtbot, demo_workspace, monkeypatch, tmp_path):
    from PySide6.QtWidgets import QFileDialog, QFormLayout

    library = tmp_path / "SeedNKeyXcp.dll"
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *args: (str(library), ""))
    dialog = ConnectionDialog(Connection(), demo_workspace.config)
    qtbot.addWidget(dialog)
    dialog.key_library.click()
    assert dialog.connection().key_function == str(library)
    label = dialog.findChild(QFormLayout).labelForField(dialog.key_library.parentWidget())
    assert label.text() == "seed && key" and label.buddy() is not None  # shown as "seed & key"


def test_a_long_scan_answer_is_shown_whole(qtbot, demo_workspace):
    dialog = ConnectionDialog(Connection("udp_multicas"), demo_workspace.config)  # the known interfaces: 4 lines
    qtbot.addWidget(dialog)
    dialog.show()
    result = dialog.slave_scan.result
    with qtbot.waitSignal(dialog.slave_scan.finished, timeout=10_000):
        dialog.slave_scan.button.click()
    assert result.text().startswith("unknown python-can interface 'udp_multicas' (known: ")
    qtbot.waitUntil(lambda: result.height() >= result.heightForWidth(result.width()) > 2 * result.fontMetrics().height())
    assert result.geometry().bottom() < dialog.findChild(QDialogButtonBox).geometry().top()  # was cut after 2 lines


def test_bus_options_that_do_not_parse_keep_the_dialog_open(qtbot, demo_workspace):
    dialog = ConnectionDialog(Connection(), demo_workspace.config)
    qtbot.addWidget(dialog)
    dialog.bus_kwargs.setText("port 43210")
    dialog._accept()
    assert "expected KEY=VALUE" in dialog.error.text() and dialog.result() == 0


def test_a_bus_option_the_interface_would_ignore_keeps_the_dialog_open(qtbot, demo_workspace):
    dialog = ConnectionDialog(Connection(), demo_workspace.config)
    qtbot.addWidget(dialog)
    dialog.bus_kwargs.setText("prot=43210")  # udp_multicast would ignore it and take the default port's bus
    dialog._accept()
    assert dialog.error.text().startswith("bus option prot=43210: python-can's udp_multicast bus has no option 'prot'")
    assert "did you mean port?" in dialog.error.text() and dialog.result() == 0
    dialog.slave_scan.button.click()  # nothing sent: said where the scan's result goes
    assert "has no option 'prot'" in dialog.slave_scan.result.text()


def test_bus_options_are_python_can_keywords():
    assert parse_bus_kwargs("port=43210, app_name=CANape fd=True x=0.5") == {  # as the CLI's --bus-kwargs
        "port": 43210, "app_name": "CANape", "fd": True, "x": 0.5}
    with pytest.raises(InputError, match="'port'"):
        parse_bus_kwargs("port")


def test_cache_sync_keeps_both_by_default_and_lists_few_differences_at_once(qtbot):
    differences = [SyncDifference("xsSWITCH_TANK_THR", "25.00 bar", "20.00 bar"),
                   SyncDifference("xvPRV_DC_FF", "MAP 6 x 5 (1 value differs)", "MAP 6 x 5")]
    dialog = SyncDialog("FLCU demo ECU", "FLCU.s19", differences)
    qtbot.addWidget(dialog)
    dialog.show()
    assert dialog.choice is SyncChoice.KEEP and dialog.buttons.button(dialog.buttons.StandardButton.Ok).text() == "Keep"
    assert dialog.table.isVisible() and not dialog.expert.isVisible() and dialog.table.rowCount() == 2
    assert dialog.table.item(0, 1).text() == "25.00 bar" and dialog.table.item(0, 2).text() == "20.00 bar"
    assert "overwrites the ECU's values shown above" in dialog.download.text() and "write nothing" in dialog.keep.text()
    dialog.upload.click()
    assert dialog.choice is SyncChoice.UPLOAD


def test_cache_sync_lists_many_differences_in_the_expert_view(qtbot):
    differences = [SyncDifference(f"object{i}", f"{i}.00 bar", "0.00 bar") for i in range(SHOWN_AT_ONCE + 1)]
    dialog = SyncDialog("FLCU demo ECU", "FLCU.s19", differences)
    qtbot.addWidget(dialog)
    dialog.show()
    assert not dialog.table.isVisible() and "11 objects differ (listed in the expert view)" in dialog.findChild(
        QLabel).text()
    dialog.expert.click()
    assert dialog.table.isVisible() and dialog.table.rowCount() == SHOWN_AT_ONCE + 1


def test_scan_for_slaves_shows_the_ids_that_answer_against_the_a2ls(qtbot, demo_workspace):
    """The dialog's scan sends GET_SLAVE_ID on the A2L's CAN_ID_BROADCAST on the bus entered, off the GUI thread."""
    from workbench.sim import serve_demo

    dialog = ConnectionDialog(Connection("virtual", "dialog-scan"), demo_workspace.config)
    qtbot.addWidget(dialog)
    scan = dialog.slave_scan
    assert scan.button.isEnabled() and "CAN_ID_BROADCAST 6F0h" in scan.button.toolTip()
    with serve_demo({"interface": "virtual", "channel": "dialog-scan"}, time_scale=None), \
            qtbot.waitSignal(scan.finished, timeout=10_000):
        scan.button.click()
    assert scan.result.text() == "commands 7F0h, answers 7F1h: the A2L's ids"
    dialog.channel.setText("dialog-scan-nobody")
    with qtbot.waitSignal(scan.finished, timeout=10_000):
        scan.button.click()
    assert scan.result.text() == "no slave answered GET_SLAVE_ID on 6F0h (virtual dialog-scan-nobody)"
