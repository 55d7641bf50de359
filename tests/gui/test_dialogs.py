"""Dialogs that need no ECU: connection settings from the A2L's IF_DATA, cache synchronisation."""

import pytest

from workbench.errors import InputError
from workbench.gui.project import Connection
from workbench.gui.widgets.connection_dialog import ConnectionDialog, parse_bus_kwargs
from workbench.gui.widgets.sync_dialog import SyncChoice, SyncDialog, SyncDifference


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


def test_bus_options_that_do_not_parse_keep_the_dialog_open(qtbot, demo_workspace):
    dialog = ConnectionDialog(Connection(), demo_workspace.config)
    qtbot.addWidget(dialog)
    dialog.bus_kwargs.setText("port 43210")
    dialog._accept()
    assert "expected KEY=VALUE" in dialog.error.text() and dialog.result() == 0


def test_bus_options_are_python_can_keywords():
    assert parse_bus_kwargs("port=43210, app_name=CANape fd=True x=0.5") == {  # as the CLI's --bus-kwargs
        "port": 43210, "app_name": "CANape", "fd": True, "x": 0.5}
    with pytest.raises(InputError, match="'port'"):
        parse_bus_kwargs("port")


def test_cache_sync_offers_download_and_upload_and_lists_the_differences(qtbot):
    differences = [SyncDifference("xsSWITCH_TANK_THR", "25.00 bar", "20.00 bar"),
                   SyncDifference("xvPRV_DC_FF", "(6, 5) values, 1 differs", "(6, 5) values")]
    dialog = SyncDialog("FLCU demo ECU", "FLCU.s19", differences)
    qtbot.addWidget(dialog)
    dialog.show()
    assert dialog.choice is SyncChoice.DOWNLOAD and not dialog.table.isVisible()
    dialog.expert.click()
    assert dialog.table.isVisible() and dialog.table.rowCount() == 2
    assert dialog.table.item(0, 1).text() == "25.00 bar" and dialog.table.item(0, 2).text() == "20.00 bar"
    dialog.upload.click()
    assert dialog.choice is SyncChoice.UPLOAD
